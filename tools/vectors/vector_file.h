#pragma once
/// The text format of tests/vectors/*.txt (README.md there), written by ricochet-vectors and read
/// by the C++ and Java tests. A file is lines; `#` starts a comment line. Every other line is a
/// record: a kind, then `key=value` fields separated by one space. A value is lowercase hex
/// (bytes), a decimal integer, or a word of [A-Za-z0-9_.:-] (a name).

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace ricochet::vectors {

/// One line of a vector file.
class Record {
 public:
  explicit Record(std::string_view kind);
  Record& bytes(std::string_view key, std::span<const std::uint8_t> value);
  Record& bytes(std::string_view key, std::string_view value);  ///< a serialised message
  Record& number(std::string_view key, std::int64_t value);
  Record& word(std::string_view key, std::string_view value);
  const std::string& line() const { return line_; }

 private:
  void key(std::string_view key);
  std::string line_;
};

/// A whole file: a header comment naming the set, then records in order.
class VectorFile {
 public:
  VectorFile(std::string_view set, std::string_view description);
  void comment(std::string_view text);
  void add(const Record& record);
  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

/// A set of vectors: tests/vectors/NAME.txt and the function that writes its text. The same
/// inputs always give the same text (no clocks, no randomness without a fixed seed).
struct VectorSet {
  const char* name;
  std::string (*write)();
};

/// Every set, in the order ricochet-vectors writes them (vector_sets.cpp).
std::span<const VectorSet> vector_sets();

}  // namespace ricochet::vectors
