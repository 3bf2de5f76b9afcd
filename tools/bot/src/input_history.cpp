#include "ricochet/bot/input_history.h"

namespace ricochet::bot {

const wire::Input& InputHistory::push(wire::Input input) {
  input.set_sequence(next_sequence_++);
  recent_.push_back(input);
  if (recent_.size() > kPerPayload) recent_.pop_front();
  kept_.push_back(std::move(input));
  if (kept_.size() > kMaxKept) kept_.pop_front();
  return kept_.back();
}

bool InputHistory::acknowledge(std::uint32_t sequence) {
  if (sequence >= next_sequence_) return false;
  if (sequence <= acknowledged_) return true;
  acknowledged_ = sequence;
  while (!kept_.empty() && kept_.front().sequence() <= sequence) kept_.pop_front();
  return true;
}

void InputHistory::fill(wire::ClientPayload& out) const {
  out.clear_inputs();
  for (const wire::Input& input : recent_) *out.add_inputs() = input;
}

}  // namespace ricochet::bot
