#include "ricochet/proto/chat_text.h"

#include <array>
#include <cstdio>

namespace ricochet::proto {

namespace {

struct Range {
  std::uint32_t first;
  std::uint32_t last;
};

// clang-format off
/// Unicode 15.1's category Cf (DerivedGeneralCategory.txt), less U+200C and U+200D.
constexpr std::array<Range, 21> kRefusedFormat = {{
    {0x00AD, 0x00AD},    // soft hyphen
    {0x0600, 0x0605},    // Arabic number signs
    {0x061C, 0x061C},    // Arabic letter mark (bidi)
    {0x06DD, 0x06DD},
    {0x070F, 0x070F},
    {0x0890, 0x0891},
    {0x08E2, 0x08E2},
    {0x180E, 0x180E},    // Mongolian vowel separator
    {0x200B, 0x200B},    // zero-width space
    {0x200E, 0x200F},    // left-to-right and right-to-left marks
    {0x202A, 0x202E},    // bidi embeddings and overrides
    {0x2060, 0x2064},    // word joiner, invisible operators
    {0x2066, 0x206F},    // bidi isolates, deprecated format characters
    {0xFEFF, 0xFEFF},    // byte order mark, zero-width no-break space
    {0xFFF9, 0xFFFB},    // interlinear annotation
    {0x110BD, 0x110BD},
    {0x110CD, 0x110CD},
    {0x13430, 0x1343F},  // Egyptian hieroglyph format controls
    {0x1BCA0, 0x1BCA3},  // shorthand format controls
    {0x1D173, 0x1D17A},  // musical symbol format controls
    {0xE0001, 0xE007F},  // language tag and tag characters
}};
// clang-format on

std::string code_point(std::uint32_t code) {
  char text[16];
  std::snprintf(text, sizeof text, "U+%04X", static_cast<unsigned>(code));
  return text;
}

/// The code point at `text[at]` and its length in bytes; length 0 when not well-formed.
std::uint32_t decode(std::string_view text, std::size_t at, std::size_t& length) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[at + k]); };
  const unsigned char lead = byte(0);
  std::uint32_t code = 0;
  length = 0;
  std::size_t size = 0;
  if (lead < 0x80) {
    size = 1;
    code = lead;
  } else if (lead >= 0xC2 && lead <= 0xDF) {
    size = 2;
    code = lead & 0x1Fu;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    size = 3;
    code = lead & 0x0Fu;
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    size = 4;
    code = lead & 0x07u;
  } else {
    return 0;
  }
  if (at + size > text.size()) return 0;
  for (std::size_t k = 1; k < size; ++k) {
    if ((byte(k) & 0xC0u) != 0x80u) return 0;
    code = (code << 6) | (byte(k) & 0x3Fu);
  }
  constexpr std::uint32_t kSmallest[] = {0, 0, 0x80, 0x800, 0x10000};
  if (code < kSmallest[size] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  length = size;
  return code;
}

}  // namespace

std::string_view name(ChatTextProblem problem) {
  switch (problem) {
    case ChatTextProblem::Empty:
      return "empty";
    case ChatTextProblem::TooLong:
      return "too_long";
    case ChatTextProblem::NotUtf8:
      return "not_utf8";
    case ChatTextProblem::Control:
      return "control_character";
    case ChatTextProblem::FormatControl:
      return "format_character";
  }
  return "unknown";
}

bool is_refused_format_character(std::uint32_t code) {
  for (const Range& range : kRefusedFormat) {
    if (code < range.first) return false;  // sorted
    if (code <= range.last) return true;
  }
  return false;
}

std::optional<ChatTextRefusal> check_chat_text(std::string_view text) {
  if (text.empty() || text.size() > kMaxChatBytes) {
    return ChatTextRefusal{text.empty() ? ChatTextProblem::Empty : ChatTextProblem::TooLong,
                           "chat text must be 1.." + std::to_string(kMaxChatBytes) +
                               " bytes, got " + std::to_string(text.size())};
  }
  std::size_t at = 0;
  while (at < text.size()) {
    std::size_t length = 0;
    const std::uint32_t code = decode(text, at, length);
    const std::string where = " at byte " + std::to_string(at);
    if (length == 0) {
      return ChatTextRefusal{ChatTextProblem::NotUtf8,
                             "chat text must be UTF-8, got a malformed sequence" + where};
    }
    if (code < 0x20 || (code >= 0x7F && code < 0xA0) || code == 0x2028 || code == 0x2029) {
      return ChatTextRefusal{
          ChatTextProblem::Control,
          "chat text must not hold control characters, got " + code_point(code) + where};
    }
    if (is_refused_format_character(code)) {
      return ChatTextRefusal{ChatTextProblem::FormatControl,
                             "chat text must not hold invisible format characters (bidi "
                             "overrides and the like), got " +
                                 code_point(code) + where};
    }
    at += length;
  }
  return std::nullopt;
}

}  // namespace ricochet::proto
