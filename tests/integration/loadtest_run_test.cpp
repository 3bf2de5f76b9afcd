// ricochet-loadtest end to end: the real ricochet-server binary on 127.0.0.1 (free ports, a
// temporary data directory; three of them on one real PostgreSQL for placement), the real
// ricochet-loadtest binary against it. The tests assert what the tool writes (report.json's
// fields, the PNGs) and that refusals are counted, never speeds.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <string>
#include <thread>

#include "loadtest_process.h"
#include "postgres_cluster.h"
#include "server_process.h"
#include "temp_dir.h"

namespace ricochet::test::loadtest_run_test {
namespace {

namespace fs = std::filesystem;

/// A TCP port on 127.0.0.1 that was free a moment ago.
std::uint16_t free_tcp_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t size = sizeof address;
  if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&address), size) != 0 ||
      getsockname(fd, reinterpret_cast<sockaddr*>(&address), &size) != 0) {
    throw std::runtime_error("cannot find a free port");
  }
  close(fd);
  return ntohs(address.sin_port);
}

TEST(LoadTest, BotsFillTheMatchesAndTheReportHasEveryFigure) {
  ServerProcess server("count = 2\nmax_players = 12\nmaps = [\"" RICOCHET_SOURCE_DIR
                       "/server/maps/foundry.toml\"]\nseed = 7\nwarmup_s = 0\nfrag_limit = 0\n"
                       "time_limit_s = 0\nrecord = false\n",
                       10, "[db]\npassword_hashing = \"minimum\"\n");
  ASSERT_TRUE(server.wait_listening()) << server.log();
  TempDir out("ricochet-loadtest");
  const int code = run_loadtest(
      "--server 127.0.0.1 --port " + std::to_string(server.control_port()) + " --admin-port " +
          std::to_string(server.admin_port()) + " --fingerprint " + server.fingerprint() +
          " --bots 24 --match-size 12 --ramp 40 --settle 2s --duration 4s --scrape-interval 0.5"
          " --out " +
          out.path().string(),
      out.path() / "loadtest.log");
  ASSERT_EQ(code, 0) << read_text(out.path() / "loadtest.log");

  const std::string report = read_text(out.path() / "report.json");
  ASSERT_FALSE(report.empty());
  EXPECT_EQ(number_field(report, "bots"), 24);
  EXPECT_EQ(number_field(report, "bots_connected"), 24) << report;
  EXPECT_EQ(number_field(report, "matches"), 2);
  const auto p99 = number_field(report, "server_tick_ms_p99");
  ASSERT_TRUE(p99);
  EXPECT_GT(*p99, 0);  // the server's own figure, read from /metrics
  EXPECT_LE(*p99, number_field(report, "server_tick_ms_max").value_or(0));
  EXPECT_TRUE(number_field(report, "overruns"));
  const auto loss = number_field(report, "snapshot_loss");
  ASSERT_TRUE(loss);
  EXPECT_GE(*loss, 0);
  EXPECT_LE(*loss, 1);
  EXPECT_GT(number_field(report, "rtt_ms_p99").value_or(0), 0);
  EXPECT_GT(number_field(report, "snapshots_per_s_per_bot").value_or(0), 0);  // not a speed
  EXPECT_GT(number_field(report, "kbps_in_per_client").value_or(0), 0);
  EXPECT_GT(number_field(report, "server_cpu_percent").value_or(0), 0);  // from /metrics
  EXPECT_GT(number_field(report, "server_rss_mb").value_or(0), 1);
  EXPECT_NE(report.find("\"server_cpu_source\":\"metrics\""), std::string::npos) << report;
  // --server-proc auto on loopback: /proc read besides, for the comparison.
  EXPECT_GT(number_field(report, "server_cpu_percent_proc").value_or(0), 0) << report;
  EXPECT_GT(number_field(report, "connect_ms_max").value_or(0), 0);
  EXPECT_NE(report.find("\"errors\":{"), std::string::npos);
  for (const char* png :
       {"tick_ms.png", "tick_p99_per_match.png", "overruns.png", "cpu_rss.png", "bandwidth.png",
        "rtt_loss.png", "errors.png", "connect_ms.png", "bots.png"}) {
    EXPECT_TRUE(fs::exists(out.path() / png) && fs::file_size(out.path() / png) > 1000) << png;
  }
}

/// Each server's object in report.json's last "servers" array (the top level's): label → the
/// object's text up to its phase_percent.
std::map<std::string, std::string> last_servers(const std::string& json) {
  const std::regex pattern(R"re(\{"server":"([^"]+)"[^{}]*)re");
  std::map<std::string, std::string> out;
  for (std::sregex_iterator it(json.begin(), json.end(), pattern), end; it != end; ++it) {
    out[(*it)[1].str()] = (*it)[0].str();
  }
  return out;
}

TEST(LoadTest, TwoGeneratorsAgainstTwoServersMergeIntoOneReport) {
  // Two servers, each on its own SQLite file, measured from /metrics only (--server-proc off:
  // as from a machine that cannot see their /proc), by two generator processes at once.
  const std::string matches = "count = 1\nmax_players = 16\nmaps = [\"" RICOCHET_SOURCE_DIR
                              "/server/maps/foundry.toml\"]\nseed = 7\nwarmup_s = 0\n"
                              "frag_limit = 0\ntime_limit_s = 0\nrecord = false\n";
  ServerProcess a(matches, 10, "[db]\npassword_hashing = \"minimum\"\n");
  ServerProcess b(matches, 10, "[db]\npassword_hashing = \"minimum\"\n");
  ASSERT_TRUE(a.wait_listening()) << a.log();
  ASSERT_TRUE(b.wait_listening()) << b.log();
  const auto endpoint = [](const ServerProcess& server) {
    return "127.0.0.1:" + std::to_string(server.control_port()) + ":" +
           std::to_string(server.admin_port());
  };
  const std::string common = " --server " + endpoint(a) + "," + endpoint(b) + " --fingerprint " +
                             a.fingerprint() + "," + b.fingerprint() +
                             " --server-proc off --bots 10 --bots-per-address 2 --match-size 16"
                             " --ramp 40 --settle 1s --duration 3s --scrape-interval 0.5"
                             " --no-plots --quiet";
  TempDir out("ricochet-loadtest");
  int codes[2] = {-1, -1};
  {
    std::thread second([&] {
      codes[1] = run_loadtest("--name gb --out " + (out.path() / "b").string() + common,
                              out.path() / "b.log");
    });
    codes[0] = run_loadtest("--name ga --out " + (out.path() / "a").string() + common,
                            out.path() / "a.log");
    second.join();
  }
  ASSERT_EQ(codes[0], 0) << read_text(out.path() / "a.log");
  ASSERT_EQ(codes[1], 0) << read_text(out.path() / "b.log");
  for (const char* generator : {"a", "b"}) {
    const std::string report = read_text(out.path() / generator / "report.json");
    EXPECT_EQ(number_field(report, "bots_connected"), 10) << report;
    EXPECT_EQ(report.find("server_cpu_percent_proc"), std::string::npos) << report;
    EXPECT_EQ(report.find("server_proc_unreadable"), std::string::npos) << report;
  }

  const fs::path merged = out.path() / "merged";
  ASSERT_EQ(run_loadtest("merge " + merged.string() + " " + (out.path() / "a").string() + " " +
                             (out.path() / "b").string(),
                         out.path() / "merge.log"),
            0)
      << read_text(out.path() / "merge.log");
  const std::string report = read_text(merged / "report.json");
  EXPECT_EQ(number_field(report, "bots"), 20) << report;
  EXPECT_EQ(number_field(report, "bots_connected"), 20) << report;
  // The top level's own fields, before its per-server ones (which have "matches" too).
  const std::string top = report.substr(report.rfind("\"bots\":"));
  EXPECT_EQ(number_field(top.substr(0, top.find("\"servers\":")), "matches"), 2)
      << report;  // one per server, counted once
  EXPECT_NE(report.find("\"server_cpu_source\":\"metrics\""), std::string::npos) << report;
  EXPECT_GT(number_field(report, "servers_cpu_percent_total").value_or(0), 0) << report;
  const auto servers = last_servers(report);
  ASSERT_EQ(servers.size(), 2u) << report;
  for (const ServerProcess* server : {&a, &b}) {
    const auto it = servers.find("127.0.0.1:" + std::to_string(server->control_port()));
    ASSERT_NE(it, servers.end()) << report;
    EXPECT_GT(number_field(it->second, "cpu_percent").value_or(0), 0) << it->second;  // /metrics
    EXPECT_EQ(number_field(it->second, "cpu_percent_proc"), -1) << it->second;        // not read
    EXPECT_GT(number_field(it->second, "rss_mb").value_or(0), 1) << it->second;
    EXPECT_EQ(number_field(it->second, "players"), 10) << it->second;
  }
  for (const char* png : {"servers_cpu.png", "generators.png", "rtt.png", "connect_ms.png"}) {
    EXPECT_TRUE(fs::exists(merged / png) && fs::file_size(merged / png) > 1000) << png;
  }
}

TEST(LoadTest, BotsPlacedThroughFindMatchAreReportedPerServerWithEachServersTickets) {
  // Three servers on one PostgreSQL, placement on: A hosts ffa only, B and C tdm only. The run
  // finds them in A's fleet directory (--fleet: A's GET /fleet, A first); every bot goes to A
  // and asks for tdm; A's tickets send them to B and C. Each server measured from its /metrics
  // only (--server-proc off), behind a bearer token. Both generators' first source address is
  // 127.0.1.1, so the seats per address are raised above their 10 bots there.
  const std::string url = PostgresCluster::shared().create_database();
  const auto matches = [](const std::string& mode) {
    return "count = 2\nmax_players = 8\nmode = \"" + mode +
           "\"\nmaps = [\"" RICOCHET_SOURCE_DIR
           "/server/maps/arena.toml\"]\nseed = 7\nwarmup_s = 0\nfrag_limit = 0\n"
           "time_limit_s = 0\nrecord = false\nmin_players = 1\nseats_per_address = 32\n";
  };
  TempDir secrets("ricochet-loadtest-token");
  const fs::path token = secrets.path() / "admin-token";
  std::ofstream(token) << "s3cret-loadtest-token\n";
  const std::string fleet = "[db]\nurl = \"" + url +
                            "\"\npassword_hashing = \"minimum\"\n"
                            "registrations_per_hour_per_address = 100\n"
                            "[placement]\nadvertise_host = \"127.0.0.1\"\nheartbeat_s = 1\n"
                            "server_ttl_s = 5\n";
  const std::string admin = "token_file = \"" + token.string() + "\"\n";
  ServerProcess a(matches("ffa"), 5, fleet, {}, admin);
  ServerProcess b(matches("tdm"), 5, fleet, {}, admin);
  ServerProcess c(matches("tdm"), 5, fleet, {}, admin);
  for (ServerProcess* server : {&a, &b, &c}) ASSERT_TRUE(server->wait_listening()) << server->log();
  // All three in the fleet directory before the run reads it from A (each writes its row once it
  // listens).
  for (ServerProcess* server : {&a, &b, &c}) {
    for (int i = 0; i < 200 && server->log().find("is in the fleet directory") == std::string::npos;
         ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(25));
    }
    ASSERT_NE(server->log().find("is in the fleet directory"), std::string::npos) << server->log();
  }
  const auto endpoint_label = [](const ServerProcess& server) {
    return "127.0.0.1:" + std::to_string(server.control_port());
  };
  const auto endpoint = [](const ServerProcess& server) {
    return "127.0.0.1:" + std::to_string(server.control_port()) + ":" +
           std::to_string(server.admin_port());
  };
  const std::string common =
      " --find-match tdm --server-proc off --match-size 8 --ramp 40"
      " --settle 3s --duration 1s --scrape-interval 0.5 --no-plots";
  TempDir out("ricochet-loadtest");
  int codes[2] = {-1, -1};
  {
    // The same run without the token (its servers listed: /fleet wants the token too), at the
    // same time: every scrape refused, the run finishes.
    std::thread untokened([&] {
      codes[1] = run_loadtest("--name nt --bots 2 --out " + (out.path() / "nt").string() +
                                  " --server " + endpoint(a) + "," + endpoint(b) + "," +
                                  endpoint(c) + " --fingerprint " + a.fingerprint() + common,
                              out.path() / "nt.log");
    });
    codes[0] = run_loadtest("--name pl --bots 16 --admin-token-file " + token.string() +
                                " --fleet 127.0.0.1:" + std::to_string(a.admin_port()) + " --out " +
                                (out.path() / "pl").string() + common,
                            out.path() / "pl.log");
    untokened.join();
  }
  ASSERT_EQ(codes[0], 0) << read_text(out.path() / "pl.log");
  ASSERT_EQ(codes[1], 0) << read_text(out.path() / "nt.log");
  // All three found in A's directory, A first, each with the admin port it advertises.
  const std::string found = "--fleet 127.0.0.1:" + std::to_string(a.admin_port()) +
                            ": 3 servers: " + endpoint_label(a) + " (admin " +
                            std::to_string(a.admin_port()) + ")";
  EXPECT_NE(read_text(out.path() / "pl.log").find(found), std::string::npos)
      << found << "\n"
      << read_text(out.path() / "pl.log");
  for (const ServerProcess* server : {&b, &c}) {
    EXPECT_NE(read_text(out.path() / "pl.log")
                  .find(" " + endpoint_label(*server) + " (admin " +
                        std::to_string(server->admin_port()) + ")"),
              std::string::npos)
        << read_text(out.path() / "pl.log");
  }

  const std::string report = read_text(out.path() / "pl" / "report.json");
  EXPECT_EQ(number_field(report, "bots_connected"), 16) << read_text(out.path() / "pl.log");
  EXPECT_EQ(report.find("metrics_unauthorized"), std::string::npos) << report;
  // The top level's bots_placed: on B and C only, 16 in all.
  const std::string top = report.substr(report.rfind("\"bots_placed\":"));
  const std::regex placed_on(R"re("127\.0\.0\.1:([0-9]+)":([0-9]+))re");
  std::map<std::uint16_t, int> placed;
  const std::string placed_object = top.substr(0, top.find('}'));
  for (std::sregex_iterator it(placed_object.begin(), placed_object.end(), placed_on), end;
       it != end; ++it) {
    placed[static_cast<std::uint16_t>(std::stoi((*it)[1].str()))] = std::stoi((*it)[2].str());
  }
  EXPECT_EQ(placed.count(a.control_port()), 0u) << placed_object;
  EXPECT_GT(placed[b.control_port()], 0) << placed_object;
  EXPECT_GT(placed[c.control_port()], 0) << placed_object;
  EXPECT_EQ(placed[b.control_port()] + placed[c.control_port()], 16) << placed_object;
  EXPECT_GT(number_field(report, "placement_ms_p50").value_or(0), 0) << report;
  EXPECT_GE(number_field(report, "placement_ms_max").value_or(0),
            number_field(report, "placement_ms_p99").value_or(1))
      << report;
  // Every server scraped with the token: its CPU from /metrics; A answered the find_matches.
  const auto servers = last_servers(report);
  for (const ServerProcess* server : {&a, &b, &c}) {
    const auto it = servers.find("127.0.0.1:" + std::to_string(server->control_port()));
    ASSERT_NE(it, servers.end()) << report;
    EXPECT_GT(number_field(it->second, "cpu_percent").value_or(0), 0) << it->second;
  }
  const std::string a_label = "\"server\":\"127.0.0.1:" + std::to_string(a.control_port()) + "\"";
  const std::string a_object = report.substr(report.rfind(a_label));
  std::smatch assigned;
  std::regex_search(a_object, assigned,
                    std::regex(R"re("placement_tickets":\{[^}]*"assigned":([0-9]+))re"));
  ASSERT_FALSE(assigned.empty()) << a_object;
  EXPECT_GE(std::stoi(assigned[1].str()), 16) << a_object;

  std::cout
      << "loadtest placement run: 16 bots through A: " << placed[b.control_port()] << " on B, "
      << placed[c.control_port()] << " on C; placement_ms p50 "
      << number_field(report, "placement_ms_p50").value_or(0) << " p99 "
      << number_field(report, "placement_ms_p99").value_or(0) << " max "
      << number_field(report, "placement_ms_max").value_or(0) << "; A's tickets assigned "
      << assigned[1].str() << " (both generators); servers' CPU from /metrics A "
      << number_field(servers.at(endpoint(a).substr(0, endpoint(a).rfind(':'))), "cpu_percent")
             .value_or(-1)
      << " % B "
      << number_field(servers.at(endpoint(b).substr(0, endpoint(b).rfind(':'))), "cpu_percent")
             .value_or(-1)
      << " % C "
      << number_field(servers.at(endpoint(c).substr(0, endpoint(c).rfind(':'))), "cpu_percent")
             .value_or(-1)
      << " %\n";

  // Without the token: counted, named in the progress line, never fatal.
  const std::string refused = read_text(out.path() / "nt" / "report.json");
  EXPECT_GT(number_field(refused, "metrics_unauthorized").value_or(0), 0) << refused;
  EXPECT_NE(read_text(out.path() / "nt.log").find("metrics_unauthorized"), std::string::npos);
}

TEST(LoadTest, ANoServerIsCountedNotACrash) {
  // Nothing listens on these ports (the kernel's choice, released again).
  const std::string control = std::to_string(free_tcp_port());
  const std::string admin = std::to_string(free_tcp_port());
  TempDir out("ricochet-loadtest");
  const int code = run_loadtest("--port " + control + " --admin-port " + admin +
                                    " --bots 3 --ramp 10 --settle 0s --duration 2s --no-plots"
                                    " --out " +
                                    out.path().string(),
                                out.path() / "loadtest.log");
  ASSERT_EQ(code, 0) << read_text(out.path() / "loadtest.log");
  const std::string report = read_text(out.path() / "report.json");
  EXPECT_EQ(number_field(report, "bots_connected"), 0);
  EXPECT_NE(report.find("\"connect_failed\":"), std::string::npos) << report;
  EXPECT_NE(report.find("\"metrics_unavailable\":"), std::string::npos) << report;
}

TEST(LoadTest, BadOptionsAreRefusedWithTheReason) {
  TempDir out("ricochet-loadtest");
  const fs::path log = out.path() / "loadtest.log";
  EXPECT_EQ(run_loadtest("--server 127.0.0.1:7777,localhost --out " + out.path().string(), log), 2);
  EXPECT_NE(read_text(log).find("--server: server 2 (\"localhost\"): expected a numeric IPv4"),
            std::string::npos)
      << read_text(log);
  EXPECT_EQ(run_loadtest("--server 127.0.0.1:7777,127.0.0.1:7787 --fingerprint A,B,C --out " +
                             out.path().string(),
                         log),
            2);
  EXPECT_NE(read_text(log).find("one per server (2), got 3"), std::string::npos) << read_text(log);
  EXPECT_EQ(
      run_loadtest("--fleet 127.0.0.1:9100 --server 127.0.0.1 --out " + out.path().string(), log),
      2);
  EXPECT_NE(read_text(log).find("drop --server and --fingerprint, or --fleet"), std::string::npos)
      << read_text(log);
  EXPECT_EQ(run_loadtest("--fleet localhost:9100 --out " + out.path().string(), log), 2);
  EXPECT_NE(read_text(log).find("--fleet: expected HOST:ADMIN_PORT with a numeric IPv4 HOST"),
            std::string::npos)
      << read_text(log);
  const std::string nobody = "127.0.0.1:" + std::to_string(free_tcp_port());
  EXPECT_EQ(run_loadtest("--fleet " + nobody + " --out " + out.path().string(), log), 2);
  EXPECT_NE(read_text(log).find("--fleet " + nobody + ": cannot connect"), std::string::npos)
      << read_text(log);
  EXPECT_EQ(run_loadtest("--server-proc on --out " + out.path().string(), log), 2);
  EXPECT_NE(read_text(log).find("--server-proc must be off or auto"), std::string::npos)
      << read_text(log);
  EXPECT_EQ(run_loadtest("--sweep 100,50 --out " + out.path().string(), log), 2);
  EXPECT_NE(read_text(log).find("increasing"), std::string::npos) << read_text(log);
  EXPECT_EQ(run_loadtest("--find-match TDM --out " + out.path().string(), log), 2);
  EXPECT_NE(read_text(log).find("find_match must be MODE or MODE:MAP"), std::string::npos)
      << read_text(log);
  EXPECT_EQ(run_loadtest("--soak --find-match tdm --out " + out.path().string(), log), 2);
  EXPECT_NE(read_text(log).find("--soak keeps its bots on one server"), std::string::npos)
      << read_text(log);
  const fs::path empty_token = out.path() / "empty-token";
  std::ofstream(empty_token) << "\n";
  EXPECT_EQ(
      run_loadtest("--admin-token-file " + empty_token.string() + " --out " + out.path().string(),
                   log),
      2);
  EXPECT_NE(read_text(log).find("--admin-token-file: the admin token file " + empty_token.string() +
                                " is empty"),
            std::string::npos)
      << read_text(log);
  EXPECT_EQ(run_loadtest("--server 127.0.0.1:7777,127.0.0.1:7787 --admin-token-file A,B,C --out " +
                             out.path().string(),
                         log),
            2);
  EXPECT_NE(read_text(log).find("--admin-token-file: one for every server or one per server (2), "
                                "got 3"),
            std::string::npos)
      << read_text(log);
  EXPECT_EQ(run_loadtest("--duration 1h --out " + out.path().string(), log), 2);
  EXPECT_NE(read_text(log).find("--duration"), std::string::npos) << read_text(log);
}

}  // namespace
}  // namespace ricochet::test::loadtest_run_test
