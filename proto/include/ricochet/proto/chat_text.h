#pragma once
/// What a chat line may hold (PROTOCOL.md Control channel §chat text): one rule for the control
/// channel, which answers a refused line with an Error, and for the match, which broadcasts the
/// lines it is given to its players.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace ricochet::proto {

/// Longest chat text, in bytes of UTF-8.
inline constexpr std::size_t kMaxChatBytes = 200;

/// Why a chat text is refused.
enum class ChatTextProblem : std::uint8_t {
  Empty,
  TooLong,        ///< more than kMaxChatBytes
  NotUtf8,        ///< not well-formed UTF-8 (overlong, surrogate, truncated, over U+10FFFF)
  Control,        ///< a C0 or C1 control (tab, newline, escape ...), or U+2028 / U+2029
  FormatControl,  ///< an invisible format character, Unicode category Cf (bidi overrides ...)
};
inline constexpr std::size_t kChatTextProblemCount =
    static_cast<std::size_t>(ChatTextProblem::FormatControl) + 1;
std::string_view name(ChatTextProblem problem);

struct ChatTextRefusal {
  ChatTextProblem problem = ChatTextProblem::Empty;
  std::string message;  ///< for the sender: what was expected and what came
};

/// The first problem of `text`, or nothing when it is a chat line a client may send. Refused,
/// never stripped: what the sender typed reaches everyone as typed, or not at all.
std::optional<ChatTextRefusal> check_chat_text(std::string_view text);

/// True when `code` is of Unicode category Cf (format) and is refused in chat: all of Cf but
/// U+200C and U+200D (zero-width non-joiner and joiner), which Persian and Indic text and emoji
/// sequences need and which reorder and hide nothing.
bool is_refused_format_character(std::uint32_t code);

}  // namespace ricochet::proto
