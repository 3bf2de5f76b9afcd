// Recordings onto disk: the directory is made, the file appears whole under its name (no
// temporary left), everything queued is written by stop(), and a directory that cannot be made
// is an error that is counted and logged, never a crash.
#include "recording_files.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "temp_dir.h"

namespace ricochet::server {
namespace {

std::vector<std::uint8_t> read_all(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(RecordingFiles, WriteFileAtomicallyMakesTheDirectoryAndLeavesNoTemporary) {
  const test::TempDir dir("ricochet-recordings");
  const auto nested = dir.path() / "a" / "b";
  const std::vector<std::uint8_t> bytes = {1, 2, 3, 0, 255};
  EXPECT_EQ(write_file_atomically(nested, "x.rcr", bytes), "");
  EXPECT_EQ(read_all(nested / "x.rcr"), bytes);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(nested),
                          std::filesystem::directory_iterator()),
            1);
  // Written again: replaced whole.
  EXPECT_EQ(write_file_atomically(nested, "x.rcr", std::vector<std::uint8_t>{9}), "");
  EXPECT_EQ(read_all(nested / "x.rcr"), std::vector<std::uint8_t>{9});
}

TEST(RecordingFiles, WritesEveryQueuedRecordingByStop) {
  const test::TempDir dir("ricochet-recordings");
  RecordingFiles files(dir.path() / "recordings");
  EXPECT_EQ(RecordingFiles::file_name(7, 1700000000123), "match-7-1700000000123.rcr");
  files.write(1, 1000, std::vector<std::uint8_t>(100, 1));
  files.write(2, 2000, std::vector<std::uint8_t>(1 << 20, 2));
  files.stop();
  EXPECT_EQ(files.written(), 2u);
  EXPECT_EQ(files.written_bytes(), 100u + (1u << 20));
  EXPECT_EQ(files.failed(), 0u);
  EXPECT_EQ(read_all(dir.path() / "recordings" / "match-1-1000.rcr").size(), 100u);
  EXPECT_EQ(read_all(dir.path() / "recordings" / "match-2-2000.rcr").size(), 1u << 20);
  files.write(3, 3000, {1});  // after stop: refused, counted
  EXPECT_EQ(files.failed(), 1u);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "recordings" / "match-3-3000.rcr"));
}

TEST(RecordingFiles, AnUnusableDirectoryIsCountedNotFatal) {
  const test::TempDir dir("ricochet-recordings");
  std::ofstream(dir.path() / "taken") << "a file where the directory should be";
  const std::string error =
      write_file_atomically(dir.path() / "taken", "x.rcr", std::vector<std::uint8_t>{1});
  EXPECT_NE(error.find("cannot create"), std::string::npos) << error;
  RecordingFiles files(dir.path() / "taken");
  files.write(1, 1, {1, 2});
  files.stop();
  EXPECT_EQ(files.written(), 0u);
  EXPECT_EQ(files.failed(), 1u);
}

}  // namespace
}  // namespace ricochet::server
