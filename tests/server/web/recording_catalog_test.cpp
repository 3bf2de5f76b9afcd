// The recordings directory listed from each file's header and footer (recording_catalog.h):
// a real recording with its map, mode, length and size; a cut one as incomplete; corrupt,
// truncated and strangely named files as unreadable with a reason, counted once; ids checked
// before any path is made from them.

#include "recording_catalog.h"

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "scripted_recording.h"
#include "temp_dir.h"
#include "version1_recording.h"

namespace ricochet::server::recording_catalog_test {
namespace {

void write(const std::filesystem::path& path, std::span<const std::uint8_t> bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

const RecordingEntry* entry_of(const RecordingList& list, const std::string& id) {
  for (const RecordingEntry& entry : list.entries) {
    if (entry.id == id) return &entry;
  }
  return nullptr;
}

TEST(RecordingCatalogTest, ARecordingIsListedFromItsHeaderAndFooter) {
  ricochet::test::TempDir dir("ricochet-catalog");
  const std::vector<std::uint8_t> bytes = web_test::scripted_recording(600);
  write(dir.path() / "match-3-1764966123456.rcr", bytes);
  // A cut file: the first half, as a crash leaves it.
  write(dir.path() / "match-4-1764966000000.interrupted.rcr",
        std::span(bytes).first(bytes.size() / 2));
  RecordingCatalog catalog(dir.path());
  const RecordingList list = catalog.list();
  ASSERT_EQ(list.entries.size(), 2u);
  EXPECT_EQ(list.unreadable, 0u);
  EXPECT_EQ(list.entries[0].id, "match-3-1764966123456") << "newest first";

  const RecordingEntry& whole = list.entries[0];
  EXPECT_EQ(whole.unreadable, "");
  EXPECT_EQ(whole.match_id, 3u);
  EXPECT_EQ(whole.unix_ms, 1764966123456);
  EXPECT_EQ(whole.size_bytes, bytes.size());
  EXPECT_EQ(whole.map, "arena");
  EXPECT_EQ(whole.mode, "ffa");
  EXPECT_EQ(whole.tick_rate_hz, 60u);
  EXPECT_TRUE(whole.complete);
  EXPECT_FALSE(whole.truncated);
  EXPECT_FALSE(whole.interrupted);
  auto read = read_recording(bytes);
  ASSERT_TRUE(std::holds_alternative<Recording>(read));
  ASSERT_TRUE(whole.ticks.has_value());
  EXPECT_EQ(*whole.ticks, std::get<Recording>(read).ticks.back().tick);
  EXPECT_DOUBLE_EQ(*whole.seconds, *whole.ticks / 60.0);
  EXPECT_EQ(whole.players, 4u);

  const RecordingEntry& cut = list.entries[1];
  EXPECT_EQ(cut.unreadable, "");
  EXPECT_TRUE(cut.interrupted);
  EXPECT_FALSE(cut.complete);
  EXPECT_FALSE(cut.ticks.has_value());
  EXPECT_FALSE(cut.players.has_value());
  EXPECT_EQ(cut.map, "arena");

  const std::string json = recording_list_json(list);
  EXPECT_NE(json.find("{\"id\":\"match-3-1764966123456\",\"match_id\":3,\"unix_ms\":1764966123456,"
                      "\"size_bytes\":" +
                      std::to_string(bytes.size()) +
                      ",\"interrupted\":false,\"map\":\"arena\",\"mode\":\"ffa\","
                      "\"tick_rate_hz\":60,\"complete\":true,\"truncated\":false,\"ticks\":" +
                      std::to_string(*whole.ticks)),
            std::string::npos)
      << json;
  EXPECT_NE(json.find(",\"players\":4}"), std::string::npos) << json;
  EXPECT_NE(json.find("\"ticks\":null,\"seconds\":null,\"players\":null}"), std::string::npos)
      << json;
}

TEST(RecordingCatalogTest, AVersion1RecordingIsListedWithItsPlayersUnknown) {
  ricochet::test::TempDir dir("ricochet-catalog");
  const std::vector<std::uint8_t> bytes =
      recording_test::as_version_1(web_test::scripted_recording(120));
  write(dir.path() / "match-2-1764966000000.rcr", bytes);
  RecordingCatalog catalog(dir.path());
  const RecordingList list = catalog.list();
  ASSERT_EQ(list.entries.size(), 1u);
  const RecordingEntry& old = list.entries[0];
  EXPECT_EQ(old.unreadable, "");
  EXPECT_EQ(old.map, "arena");
  EXPECT_TRUE(old.complete);
  ASSERT_TRUE(old.ticks.has_value());
  EXPECT_GT(*old.ticks, 0u);
  EXPECT_FALSE(old.players.has_value());
  const std::string json = recording_list_json(list);
  EXPECT_NE(json.find(",\"ticks\":" + std::to_string(*old.ticks)), std::string::npos) << json;
  EXPECT_NE(json.find(",\"players\":null}"), std::string::npos) << json;
}

TEST(RecordingCatalogTest, CorruptTruncatedAndStrangeFilesAreUnreadableWithAReasonCountedOnce) {
  ricochet::test::TempDir dir("ricochet-catalog");
  std::vector<std::uint8_t> bytes = web_test::scripted_recording(120);
  write(dir.path() / "match-1-1.rcr", std::span(bytes).first(20));  // inside the header chunk
  write(dir.path() / "match-2-2.rcr", std::vector<std::uint8_t>{});
  write(dir.path() / "match-3-3.rcr", std::vector<std::uint8_t>(100, 'x'));
  std::vector<std::uint8_t> flipped = bytes;
  flipped[30] ^= 0x10;  // in the header chunk's payload
  write(dir.path() / "match-4-4.rcr", flipped);
  write(dir.path() / "evil.rcr", bytes);  // not a name the server writes
  write(dir.path() / "match-5-5.rcr", bytes);
  write(dir.path() / "notes.txt", bytes);  // not listed at all
  RecordingCatalog catalog(dir.path());
  const RecordingList list = catalog.list();
  EXPECT_EQ(list.entries.size(), 6u);
  EXPECT_EQ(list.unreadable, 5u);
  EXPECT_EQ(catalog.unreadable_files(), 5u);
  const auto reason = [&](const std::string& id) {
    const RecordingEntry* entry = entry_of(list, id);
    return entry ? entry->unreadable : std::string("(not listed)");
  };
  EXPECT_NE(reason("match-1-1").find("truncated at byte 20 in chunk 0"), std::string::npos)
      << reason("match-1-1");
  EXPECT_NE(reason("match-2-2").find("in the magic"), std::string::npos) << reason("match-2-2");
  EXPECT_NE(reason("match-3-3").find("not a ricochet recording"), std::string::npos)
      << reason("match-3-3");
  EXPECT_NE(reason("match-4-4").find("CRC-32 mismatch"), std::string::npos) << reason("match-4-4");
  EXPECT_NE(reason("evil").find("not a name the server writes"), std::string::npos);
  EXPECT_EQ(reason("match-5-5"), "");

  catalog.list();
  EXPECT_EQ(catalog.unreadable_files(), 5u) << "each bad file counted (and logged) once";
  write(dir.path() / "match-2-2.rcr", std::vector<std::uint8_t>(3, 0));  // changed: new
  catalog.list();
  EXPECT_EQ(catalog.unreadable_files(), 6u);
}

TEST(RecordingCatalogTest, IdsAreCheckedBeforeAPathIsMadeOfThem) {
  ricochet::test::TempDir dir("ricochet-catalog");
  const std::filesystem::path recordings = dir.path() / "recordings";
  std::filesystem::create_directories(recordings);
  write(recordings / "match-1-2.rcr", std::vector<std::uint8_t>{1});
  write(dir.path() / "secret.rcr", std::vector<std::uint8_t>{1});
  std::filesystem::create_symlink(dir.path() / "secret.rcr", recordings / "match-9-9.rcr");
  RecordingCatalog catalog(recordings);
  std::string error;
  for (const std::string& id : std::vector<std::string>{
           "../secret", "match-1-2/../../secret", "../recordings/match-1-2", "match-1-2.rcr", "",
           "match-1-", "match--2", "match-1-2.interrupted.x", "match-1-2 ", "match-+1-2",
           "match-1-2" + std::string(1, '\0'), "/etc/passwd", "match-1-99999999999999999999",
           "match-1-" + std::string(60, '1')}) {
    EXPECT_FALSE(catalog.file_of(id, error).has_value()) << id;
    EXPECT_NE(error.find("a recording id is match-<match id>-<unix ms>"), std::string::npos)
        << id << ": " << error;
  }
  EXPECT_EQ(catalog.bad_ids(), 14u);
  EXPECT_FALSE(catalog.file_of("match-9-9", error).has_value()) << "a symbolic link is no file";
  EXPECT_FALSE(catalog.file_of("match-7-7", error).has_value());
  EXPECT_EQ(error, "no recording match-7-7");
  const auto file = catalog.file_of("match-1-2", error);
  ASSERT_TRUE(file.has_value()) << error;
  EXPECT_EQ(*file, recordings / "match-1-2.rcr");
  EXPECT_EQ(catalog.bad_ids(), 14u);
}

}  // namespace
}  // namespace ricochet::server::recording_catalog_test
