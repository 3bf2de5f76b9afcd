#include "ricochet/proto/frame.h"

#include <algorithm>

namespace ricochet::proto {
namespace {

/// Compacts the buffer once the consumed prefix is at least this large (bytes).
constexpr std::size_t kCompactThreshold = 16 * 1024;

std::uint32_t read_length(const std::uint8_t* header) {
  return (std::uint32_t{header[0]} << 24) | (std::uint32_t{header[1]} << 16) |
         (std::uint32_t{header[2]} << 8) | std::uint32_t{header[3]};
}

template <class Message>
bool parse_into(std::span<const std::uint8_t> payload, Message& out) {
  if (payload.size() > kMaxFramePayloadBytes) return false;
  return out.ParseFromArray(payload.data(), static_cast<int>(payload.size()));
}

}  // namespace

const char* name(FrameRefusal refusal) {
  switch (refusal) {
    case FrameRefusal::Oversize:
      return "frame_oversize";
    case FrameRefusal::Empty:
      return "frame_empty";
    case FrameRefusal::Malformed:
      return "frame_malformed";
    case FrameRefusal::MissingBody:
      return "frame_missing_body";
  }
  return "unknown";
}

void FrameReader::feed(std::span<const std::uint8_t> bytes) {
  if (refusal_ || bytes.empty()) return;
  if (start_ >= kCompactThreshold || (start_ > 0 && start_ == buffer_.size())) {
    buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<std::ptrdiff_t>(start_));
    start_ = 0;
  }
  buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
}

FrameReader::Status FrameReader::next(std::vector<std::uint8_t>& payload) {
  if (refusal_) return Status::Refused;
  if (buffered() < kFrameHeaderBytes) return Status::NeedMore;
  const std::uint32_t length = read_length(buffer_.data() + start_);
  if (length == 0 || length > kMaxFramePayloadBytes) {
    refusal_ = length == 0 ? FrameRefusal::Empty : FrameRefusal::Oversize;
    refused_length_ = length;
    buffer_.clear();
    buffer_.shrink_to_fit();
    start_ = 0;
    return Status::Refused;
  }
  if (buffered() - kFrameHeaderBytes < length) return Status::NeedMore;
  const auto first = buffer_.begin() + static_cast<std::ptrdiff_t>(start_ + kFrameHeaderBytes);
  payload.assign(first, first + length);
  start_ += kFrameHeaderBytes + length;
  return Status::Frame;
}

bool append_frame(const google::protobuf::MessageLite& message, std::vector<std::uint8_t>& out) {
  const std::size_t size = message.ByteSizeLong();
  if (size == 0 || size > kMaxFramePayloadBytes) return false;
  const std::size_t at = out.size();
  out.resize(at + kFrameHeaderBytes + size);
  std::uint8_t* header = out.data() + at;
  header[0] = static_cast<std::uint8_t>(size >> 24);
  header[1] = static_cast<std::uint8_t>(size >> 16);
  header[2] = static_cast<std::uint8_t>(size >> 8);
  header[3] = static_cast<std::uint8_t>(size);
  if (!message.SerializeToArray(header + kFrameHeaderBytes, static_cast<int>(size))) {
    out.resize(at);
    return false;
  }
  return true;
}

std::optional<FrameRefusal> parse_client_message(std::span<const std::uint8_t> payload,
                                                 wire::ClientMessage& out) {
  if (!parse_into(payload, out)) return FrameRefusal::Malformed;
  if (out.body_case() == wire::ClientMessage::BODY_NOT_SET) return FrameRefusal::MissingBody;
  return std::nullopt;
}

std::optional<FrameRefusal> parse_server_message(std::span<const std::uint8_t> payload,
                                                 wire::ServerMessage& out) {
  if (!parse_into(payload, out)) return FrameRefusal::Malformed;
  if (out.body_case() == wire::ServerMessage::BODY_NOT_SET) return FrameRefusal::MissingBody;
  return std::nullopt;
}

}  // namespace ricochet::proto
