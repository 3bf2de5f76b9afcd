// ricochet-server: parses the configuration (TOML file + flags), sets up logging, runs the
// Server until SIGINT/SIGTERM, and exits 0 after a graceful stop within the grace period.
#include <google/protobuf/stubs/logging.h>
#include <spdlog/spdlog.h>

#include <boost/asio/io_context.hpp>
#include <chrono>
#include <cstdio>
#include <exception>

#include "logging.h"
#include "server.h"
#include "signals.h"

int main(int argc, char** argv) {
  using namespace ricochet::server;
  ParseOutcome outcome = parse_command_line(argc, argv);
  if (!outcome.config) {
    std::fputs(outcome.text.c_str(), outcome.exit_code == 0 ? stdout : stderr);
    return outcome.exit_code;
  }
  const ServerConfig& config = *outcome.config;
  setup_logging(config.log.level, config.log.format);
  // protobuf complains on stderr about untrusted bytes it parses (invalid UTF-8 in a string
  // field); those go through our log, at debug, so a client cannot fill the operator's terminal.
  google::protobuf::SetLogHandler(
      [](google::protobuf::LogLevel, const char*, int, const std::string& message) {
        spdlog::debug("protobuf: {}", message);
      });
  try {
    Server server(config);
    server.start();
    // Signals get their own small io_context, so a stuck match cannot delay a second signal.
    boost::asio::io_context signal_io;
    // The backstop fires 2 s after the server's own deadline, so a stop that uses its whole
    // grace still ends through the server's path (threads joined, DB closed).
    ShutdownSignals signals(signal_io, std::chrono::seconds(config.server.shutdown_grace_s + 2),
                            [&server](int) { server.stop(); });
    std::thread signal_thread([&signal_io] { signal_io.run(); });
    const int code = server.wait();
    signals.close();
    signal_thread.join();
    return code;
  } catch (const std::exception& error) {
    spdlog::critical("{}", error.what());
    return 1;
  }
}
