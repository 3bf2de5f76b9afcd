// ricochet-loadtest end to end: the real ricochet-server binary on 127.0.0.1 (free ports, a
// temporary data directory), the real ricochet-loadtest binary against it. The tests assert what
// the tool writes (report.json's fields, the PNGs) and that refusals are counted, never speeds.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "loadtest_process.h"
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
  EXPECT_EQ(run_loadtest("--server-proc on --out " + out.path().string(), log), 2);
  EXPECT_NE(read_text(log).find("--server-proc must be off or auto"), std::string::npos)
      << read_text(log);
  EXPECT_EQ(run_loadtest("--sweep 100,50 --out " + out.path().string(), log), 2);
  EXPECT_NE(read_text(log).find("increasing"), std::string::npos) << read_text(log);
  EXPECT_EQ(run_loadtest("--duration 1h --out " + out.path().string(), log), 2);
  EXPECT_NE(read_text(log).find("--duration"), std::string::npos) << read_text(log);
}

}  // namespace
}  // namespace ricochet::test::loadtest_run_test
