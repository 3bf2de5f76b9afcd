#pragma once
/// The control channel's framing, sans-IO: a frame is a 4-byte big-endian payload length
/// followed by that many bytes of one protobuf message (ClientMessage or ServerMessage,
/// control.proto). A payload is 1..kMaxFramePayloadBytes bytes.
///
/// FrameReader takes bytes as they arrive (any split), yields whole payloads in order, and
/// refuses a stream at the first frame that cannot be right (oversize or empty) with a reason;
/// an oversize length is refused as soon as its 4 header bytes are in, so a hostile peer never
/// makes it buffer more than one frame. parse_client_message() then checks the payload.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "ricochet/wire/control.pb.h"

namespace ricochet::proto {

inline constexpr std::size_t kFrameHeaderBytes = 4;
inline constexpr std::size_t kMaxFramePayloadBytes = 65536;  ///< 64 KiB, the largest payload

/// Why a frame or its payload was refused.
enum class FrameRefusal : std::uint8_t {
  Oversize,     ///< the declared length is over kMaxFramePayloadBytes
  Empty,        ///< the declared length is 0
  Malformed,    ///< the payload is not a valid message (bad wire format, invalid UTF-8 ...)
  MissingBody,  ///< a valid message with no body in its oneof
};
inline constexpr std::size_t kFrameRefusalCount =
    static_cast<std::size_t>(FrameRefusal::MissingBody) + 1;
const char* name(FrameRefusal refusal);

/// Reassembles frames from a byte stream. Not thread-safe; one per connection.
class FrameReader {
 public:
  enum class Status {
    NeedMore,  ///< no whole frame buffered; feed more bytes
    Frame,     ///< `payload` holds the next frame's payload
    Refused,   ///< the stream is broken; refusal() says why; every later call returns Refused
  };

  /// Appends received bytes. Bytes fed after a refusal are ignored.
  void feed(std::span<const std::uint8_t> bytes);
  /// Takes the next whole frame, if any, into `payload` (its previous content is replaced).
  Status next(std::vector<std::uint8_t>& payload);

  std::optional<FrameRefusal> refusal() const { return refusal_; }
  /// The length the peer declared for the refused frame (for the error message), 0 if unknown.
  std::uint32_t refused_length() const { return refused_length_; }
  /// True while part of a frame is buffered (the slowloris deadline runs while this holds).
  bool inside_frame() const { return buffered() > 0; }
  /// Bytes buffered and not yet returned.
  std::size_t buffered() const { return buffer_.size() - start_; }

 private:
  std::vector<std::uint8_t> buffer_;
  std::size_t start_ = 0;  ///< first byte not yet returned
  std::optional<FrameRefusal> refusal_;
  std::uint32_t refused_length_ = 0;
};

/// Appends one frame (header + payload) holding `message` to `out`. Returns false and appends
/// nothing when the serialised message would be over kMaxFramePayloadBytes or empty.
bool append_frame(const google::protobuf::MessageLite& message, std::vector<std::uint8_t>& out);

/// Parses a payload as a ClientMessage: nullopt when it is well formed and has a body,
/// otherwise Malformed or MissingBody.
std::optional<FrameRefusal> parse_client_message(std::span<const std::uint8_t> payload,
                                                 wire::ClientMessage& out);
/// The same for a ServerMessage (clients and tests).
std::optional<FrameRefusal> parse_server_message(std::span<const std::uint8_t> payload,
                                                 wire::ServerMessage& out);

}  // namespace ricochet::proto
