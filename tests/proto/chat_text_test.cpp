#include "ricochet/proto/chat_text.h"

#include <gtest/gtest.h>

#include <string>

namespace ricochet::proto::chat_text_test {
namespace {

std::optional<ChatTextProblem> problem_of(std::string_view text) {
  const auto refusal = check_chat_text(text);
  if (!refusal) return std::nullopt;
  return refusal->problem;
}

TEST(ChatText, OneLengthLimitInBytes) {
  EXPECT_EQ(problem_of(""), ChatTextProblem::Empty);
  EXPECT_EQ(problem_of(std::string(kMaxChatBytes, 'a')), std::nullopt);
  const auto refusal = check_chat_text(std::string(kMaxChatBytes + 1, 'a'));
  ASSERT_TRUE(refusal);
  EXPECT_EQ(refusal->problem, ChatTextProblem::TooLong);
  EXPECT_EQ(refusal->message, "chat text must be 1..200 bytes, got 201");
}

TEST(ChatText, PrintableUtf8PassesWithJoinersForScriptsAndEmoji) {
  EXPECT_EQ(problem_of("gl hf \xC3\xA9 \xE4\xBD\xA0\xE5\xA5\xBD"), std::nullopt);
  EXPECT_EQ(problem_of("\xD9\x85\xDB\x8C\xE2\x80\x8C\xD8\xAE\xD9\x88\xD8\xA7\xD9\x85"),
            std::nullopt);  // Persian with a zero-width non-joiner (U+200C)
  EXPECT_EQ(problem_of("\xF0\x9F\x91\xA8\xE2\x80\x8D\xF0\x9F\x91\xA9"),
            std::nullopt);  // an emoji sequence with a zero-width joiner (U+200D)
  EXPECT_EQ(problem_of("\xD7\xA9\xD7\x9C\xD7\x95\xD7\x9D"), std::nullopt);  // Hebrew: RTL text
}

TEST(ChatText, ControlCharactersAreRefused) {
  for (const char* text : {"bell\a", "tab\there", "new\nline", "esc\x1b[31m", "del\x7f"}) {
    EXPECT_EQ(problem_of(text), ChatTextProblem::Control) << text;
  }
  EXPECT_EQ(problem_of("c1 \xC2\x9B"), ChatTextProblem::Control);      // U+009B CSI
  EXPECT_EQ(problem_of("ls \xE2\x80\xA8"), ChatTextProblem::Control);  // U+2028
  EXPECT_EQ(problem_of("ps \xE2\x80\xA9"), ChatTextProblem::Control);  // U+2029
}

TEST(ChatText, BidiAndOtherFormatCharactersAreRefusedNamingThem) {
  const auto refusal = check_chat_text(
      "gg \xE2\x80\xAE"
      "olleh");  // U+202E RIGHT-TO-LEFT OVERRIDE
  ASSERT_TRUE(refusal);
  EXPECT_EQ(refusal->problem, ChatTextProblem::FormatControl);
  EXPECT_NE(refusal->message.find("U+202E at byte 3"), std::string::npos) << refusal->message;
  for (const std::uint32_t code :
       {0x00ADu, 0x061Cu, 0x200Bu, 0x200Eu, 0x200Fu, 0x202Au, 0x202Eu, 0x2066u, 0x2067u, 0x2068u,
        0x2069u, 0x206Fu, 0xFEFFu, 0xFFFBu, 0x1D173u, 0xE0001u, 0xE007Fu}) {
    EXPECT_TRUE(is_refused_format_character(code)) << std::hex << code;
  }
  for (const std::uint32_t code :
       {0x41u, 0xE9u, 0x200Cu, 0x200Du, 0x2065u, 0x2070u, 0xFFFCu, 0x1F600u, 0xE0080u}) {
    EXPECT_FALSE(is_refused_format_character(code)) << std::hex << code;
  }
  EXPECT_EQ(problem_of("\xEF\xBB\xBFhi"), ChatTextProblem::FormatControl);  // U+FEFF
  EXPECT_EQ(problem_of("a\xE2\x81\xA6"
                       "b"),
            ChatTextProblem::FormatControl);                                     // U+2066
  EXPECT_EQ(problem_of("\xF3\xA0\x80\x81tag"), ChatTextProblem::FormatControl);  // U+E0001
}

TEST(ChatText, MalformedUtf8IsRefused) {
  EXPECT_EQ(problem_of("\xC0\xAF"), ChatTextProblem::NotUtf8);          // overlong '/'
  EXPECT_EQ(problem_of("\xED\xA0\x80"), ChatTextProblem::NotUtf8);      // a surrogate
  EXPECT_EQ(problem_of("cut \xE2\x82"), ChatTextProblem::NotUtf8);      // truncated
  EXPECT_EQ(problem_of("\xF4\x90\x80\x80"), ChatTextProblem::NotUtf8);  // over U+10FFFF
  EXPECT_EQ(problem_of("\xFF"), ChatTextProblem::NotUtf8);
}

}  // namespace
}  // namespace ricochet::proto::chat_text_test
