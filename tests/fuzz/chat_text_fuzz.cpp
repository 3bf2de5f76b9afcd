// libFuzzer target for the chat text rule (proto/src/chat_text.cpp), which every chat line a
// client sends goes through: any bytes are refused or accepted without a crash, and what is
// accepted holds what the rule promises, checked here by a decoder of its own (std::mbrtowc
// would depend on the locale).
// Run it with tools/fuzz.sh --only chat_text.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "ricochet/proto/chat_text.h"

namespace {

using namespace ricochet::proto;

/// Decodes well-formed UTF-8 the plain way (the rule refused everything else).
std::uint32_t next_code_point(std::string_view text, std::size_t& at) {
  const auto lead = static_cast<unsigned char>(text[at]);
  const std::size_t size = lead < 0x80 ? 1 : lead < 0xE0 ? 2 : lead < 0xF0 ? 3 : 4;
  std::uint32_t code = size == 1 ? lead : lead & (0x7Fu >> size);
  for (std::size_t k = 1; k < size; ++k) {
    code = (code << 6) | (static_cast<unsigned char>(text[at + k]) & 0x3Fu);
  }
  at += size;
  return code;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto refusal = check_chat_text(text);
  if (refusal) {
    if (refusal->message.empty()) std::abort();
    return 0;
  }
  if (text.empty() || text.size() > kMaxChatBytes) std::abort();
  for (std::size_t at = 0; at < text.size();) {
    const std::uint32_t code = next_code_point(text, at);
    if (at > text.size()) std::abort();  // a sequence ran past the end
    if (code < 0x20 || (code >= 0x7F && code < 0xA0) || code == 0x2028 || code == 0x2029) {
      std::abort();
    }
    if (code == 0x202E || code == 0x2066 || code == 0xFEFF || is_refused_format_character(code)) {
      std::abort();
    }
  }
  return 0;
}
