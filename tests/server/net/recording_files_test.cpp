// Recordings onto disk as they run: the file in progress grows chunk by chunk under its `.part`
// name, is renamed whole to its final name when the match ends (no `.part` left), a `.part` a
// crash left is kept under its interrupted name at the next start, and a directory that cannot
// be made is an error that is counted and logged, never a crash.
#include "recording_files.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "temp_dir.h"

namespace ricochet::server::recording_files_test {
namespace {

std::vector<std::uint8_t> read_all(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::size_t entries(const std::filesystem::path& directory) {
  return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(directory),
                                                std::filesystem::directory_iterator()));
}

constexpr std::size_t kRoom = 1u << 20;

TEST(RecordingFiles, Names) {
  EXPECT_EQ(RecordingFiles::part_name(7, 1700000000123), "match-7-1700000000123.rcr.part");
  EXPECT_EQ(RecordingFiles::file_name(7, 1700000000999), "match-7-1700000000999.rcr");
  EXPECT_EQ(RecordingFiles::interrupted_name("match-7-1700000000123.rcr.part"),
            "match-7-1700000000123.interrupted.rcr");
}

TEST(RecordingFiles, AFileGrowsAsThePartAndIsRenamedWholeWhenItEnds) {
  const ricochet::test::TempDir dir("ricochet-recordings");
  const auto recordings = dir.path() / "a" / "recordings";
  RecordingFiles files(recordings, kRoom);
  EXPECT_TRUE(files.has_room());
  const std::string part = RecordingFiles::part_name(1, 1000);
  const std::vector<std::uint8_t> head(100, 1), chunk(5000, 2), rest(30, 3);
  files.append(part, head);
  files.append(part, chunk);
  files.append(part, {});  // nothing completed this tick
  files.append(RecordingFiles::part_name(2, 2000), {9, 9});
  files.finish(part, RecordingFiles::file_name(1, 5000), rest);
  files.stop();
  EXPECT_EQ(files.written(), 1u);
  EXPECT_EQ(files.written_bytes(), 5130u);
  EXPECT_EQ(files.failed(), 0u);
  // head, chunk, rest (gcc 12 warns falsely on inserting one vector after another here)
  std::vector<std::uint8_t> whole(head.size() + chunk.size() + rest.size(), 2);
  std::fill_n(whole.begin(), head.size(), 1);
  std::fill_n(whole.end() - static_cast<std::ptrdiff_t>(rest.size()), rest.size(), 3);
  EXPECT_EQ(read_all(recordings / "match-1-5000.rcr"), whole);
  EXPECT_FALSE(std::filesystem::exists(recordings / part));
  // The match that never ended stays as its part.
  EXPECT_EQ(read_all(recordings / "match-2-2000.rcr.part"), (std::vector<std::uint8_t>{9, 9}));
  EXPECT_EQ(entries(recordings), 2u);
  files.finish(RecordingFiles::part_name(3, 3000), "match-3-4000.rcr", {1});  // after stop
  EXPECT_EQ(files.failed(), 1u);
  EXPECT_FALSE(std::filesystem::exists(recordings / "match-3-4000.rcr"));
}

TEST(RecordingFiles, AFileWrittenInOnePieceAtTheEndIsTheSame) {
  const ricochet::test::TempDir dir("ricochet-recordings");
  RecordingFiles files(dir.path(), kRoom);
  files.finish(RecordingFiles::part_name(4, 10), "match-4-20.rcr",
               std::vector<std::uint8_t>(1 << 20, 4));
  files.stop();
  EXPECT_EQ(read_all(dir.path() / "match-4-20.rcr"), std::vector<std::uint8_t>(1 << 20, 4));
  EXPECT_EQ(entries(dir.path()), 1u);
}

TEST(RecordingFiles, APartLeftByACrashIsKeptUnderItsInterruptedNameAtStart) {
  const ricochet::test::TempDir dir("ricochet-recordings");
  std::ofstream(dir.path() / "match-5-100.rcr.part") << "cut";
  std::ofstream(dir.path() / "match-6-200.rcr") << "whole";
  std::ofstream(dir.path() / "notes.txt") << "not ours";
  RecordingFiles files(dir.path(), kRoom);
  files.stop();
  EXPECT_EQ(files.interrupted(), 1u);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "match-5-100.rcr.part"));
  const auto kept = read_all(dir.path() / "match-5-100.interrupted.rcr");
  EXPECT_EQ(std::string(kept.begin(), kept.end()), "cut");
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "match-6-200.rcr"));
  EXPECT_TRUE(std::filesystem::exists(dir.path() / "notes.txt"));
  EXPECT_EQ(entries(dir.path()), 3u);
}

TEST(RecordingFiles, AnUnusableDirectoryIsCountedNotFatal) {
  const ricochet::test::TempDir dir("ricochet-recordings");
  std::ofstream(dir.path() / "taken") << "a file where the directory should be";
  RecordingFiles files(dir.path() / "taken", kRoom);
  const std::string part = RecordingFiles::part_name(1, 1);
  files.append(part, {1, 2});
  files.finish(part, "match-1-2.rcr", {3});
  files.stop();
  EXPECT_EQ(files.written(), 0u);
  EXPECT_EQ(files.failed(), 1u);
  EXPECT_EQ(files.interrupted(), 0u);
}

}  // namespace
}  // namespace ricochet::server::recording_files_test
