#include "ricochet/bot/state_dump.h"

namespace ricochet::bot {

std::unique_ptr<StateDump> StateDump::create(const std::string& path, std::string& error) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (file == nullptr || std::fputs("tick,entity,x,y,z\n", file) < 0) {
    if (file != nullptr) std::fclose(file);
    error = "cannot write the states file " + path;
    return nullptr;
  }
  return std::unique_ptr<StateDump>(new StateDump(file));
}

StateDump::~StateDump() {
  std::fclose(file_);
}

void StateDump::write(const WorldView& view) {
  for (const SeenEntity& entity : view.entities()) {
    if (entity.kind() != proto::EntityKind::Player) continue;
    std::fprintf(file_, "%u,%u,%.9g,%.9g,%.9g\n", view.tick(), entity.id, entity.position_m[0],
                 entity.position_m[1], entity.position_m[2]);
  }
}

}  // namespace ricochet::bot
