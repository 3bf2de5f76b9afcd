#include "signals.h"

#include <gtest/gtest.h>

#include <boost/asio/steady_timer.hpp>
#include <chrono>
#include <csignal>

namespace ricochet::server::signals_test {
namespace {

using namespace std::chrono_literals;

TEST(ShutdownSignals, FirstSignalAsksForAGracefulStop) {
  boost::asio::io_context io;
  int stopped_by = 0;
  ShutdownSignals signals{io, 10s, [&](int signal) {
                            stopped_by = signal;
                            signals.close();  // the graceful stop is done at once here
                          }};
  std::raise(SIGTERM);
  io.run_for(5s);  // returns early: closing leaves no work
  EXPECT_EQ(stopped_by, SIGTERM);
  EXPECT_TRUE(io.stopped());
}

TEST(ShutdownSignals, CloseLetsTheIoContextRunOut) {
  boost::asio::io_context io;
  bool called = false;
  ShutdownSignals signals{io, 10s, [&](int) { called = true; }};
  signals.close();
  io.run_for(5s);
  EXPECT_TRUE(io.stopped());
  EXPECT_FALSE(called);
}

/// Raises `signal` once, then (when `again`) again from the graceful stop; runs the io_context
/// for at most 5 s and exits 0 if nothing ended the process first.
[[noreturn]] void signal_and_run(int signal, bool again, std::chrono::milliseconds grace) {
  boost::asio::io_context io;
  ShutdownSignals signals{io, grace, [&](int) {
                            if (again) std::raise(signal);
                          }};
  std::raise(signal);
  io.run_for(5s);
  std::exit(0);
}

TEST(ShutdownSignalsDeathTest, SecondSignalExitsAtOnce) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(signal_and_run(SIGINT, true, 10s), ::testing::ExitedWithCode(128 + SIGINT), "");
  EXPECT_EXIT(signal_and_run(SIGTERM, true, 10s), ::testing::ExitedWithCode(128 + SIGTERM), "");
}

TEST(ShutdownSignalsDeathTest, GracePeriodRunningOutExitsWithOne) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(signal_and_run(SIGTERM, false, 100ms), ::testing::ExitedWithCode(1), "");
}

}  // namespace
}  // namespace ricochet::server::signals_test
