#pragma once
/// What a bot decoded, written down for a test to compare (`ricochet-bot --dump-states FILE`):
/// for every snapshot it accepted, each player of it (not projectiles) as a CSV line
/// `tick,entity,x,y,z`, the dequantised position in metres, the format and precision of
/// `ricochet-replay --export`. The Java client's tests compare it with what that client decoded
/// at the same ticks (tests/clients/java: a Java client and a ricochet-bot see each other
/// identically).

#include <cstdio>
#include <memory>
#include <string>

#include "ricochet/bot/world_view.h"

namespace ricochet::bot {

class StateDump {
 public:
  /// The file created (truncated) with its header line; nullptr, with `error` set, when it
  /// cannot be.
  static std::unique_ptr<StateDump> create(const std::string& path, std::string& error);
  ~StateDump();
  StateDump(const StateDump&) = delete;
  StateDump& operator=(const StateDump&) = delete;

  /// The players of the newest decoded snapshot, as `view` holds it (before any rendering).
  void write(const WorldView& view);

 private:
  explicit StateDump(std::FILE* file) : file_(file) {}
  std::FILE* file_;
};

}  // namespace ricochet::bot
