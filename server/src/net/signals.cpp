#include "signals.h"

#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/strand.hpp>
#include <csignal>
#include <cstdlib>

namespace ricochet::server {

namespace asio = boost::asio;

struct ShutdownSignals::State {
  State(asio::io_context& io, std::chrono::milliseconds grace_in,
        std::function<void(int)> graceful_stop_in)
      : strand(asio::make_strand(io)),
        signals(strand, SIGINT, SIGTERM),
        deadline(strand),
        grace(grace_in),
        graceful_stop(std::move(graceful_stop_in)) {}

  asio::strand<asio::io_context::executor_type> strand;
  asio::signal_set signals;  ///< on the strand only
  asio::steady_timer deadline;
  const std::chrono::milliseconds grace;
  const std::function<void(int)> graceful_stop;
  bool stopping = false;  ///< a first signal came; on the strand only
  bool closed = false;    ///< on the strand only
};

namespace {

using State = ShutdownSignals::State;

const char* signal_name(int signal) {
  switch (signal) {
    case SIGINT:
      return "SIGINT";
    case SIGTERM:
      return "SIGTERM";
  }
  return "a signal";
}

[[noreturn]] void exit_now(int status) {
  spdlog::default_logger()->flush();
  std::_Exit(status);
}

void wait_for_signal(const std::shared_ptr<State>& state) {
  state->signals.async_wait([state](const boost::system::error_code& error, int signal) {
    if (error || state->closed) return;  // closed
    if (state->stopping) {
      spdlog::critical("{} again during the graceful stop: exiting now", signal_name(signal));
      exit_now(128 + signal);
    }
    state->stopping = true;
    spdlog::info("{}: stopping gracefully within {} ms (send it again to exit now)",
                 signal_name(signal), state->grace.count());
    state->deadline.expires_after(state->grace);
    state->deadline.async_wait([state](const boost::system::error_code& timer_error) {
      if (timer_error || state->closed) return;
      spdlog::critical("graceful stop did not finish within {} ms: exiting now",
                       state->grace.count());
      exit_now(1);
    });
    wait_for_signal(state);
    state->graceful_stop(signal);
  });
}

}  // namespace

ShutdownSignals::ShutdownSignals(asio::io_context& io, std::chrono::milliseconds grace,
                                 std::function<void(int signal)> graceful_stop)
    : state_(std::make_shared<State>(io, grace, std::move(graceful_stop))) {
  asio::post(state_->strand, [state = state_] { wait_for_signal(state); });
}

ShutdownSignals::~ShutdownSignals() {
  close();
}

void ShutdownSignals::close() {
  asio::post(state_->strand, [state = state_] {
    if (state->closed) return;
    state->closed = true;
    boost::system::error_code ignored;
    state->signals.cancel(ignored);
    state->signals.clear(ignored);
    state->deadline.cancel();
  });
}

}  // namespace ricochet::server
