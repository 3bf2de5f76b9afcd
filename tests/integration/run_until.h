#pragma once
/// The end-to-end tests' one bounded wait: runs the bots' event loop until a condition holds.

#include <boost/asio/io_context.hpp>
#include <chrono>

namespace ricochet::test {

/// Runs `io` until `done()` holds or `limit` passes; whether it holds.
template <class Done>
bool run_until(boost::asio::io_context& io, Done done, std::chrono::milliseconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  while (!done()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    io.run_for(std::chrono::milliseconds(20));
    if (io.stopped()) io.restart();
  }
  return true;
}

}  // namespace ricochet::test
