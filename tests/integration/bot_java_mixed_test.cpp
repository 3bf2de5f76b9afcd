// Java bots and C++ bots in one match, nothing in-process: the real ricochet-server binary, the
// Java client library's bot (`java -jar ricochet-java-bot.jar`) and ricochet-bot, each a child
// process on 127.0.0.1. They play one recorded match to its time limit; then the database (read
// through the db module's API once the server has exited) and the recording's replay hold, for
// every bot of either language, the kills and deaths it counted from the Kill events it saw.
// Built only with the Java client (RICOCHET_JAVA). Every wait is bounded.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "ctest_budget.h"
#include "postgres_cluster.h"
#include "replay_process.h"
#include "ricochet/db/store.h"
#include "server_process.h"

namespace ricochet::test::bot_java_mixed_test {
namespace {

using namespace std::chrono_literals;
using ricochet::test::PostgresCluster;

constexpr std::chrono::seconds kStartBudget{10};
/// Beyond the time limit: two JVMs and a C++ process start, four accounts register and sign in
/// (Argon2), join, and the results come back.
constexpr std::chrono::seconds kSignInBudget{25};
constexpr int kShutdownGraceS = 5;
constexpr std::chrono::seconds kExitBudget{kShutdownGraceS + 3};

/// A child process with its stdout and stderr in files; killed with the test (PDEATHSIG) and,
/// when still running, by the destructor.
class Child {
 public:
  Child(const std::vector<std::string>& argv, const std::filesystem::path& out,
        const std::filesystem::path& err)
      : out_(out), err_(err) {
    std::vector<char*> args;
    for (const std::string& each : argv) args.push_back(const_cast<char*>(each.c_str()));
    args.push_back(nullptr);
    const int out_fd = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    const int err_fd = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (out_fd < 0 || err_fd < 0) throw std::runtime_error("cannot create " + out.string());
    const pid_t parent = getpid();
    pid_ = fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || getppid() != parent) _exit(125);
      if (dup2(out_fd, STDOUT_FILENO) < 0 || dup2(err_fd, STDERR_FILENO) < 0) _exit(126);
      execv(args[0], args.data());
      _exit(127);
    }
    close(out_fd);
    close(err_fd);
  }
  ~Child() {
    if (!exit_code_) {
      kill(pid_, SIGKILL);
      int status = 0;
      waitpid(pid_, &status, 0);
    }
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  /// Its exit code (128 + signal), or nullopt when it is still running at `deadline`.
  std::optional<int> wait_exit(std::chrono::steady_clock::time_point deadline) {
    while (!exit_code_) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exit_code_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        break;
      }
      if (std::chrono::steady_clock::now() >= deadline) break;
      std::this_thread::sleep_for(20ms);
    }
    return exit_code_;
  }
  std::string out() const { return read_text(out_); }
  std::string err() const { return read_text(err_); }

 private:
  std::filesystem::path out_;
  std::filesystem::path err_;
  pid_t pid_ = -1;
  std::optional<int> exit_code_;
};

/// What a bot's JSON line (ricochet-bot's and ricochet-java-bot's share the shape:
/// per_bot[{"name":..,"state":..,"error":..,"metrics":{..}}]) says of each bot.
struct BotLine {
  std::string state;
  std::string error;
  std::string metrics;
};

std::map<std::string, BotLine> per_bot(const std::string& json) {
  std::map<std::string, BotLine> bots;
  const std::regex entry(
      R"re(\{"name":"([^"]*)","state":"([^"]*)","error":"([^"]*)","metrics":(\{[^}]*\}))re");
  for (std::sregex_iterator it(json.begin(), json.end(), entry), end; it != end; ++it) {
    bots[(*it)[1].str()] = {(*it)[2].str(), (*it)[3].str(), (*it)[4].str()};
  }
  return bots;
}

/// The integer after `"key":` in a metrics object (-1 when absent).
long long integer(const std::string& metrics, const std::string& key) {
  std::smatch match;
  if (!std::regex_search(metrics, match, std::regex("\"" + key + "\":(-?[0-9]+)"))) return -1;
  return std::stoll(match[1].str());
}

/// The number after `"key":` in the replay's score object of `account` (-1 when absent).
long long replay_score(const std::string& json, std::uint64_t account, const std::string& key) {
  const auto at = json.find("{\"account\":" + std::to_string(account) + ",");
  if (at == std::string::npos) return -1;
  const auto field = json.find("\"" + key + "\":", at);
  if (field == std::string::npos) return -1;
  return std::stoll(json.substr(field + key.size() + 3));
}

TEST(MixedBots, JavaAndCppBotsPlayToTheTimeLimitAndTheDatabaseHoldsTheKillsEachSaw) {
  constexpr std::chrono::seconds kTimeLimit{10};
  static_assert(fits_ctest(kStartBudget + kTimeLimit + kSignInBudget + kExitBudget));
  // Four players start the match (two of each); its time limit runs from then.
  const std::string matches =
      "count = 1\nmax_players = 16\nmaps = [\"" RICOCHET_SOURCE_DIR
      "/server/maps/arena.toml\"]\nseed = 42\nwarmup_s = 0\nfrag_limit = 0\nrecord = true\n"
      "min_players = 4\ntime_limit_s = " +
      std::to_string(kTimeLimit.count()) + "\n";
  ServerProcess server(matches, kShutdownGraceS,
                       "[db]\npassword_hashing = \"minimum\"\n"
                       "registrations_per_hour_per_address = 1000\n");
  ASSERT_TRUE(server.wait_listening(kStartBudget)) << server.log();
  const std::string port = std::to_string(server.control_port());
  const std::string play_s = std::to_string((kTimeLimit + kSignInBudget).count());
  const auto dir = server.dir();
  Child java({RICOCHET_JAVA_EXECUTABLE,
              "-jar",
              RICOCHET_JAVA_BOT_JAR,
              "--host",
              "127.0.0.1",
              "--control-port",
              port,
              "--pin-sha256",
              server.fingerprint(),
              "--bots",
              "2",
              "--name",
              "jmix",
              "--password",
              "password-of-jmix",
              "--skill",
              "0.9",
              "--matches",
              "1",
              "--duration-s",
              play_s},
             dir / "java.out", dir / "java.err");
  Child cpp({RICOCHET_BOT_BINARY,
             "--host",
             "127.0.0.1",
             "--port",
             port,
             "--fingerprint",
             server.fingerprint(),
             "--bots",
             "2",
             "--name",
             "cmix",
             "--password",
             "password-of-cmix",
             "--skill",
             "0.9",
             "--seed",
             "5",
             "--matches",
             "1",
             "--duration-s",
             play_s},
            dir / "cpp.out", dir / "cpp.err");
  const auto deadline = std::chrono::steady_clock::now() + kTimeLimit + kSignInBudget;
  const std::optional<int> java_exit = java.wait_exit(deadline);
  const std::optional<int> cpp_exit = cpp.wait_exit(deadline);
  std::cout << "[ figures  ] java: " << java.out() << "[ figures  ] c++: " << cpp.out();
  ASSERT_EQ(java_exit, std::optional<int>(0)) << java.err();
  ASSERT_EQ(cpp_exit, std::optional<int>(0)) << cpp.err();
  server.terminate();
  ASSERT_EQ(server.wait_exit(kExitBudget), std::optional<int>(0)) << server.log();

  std::map<std::string, BotLine> bots = per_bot(java.out());
  const std::map<std::string, BotLine> cpp_bots = per_bot(cpp.out());
  ASSERT_EQ(bots.size(), 2u) << java.out();
  ASSERT_EQ(cpp_bots.size(), 2u) << cpp.out();
  for (const auto& [name, line] : bots) {
    // The Java bot also kept the server's MatchResults: its own count agrees with them.
    EXPECT_EQ(integer(line.metrics, "kills"), integer(line.metrics, "result_kills")) << name;
    EXPECT_EQ(integer(line.metrics, "deaths"), integer(line.metrics, "result_deaths")) << name;
  }
  bots.insert(cpp_bots.begin(), cpp_bots.end());

  // The database (the server has exited: the file is ours), and the recording's replay.
  auto opened = db::open_sqlite_store({.path = server.db_path().string()});
  ASSERT_TRUE(opened.ok());
  std::unique_ptr<db::Store> store = std::move(opened).value();
  std::vector<std::filesystem::path> recordings;
  for (const auto& entry : std::filesystem::directory_iterator(server.data_dir() / "recordings")) {
    if (entry.path().extension() == ".rcr") recordings.push_back(entry.path());
  }
  ASSERT_EQ(recordings.size(), 1u);
  const auto [replay_exit, replayed] = replay(recordings[0]);
  EXPECT_EQ(replay_exit, 0) << replayed;
  EXPECT_NE(replayed.find("\"hashes_differing\":0,"), std::string::npos) << replayed;

  long long kills = 0;
  long long deaths = 0;
  for (const auto& [name, line] : bots) {
    EXPECT_EQ(line.state, "done") << name;
    EXPECT_EQ(line.error, "") << name;
    EXPECT_EQ(integer(line.metrics, "matches"), 1) << name;
    EXPECT_GT(integer(line.metrics, "snapshots"), 200) << name;
    std::string key = name;
    std::transform(key.begin(), key.end(), key.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    const auto account = store->find_account_by_key(key);
    ASSERT_TRUE(account.ok() && account.value().has_value()) << name;
    const db::AccountId id = account.value()->account.id;
    const auto stats = store->player_stats(id);
    ASSERT_TRUE(stats.ok()) << name;
    EXPECT_EQ(stats.value().matches, 1) << name;
    EXPECT_EQ(stats.value().kills, integer(line.metrics, "kills")) << name << " " << line.metrics;
    EXPECT_EQ(stats.value().deaths, integer(line.metrics, "deaths")) << name << " " << line.metrics;
    EXPECT_EQ(replay_score(replayed, static_cast<std::uint64_t>(id), "kills"), stats.value().kills)
        << name;
    EXPECT_EQ(replay_score(replayed, static_cast<std::uint64_t>(id), "deaths"),
              stats.value().deaths)
        << name;
    kills += stats.value().kills;
    deaths += stats.value().deaths;
  }
  // Every kill is someone's death (deaths also count suicides and the world's).
  EXPECT_GE(deaths, kills);
  std::cout << "[ figures  ] kills " << kills << ", deaths " << deaths << " among the four"
            << std::endl;
  if (HasFailure()) std::cout << "server log:\n" << server.log();
}

/// Placement (PROTOCOL.md, Placement) followed by the Java client: two real servers on one
/// PostgreSQL database, A hosting only ffa (a match that never starts with one player), B only a
/// short tdm match. One Java bot signs in on A with `--find-match tdm`: A assigns it to B, the bot
/// connects to B pinned to the assignment's fingerprint, resumes its session there, joins with
/// the ticket and plays B's match to its end; then asks B, which places it on itself
/// (on_this_server), for a second match. The database holds both matches for it.
TEST(MixedBots, AJavaBotSignedInOnOneServerFollowsItsAssignmentToAnotherAndPlaysThere) {
  constexpr std::chrono::seconds kTimeLimit{2};
  constexpr std::chrono::seconds kPlayBudget{20};   // a JVM, a sign-in, placement, two TLS
  constexpr std::chrono::seconds kReportBudget{5};  // the bot's own limit ran out: its report
  static_assert(fits_ctest(kStartBudget + kPlayBudget + kReportBudget + kExitBudget));
  const std::string url = PostgresCluster::shared().create_database();
  const auto matches = [](const std::string& mode, int min_players, int time_limit_s) {
    return "count = 1\nmax_players = 8\nmode = \"" + mode +
           "\"\nmaps = [\"" RICOCHET_SOURCE_DIR
           "/server/maps/arena.toml\"]\nseed = 7\nwarmup_s = 0\nrecord = false\n"
           "min_players = " +
           std::to_string(min_players) + "\ntime_limit_s = " + std::to_string(time_limit_s) + "\n";
  };
  const std::string fleet = "[db]\nurl = \"" + url +
                            "\"\npassword_hashing = \"minimum\"\n[placement]\n"
                            "advertise_host = \"127.0.0.1\"\nheartbeat_s = 1\nserver_ttl_s = 5\n";
  ServerProcess a(matches("ffa", 2, 600), kShutdownGraceS, fleet);
  ServerProcess b(matches("tdm", 1, static_cast<int>(kTimeLimit.count())), kShutdownGraceS, fleet);
  ASSERT_TRUE(a.wait_listening(kStartBudget)) << a.log();
  ASSERT_TRUE(b.wait_listening(kStartBudget)) << b.log();
  // Both in the directory before the bot asks (each logs its first heartbeat's row).
  const auto listed_by = std::chrono::steady_clock::now() + kStartBudget;
  while (a.log().find("is in the fleet directory") == std::string::npos ||
         b.log().find("is in the fleet directory") == std::string::npos) {
    ASSERT_LT(std::chrono::steady_clock::now(), listed_by) << a.log() << b.log();
    std::this_thread::sleep_for(20ms);
  }
  const auto dir = a.dir();
  Child java({RICOCHET_JAVA_EXECUTABLE,
              "-jar",
              RICOCHET_JAVA_BOT_JAR,
              "--host",
              "127.0.0.1",
              "--control-port",
              std::to_string(a.control_port()),
              "--pin-sha256",
              a.fingerprint(),
              "--name",
              "jplaced",
              "--password",
              "password-of-jplaced",
              "--find-match",
              "tdm",
              "--matches",
              "2",
              "--log-level",
              "info",
              "--duration-s",
              std::to_string(kPlayBudget.count())},
             dir / "placed.out", dir / "placed.err");
  const std::optional<int> exit =
      java.wait_exit(std::chrono::steady_clock::now() + kPlayBudget + kReportBudget);
  std::cout << "[ figures  ] java: " << java.out();
  ASSERT_EQ(exit, std::optional<int>(0)) << java.err();
  const std::map<std::string, BotLine> bots = per_bot(java.out());
  ASSERT_EQ(bots.size(), 1u) << java.out();
  const BotLine& line = bots.begin()->second;
  EXPECT_EQ(line.state, "done") << java.err();
  EXPECT_EQ(line.error, "") << java.err();
  EXPECT_EQ(integer(line.metrics, "matches"), 2) << java.err();  // only B's matches end
  EXPECT_GT(integer(line.metrics, "snapshots"), 0) << java.err();
  EXPECT_NE(java.err().find("joined match 1 on 127.0.0.1"), std::string::npos) << java.err();

  auto store = db::open_store({.url_or_path = url});
  ASSERT_TRUE(store.ok());
  const auto account = store.value()->find_account_by_key("jplaced");
  ASSERT_TRUE(account.ok() && account.value().has_value());
  const auto stats = store.value()->player_stats(account.value()->account.id);
  ASSERT_TRUE(stats.ok());
  EXPECT_EQ(stats.value().matches, 2);
  if (HasFailure()) std::cout << "A's log:\n" << a.log() << "B's log:\n" << b.log();
}

}  // namespace
}  // namespace ricochet::test::bot_java_mixed_test
