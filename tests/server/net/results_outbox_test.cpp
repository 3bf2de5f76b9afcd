// The results outbox on a real directory: a kept record reads back whole in a new process's
// outbox (every field, bit for bit), a removed one is gone, a keep cut short by a crash is never
// delivered, and a file that is not a record (corrupt, truncated, oversized, misnamed, another
// match inside) is moved to rejected/ with its reason, counted, and never stops the others.
// Two outboxes on one directory (the servers of one shared volume): each delivers what it
// finds, a record the other removes while it lists is passed over (not rejected), and a .tmp
// the other is writing (its flock held) is left alone; a live one picks up, on fake time, the
// records another left once they are old enough, and never its own.
#include "results_outbox.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "temp_dir.h"

namespace ricochet::server::results_outbox_test {
namespace {

namespace fs = std::filesystem;

constexpr const char* kUuidA = "0123456789abcdef0123456789abcdef";
constexpr const char* kUuidB = "fedcba9876543210fedcba9876543210";

OutboxRecord record(const std::string& uuid, const std::string& mode = "ffa") {
  OutboxRecord out;
  out.match_id = 42;
  db::MatchRecord& r = out.record;
  r.uuid = uuid;
  r.map = "foundry";
  r.mode = mode;
  r.started_ms = 1'700'000'000'123;
  r.ended_ms = 1'700'000'300'456;
  r.tick_rate = 60;
  r.aborted = true;
  if (mode == "tdm") r.team_scores = {7, -2};
  for (int i = 0; i < 3; ++i) {
    db::PlayerResult p;
    p.account = 9'000'000'000LL + i;
    p.team = mode == "tdm" ? 1 + i % 2 : 0;
    p.kills = 10 + i;
    p.deaths = 3;
    p.score = -1 - i;
    p.shots = 100;
    p.hits = 37;
    p.damage_dealt = 512.125;
    p.damage_taken = 0.1;  // not exact in binary: must come back bit for bit
    p.seconds_played = 299.999;
    r.players.push_back(p);
  }
  return out;
}

void expect_same(const OutboxRecord& a, const OutboxRecord& b) {
  EXPECT_EQ(a.match_id, b.match_id);
  const db::MatchRecord &x = a.record, &y = b.record;
  EXPECT_EQ(x.uuid, y.uuid);
  EXPECT_EQ(x.map, y.map);
  EXPECT_EQ(x.mode, y.mode);
  EXPECT_EQ(x.started_ms, y.started_ms);
  EXPECT_EQ(x.ended_ms, y.ended_ms);
  EXPECT_EQ(x.tick_rate, y.tick_rate);
  EXPECT_EQ(x.aborted, y.aborted);
  EXPECT_EQ(x.team_scores.red, y.team_scores.red);
  EXPECT_EQ(x.team_scores.blue, y.team_scores.blue);
  ASSERT_EQ(x.players.size(), y.players.size());
  for (std::size_t i = 0; i < x.players.size(); ++i) {
    const db::PlayerResult &p = x.players[i], &q = y.players[i];
    EXPECT_EQ(p.account, q.account);
    EXPECT_EQ(p.team, q.team);
    EXPECT_EQ(p.kills, q.kills);
    EXPECT_EQ(p.deaths, q.deaths);
    EXPECT_EQ(p.score, q.score);
    EXPECT_EQ(p.shots, q.shots);
    EXPECT_EQ(p.hits, q.hits);
    EXPECT_EQ(p.damage_dealt, q.damage_dealt);
    EXPECT_EQ(p.damage_taken, q.damage_taken);
    EXPECT_EQ(p.seconds_played, q.seconds_played);
  }
}

void write(const fs::path& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file()) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(ResultsOutbox, AKeptRecordReadsBackWholeInTheNextProcessAndARemovedOneIsGone) {
  ricochet::test::TempDir dir;
  const fs::path outbox = dir.path() / "outbox";
  {
    ResultsOutbox first(outbox);
    ASSERT_TRUE(first.keep(record(kUuidA)));
    ASSERT_TRUE(first.keep(record(kUuidB, "tdm")));
    ASSERT_TRUE(first.keep(record(kUuidB, "tdm")));  // again: the same file
    EXPECT_EQ(first.files(), 2u);
    EXPECT_EQ(names_in(outbox), (std::vector<std::string>{std::string(kUuidA) + ".rec",
                                                          std::string(kUuidB) + ".rec"}));
  }
  ResultsOutbox next(outbox);  // as the next start finds it
  const std::vector<OutboxRecord> left = next.list();
  ASSERT_EQ(left.size(), 2u);
  EXPECT_EQ(next.files(), 2u);
  expect_same(left[0], record(kUuidA));
  expect_same(left[1], record(kUuidB, "tdm"));
  next.remove(kUuidA);
  EXPECT_EQ(next.files(), 1u);
  EXPECT_EQ(names_in(outbox), std::vector<std::string>{std::string(kUuidB) + ".rec"});
  next.remove(kUuidA);  // twice: nothing more
  EXPECT_EQ(next.files(), 1u);
  EXPECT_EQ(next.rejected(), 0u);
}

TEST(ResultsOutbox, AKeepCutShortByACrashIsNeverDelivered) {
  ricochet::test::TempDir dir;
  ResultsOutbox outbox(dir.path());
  const std::vector<std::uint8_t> bytes = encode_outbox_record(record(kUuidA));
  write(dir.path() / (std::string(kUuidA) + ".rec.tmp"), bytes);
  EXPECT_TRUE(outbox.list().empty());
  EXPECT_TRUE(names_in(dir.path()).empty());
  EXPECT_EQ(outbox.rejected(), 0u);
}

TEST(ResultsOutbox, FilesThatAreNotRecordsAreMovedAsideWithTheirReasonAndTheRestDelivered) {
  ricochet::test::TempDir dir;
  ResultsOutbox outbox(dir.path());
  const std::vector<std::uint8_t> good = encode_outbox_record(record(kUuidA));
  ASSERT_TRUE(outbox.keep(record(kUuidA)));
  const auto named = [&](char c) {
    std::string name(32, c);     // not `std::string(32, c) + ".rec"`: GCC 12 -O3 warns falsely
    return name.append(".rec");  // (-Warray-bounds in the inlined operator+)
  };
  std::vector<std::uint8_t> flipped = encode_outbox_record(record(std::string(32, '1')));
  flipped[flipped.size() - 3] ^= 0x10;      // in the last player's time: only the CRC tells
  write(dir.path() / named('1'), flipped);  // CRC-32 mismatch
  write(dir.path() / named('2'), std::vector<std::uint8_t>(good.begin(), good.begin() + 30));
  write(dir.path() / named('3'), {});
  write(dir.path() / named('4'), std::vector<std::uint8_t>(kMaxOutboxFileBytes + 1, 0));
  write(dir.path() / "notes.txt", good);                     // not <uuid>.rec
  write(dir.path() / (std::string(kUuidB) + ".rec"), good);  // holds kUuidA's match
  const std::vector<OutboxRecord> left = outbox.list();
  ASSERT_EQ(left.size(), 1u);
  expect_same(left[0], record(kUuidA));
  EXPECT_EQ(outbox.rejected(), 6u);
  EXPECT_EQ(outbox.files(), 1u);
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{std::string(kUuidA) + ".rec"});
  EXPECT_EQ(names_in(dir.path() / "rejected").size(), 6u);
  EXPECT_TRUE(outbox.list().size() == 1u && outbox.rejected() == 6u);  // once moved, left alone
}

/// A uuid per `i`: 32 hex digits.
std::string uuid_of(int i) {
  std::string uuid(32, '0');
  const std::string digits = std::to_string(i);
  uuid.replace(uuid.size() - digits.size(), digits.size(), digits);
  return uuid;
}

TEST(ResultsOutbox, TwoOnOneDirectoryEachDeliverWhatTheyFindAndRemoveOnce) {
  ricochet::test::TempDir dir;
  ResultsOutbox a(dir.path());
  ResultsOutbox b(dir.path());
  ASSERT_TRUE(a.keep(record(kUuidA)));
  ASSERT_TRUE(b.keep(record(kUuidB, "tdm")));
  ASSERT_EQ(a.list().size(), 2u);  // b's record too: whoever starts delivers it
  ASSERT_EQ(b.list().size(), 2u);
  EXPECT_EQ(a.files(), 2u);
  a.remove(kUuidA);
  a.remove(kUuidB);  // delivered by a: record_match keeps it once whoever delivers it again
  b.remove(kUuidB);  // gone already: nothing to log, and no longer counted
  b.remove(kUuidA);
  EXPECT_EQ(a.files(), 0u);
  EXPECT_EQ(b.files(), 0u);
  EXPECT_TRUE(names_in(dir.path()).empty());
  EXPECT_EQ(a.rejected() + b.rejected(), 0u);
}

TEST(ResultsOutbox, ARecordAnotherProcessRemovesWhileThisOneListsIsPassedOverNotRejected) {
  ricochet::test::TempDir dir;
  ResultsOutbox delivering(dir.path());
  ResultsOutbox starting(dir.path());
  constexpr int kRecords = 64;
  for (int i = 0; i < kRecords; ++i) ASSERT_TRUE(delivering.keep(record(uuid_of(i))));
  std::atomic<bool> done{false};
  std::thread remover([&] {
    for (int i = 0; i < kRecords; ++i) delivering.remove(uuid_of(i));
    done = true;
  });
  int lists = 0;
  while (!done || lists == 0) {
    for (const OutboxRecord& found : starting.list()) EXPECT_EQ(found.record.players.size(), 3u);
    ++lists;
  }
  remover.join();
  EXPECT_EQ(starting.rejected(), 0u) << "after " << lists << " lists";
  EXPECT_TRUE(names_in(dir.path() / "rejected").empty());
  EXPECT_TRUE(starting.list().empty());
  EXPECT_EQ(starting.files(), 0u);  // what it listed is gone: not counted as kept any more
}

/// Sets `file`'s last write to `unix_s` (Unix seconds): the outbox's age rule on fake time.
void written_at(const fs::path& file, std::int64_t unix_s) {
  const timespec times[2] = {{unix_s, 0}, {unix_s, 0}};
  ASSERT_EQ(::utimensat(AT_FDCWD, file.c_str(), times, 0), 0) << file;
}

TEST(ResultsOutbox, ALiveOneTakesTheRecordsAnotherLeftOnceOldEnoughButNotItsOwn) {
  constexpr std::int64_t kWrittenS = 1'700'000'000;
  constexpr std::int64_t kAgeMs = 60'000;
  ricochet::test::TempDir dir;
  ResultsOutbox live(dir.path());
  EXPECT_TRUE(live.list().empty());  // its start: nothing left yet
  {
    ResultsOutbox dead(dir.path());  // another server, killed after keeping its record
    ASSERT_TRUE(dead.keep(record(kUuidA)));
  }
  ASSERT_TRUE(live.keep(record(kUuidB, "tdm")));  // its own, being delivered
  written_at(dir.path() / (std::string(kUuidA) + ".rec"), kWrittenS);
  written_at(dir.path() / (std::string(kUuidB) + ".rec"), kWrittenS);
  // Too young: its writer may still be delivering it.
  EXPECT_TRUE(live.list_left(kWrittenS * 1000 + kAgeMs - 1, kAgeMs).empty());
  const auto left = live.list_left(kWrittenS * 1000 + kAgeMs, kAgeMs);
  ASSERT_EQ(left.size(), 1u);
  EXPECT_EQ(left[0].record.uuid, kUuidA);
  EXPECT_EQ(live.files(), 2u);
  // Held now: the next rescan does not deliver it a second time.
  EXPECT_TRUE(live.list_left(kWrittenS * 1000 + 10 * kAgeMs, kAgeMs).empty());
  live.remove(kUuidA);
  live.remove(kUuidB);
  EXPECT_TRUE(names_in(dir.path()).empty());
  EXPECT_EQ(live.rejected(), 0u);
}

TEST(ResultsOutbox, ATmpAnotherProcessIsWritingIsLeftAloneAndRemovedOnceItsWriterIsGone) {
  ricochet::test::TempDir dir;
  ResultsOutbox outbox(dir.path());
  const std::string tmp = std::string(kUuidA) + ".rec.tmp";
  write(dir.path() / tmp, {1, 2, 3});
  // A live keep() in another process holds the lock until its rename.
  const int writer = ::open((dir.path() / tmp).c_str(), O_RDWR | O_CLOEXEC);
  ASSERT_GE(writer, 0);
  ASSERT_EQ(::flock(writer, LOCK_EX), 0);
  EXPECT_TRUE(outbox.list().empty());
  EXPECT_EQ(names_in(dir.path()), std::vector<std::string>{tmp});
  ::close(writer);  // the writer killed: the kernel drops its lock
  EXPECT_TRUE(outbox.list().empty());
  EXPECT_TRUE(names_in(dir.path()).empty());
  EXPECT_EQ(outbox.rejected(), 0u);
}

TEST(ResultsOutboxFormat, EachWayOfBeingBrokenIsRefusedWithWhatIsWrong) {
  const std::vector<std::uint8_t> good = encode_outbox_record(record(kUuidA));
  ASSERT_TRUE(decode_outbox_record(good).ok);
  const auto problem = [](std::vector<std::uint8_t> bytes) {
    const DecodedOutbox decoded = decode_outbox_record(bytes);
    EXPECT_FALSE(decoded.ok);
    return decoded.problem;
  };
  auto has = [](const std::string& text, const char* word) {
    return text.find(word) != std::string::npos;
  };
  std::vector<std::uint8_t> magic = good;
  magic[0] = 'X';
  EXPECT_TRUE(has(problem(magic), "RCOUTBOX"));
  std::vector<std::uint8_t> version = good;
  version[8] = 2;
  EXPECT_TRUE(has(problem(version), "version 2"));
  EXPECT_TRUE(has(problem({good.begin(), good.begin() + 10}), "truncated"));
  EXPECT_TRUE(has(problem({good.begin(), good.end() - 1}), "truncated"));
  std::vector<std::uint8_t> longer = good;
  longer.push_back(0);
  EXPECT_TRUE(has(problem(longer), "trailing"));
  std::vector<std::uint8_t> flipped = good;
  flipped.back() ^= 1;
  EXPECT_TRUE(has(problem(flipped), "CRC-32 mismatch"));
  std::vector<std::uint8_t> huge = good;
  huge[13] = 0x7f;  // a length of about 2 GB
  EXPECT_TRUE(has(problem(huge), "oversized"));
  // A payload whose CRC matches but whose content is wrong: the checks behind the CRC hold.
  OutboxRecord bad_uuid = record(kUuidA);
  bad_uuid.record.uuid = "0123456789ABCDEF0123456789ABCDEF";
  EXPECT_TRUE(has(problem(encode_outbox_record(bad_uuid)), "uuid"));
  OutboxRecord nobody = record(kUuidA);
  nobody.record.players.clear();
  EXPECT_TRUE(has(problem(encode_outbox_record(nobody)), "player count"));
}

}  // namespace
}  // namespace ricochet::server::results_outbox_test
