#pragma once
/// The I/O around AgonesSdk (agones_sdk.h, where the paths, bodies and rules are): an HTTP/1.1
/// client (Boost.Beast) of the Agones SDK sidecar's REST gateway on
/// 127.0.0.1:${AGONES_SDK_HTTP_PORT}, one connection per call, each call bounded by
/// call_timeout. It runs on its own thread and io_context, so it outlives the server's threads
/// through the graceful stop (POST /shutdown is its last step) and a stuck match cannot delay it
/// (a stuck match withholds the pings: AgonesSdk reads the ticks from `matches`).
///
///   AgonesHttp agones(options);  // its thread; sends nothing yet
///   agones.ready();              // POST /ready, then pings and labels
///   agones.stopping(); ... agones.drained(limit);  // the graceful stop, then POST /shutdown
///
/// /metrics: ricochet_agones_calls_total{call, outcome} and
/// ricochet_agones_health_withheld_total.

#include <array>
#include <boost/asio/awaitable.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <thread>
#include <utility>
#include <vector>

#include "agones_sdk.h"
#include "ricochet/server/metrics.h"

namespace ricochet::server {

/// The value of AGONES_SDK_HTTP_PORT as a port (1..65535); throws std::runtime_error saying what
/// came and what is expected.
std::uint16_t parse_agones_sdk_port(std::string_view text);

struct AgonesHttpOptions {
  std::uint16_t port = 0;  ///< the sidecar's REST port on 127.0.0.1
  AgonesSdkConfig sdk;
  /// The matches now; called on the client's thread, so it must be thread-safe.
  std::function<std::vector<AgonesMatchView>()> matches;
  /// An HTTP call's limit, from connecting to the last byte of the answer.
  std::chrono::milliseconds call_timeout{2000};
  /// How often the matches are read when nothing else is due.
  std::chrono::milliseconds poll_interval{250};
  /// When set, GET /gameserver once Ready, and this gets its answer's body on the client's
  /// thread (nothing: the sidecar refused the call).
  std::function<void(std::optional<std::string> body)> game_server;
};

class AgonesHttp {
 public:
  /// Registers its metrics in `metrics` (which must outlive it) and starts its thread.
  AgonesHttp(AgonesHttpOptions options, MetricsRegistry& metrics);
  /// Stops the thread; a call in flight is abandoned.
  ~AgonesHttp();
  AgonesHttp(const AgonesHttp&) = delete;
  AgonesHttp& operator=(const AgonesHttp&) = delete;

  // Thread-safe; each posts to the client's thread (AgonesSdk's events).
  void ready();
  /// A ticket seated a player here (POST /allocate on the first).
  void players_placed();
  void match_finished();
  void stopping();
  /// POST /shutdown, and waits until it is answered or `limit` passes; whether it was.
  bool drained(std::chrono::milliseconds limit);

 private:
  boost::asio::awaitable<void> run();
  /// One call; its outcome and the answer's body.
  boost::asio::awaitable<std::pair<AgonesOutcome, std::string>> perform(
      const AgonesRequest& request);
  /// Runs `event` on the client's thread and looks for a call at once.
  void post_event(std::function<void(AgonesSdk&, proto::TimeUs now)> event);
  void publish_counters();

  boost::asio::io_context io_;  ///< first: destroyed last, after what its handlers reference
  AgonesHttpOptions options_;
  AgonesSdk sdk_;  ///< on the client's thread only
  boost::asio::steady_timer wake_{io_};
  std::array<std::array<Counter*, kAgonesOutcomeCount>, kAgonesCallCount> calls_{};
  Counter* health_withheld_ = nullptr;
  std::uint64_t withheld_published_ = 0;
  std::mutex finished_mutex_;
  std::condition_variable finished_changed_;
  bool finished_ = false;  ///< POST /shutdown answered; guarded by finished_mutex_
  std::thread thread_;     ///< last: starts once everything above is made
};

}  // namespace ricochet::server
