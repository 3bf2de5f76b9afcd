#include "vector_file.h"

#include <stdexcept>

namespace ricochet::vectors {
namespace {

bool is_word(std::string_view text) {
  if (text.empty()) return false;
  for (const char c : text) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '.' || c == ':' || c == '-';
    if (!ok) return false;
  }
  return true;
}

}  // namespace

Record::Record(std::string_view kind) : line_(kind) {
  if (!is_word(kind)) throw std::invalid_argument("a record kind is a word");
}

void Record::key(std::string_view key) {
  if (!is_word(key)) throw std::invalid_argument("a key is a word");
  line_ += ' ';
  line_ += key;
  line_ += '=';
}

Record& Record::bytes(std::string_view key, std::span<const std::uint8_t> value) {
  static constexpr char kHex[] = "0123456789abcdef";
  this->key(key);
  for (const std::uint8_t b : value) {
    line_ += kHex[b >> 4];
    line_ += kHex[b & 15];
  }
  return *this;
}

Record& Record::bytes(std::string_view key, std::string_view value) {
  return bytes(key, std::span(reinterpret_cast<const std::uint8_t*>(value.data()), value.size()));
}

Record& Record::number(std::string_view key, std::int64_t value) {
  this->key(key);
  line_ += std::to_string(value);
  return *this;
}

Record& Record::word(std::string_view key, std::string_view value) {
  if (!is_word(value)) throw std::invalid_argument("a word value is [A-Za-z0-9_.:-]+");
  this->key(key);
  line_ += value;
  return *this;
}

VectorFile::VectorFile(std::string_view set, std::string_view description) {
  text_ = "# ricochet test vectors: ";
  text_ += set;
  text_ += ". Written by ricochet-vectors (tools/vectors); do not edit.\n";
  comment(description);
}

void VectorFile::comment(std::string_view text) {
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t end = std::min(text.find('\n', start), text.size());
    text_ += "# ";
    text_ += text.substr(start, end - start);
    text_ += '\n';
    start = end + 1;
  }
}

void VectorFile::add(const Record& record) {
  text_ += record.line();
  text_ += '\n';
}

}  // namespace ricochet::vectors
