#pragma once
/// SIGINT and SIGTERM for the server: the first one asks for a graceful stop (stop accepting,
/// tell clients, end matches, flush results); a second one, or the grace period running out,
/// ends the process at once with std::_Exit (no destructors, no flushing beyond the log).
///
/// Exit statuses: 128 + the signal number for a second signal (130 for SIGINT, 143 for SIGTERM),
/// 1 when the grace period runs out. A clean graceful stop is the caller's exit (0).

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <functional>
#include <memory>

namespace ricochet::server {

class ShutdownSignals {
 public:
  /// Starts listening for SIGINT and SIGTERM on `io`. On the first, `graceful_stop(signal)` runs
  /// on the io_context and a deadline of `grace` is armed.
  ShutdownSignals(boost::asio::io_context& io, std::chrono::milliseconds grace,
                  std::function<void(int signal)> graceful_stop);
  /// close().
  ~ShutdownSignals();
  ShutdownSignals(const ShutdownSignals&) = delete;
  ShutdownSignals& operator=(const ShutdownSignals&) = delete;

  /// Stops listening and disarms the deadline, so io_context::run() can run out of work. Call
  /// when the graceful stop is done (a signal after that gets the default action: the process
  /// ends). Thread-safe; idempotent.
  void close();

  struct State;

 private:
  std::shared_ptr<State> state_;
};

}  // namespace ricochet::server
