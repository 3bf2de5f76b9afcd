#pragma once
/// The game channel's packet codec (PROTOCOL.md Game channel transport §packets). All integers
/// little endian.
///
///   connection request (unencrypted, exactly 1200 bytes):
///     u8 type=0 | 16 version | u64 protocol_id | u16 token_len=128 | token | zero padding
///   every other packet (encrypted):
///     u8 type | u64 sequence | ChaCha20-Poly1305(body) with its 16-byte tag
///     additional data = version | protocol_id | type byte; nonce = 4 zero bytes | sequence
///
/// The readers take untrusted bytes: they check every length and range and return a DropReason
/// instead of asserting.

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "ricochet/proto/crypto.h"
#include "ricochet/proto/token_grant.h"
#include "ricochet/proto/transport_counters.h"

namespace ricochet::proto {

inline constexpr std::size_t kMaxDatagramBytes = 1200;
/// The request is padded to this size so that no reply (at most kMaxDatagramBytes) is larger.
inline constexpr std::size_t kConnectionRequestBytes = kMaxDatagramBytes;
inline constexpr std::size_t kVersionBytes = 16;
inline constexpr std::array<std::uint8_t, kVersionBytes> kVersionInfo = {
    'R', 'I', 'C', 'O', 'C', 'H', 'E', 'T', ' ', 'G', 'A', 'M', 'E', ' ', '0', '1'};
inline constexpr std::size_t kEncryptedHeaderBytes = 1 + 8;  ///< type, sequence
inline constexpr std::size_t kMaxBodyBytes = kMaxDatagramBytes - kEncryptedHeaderBytes - kMacBytes;
inline constexpr std::size_t kAckHeaderBytes = 2 + 4;
/// Handshake packets (challenge, denied) use sequences with this bit set, from a server-wide
/// counter, so their nonces never meet the per-connection sequences under the same key.
inline constexpr std::uint64_t kHandshakeSequenceBit = std::uint64_t{1} << 63;
/// Disconnect packets are sent this many times back to back, so that one arrives despite loss.
inline constexpr int kDisconnectCopies = 3;

/// version | u64 protocol_id: the additional data of connect tokens, and the start of every
/// packet's additional data.
using VersionAndProtocol = std::array<std::uint8_t, kVersionBytes + 8>;
VersionAndProtocol version_and_protocol(std::uint64_t protocol_id);

enum class PacketType : std::uint8_t {
  ConnectionRequest = 0,
  ConnectionDenied = 1,
  Challenge = 2,
  Response = 3,
  KeepAlive = 4,
  Payload = 5,
  Disconnect = 6,
};
inline constexpr std::size_t kPacketTypeCount =
    static_cast<std::size_t>(PacketType::Disconnect) + 1;
std::string_view name(PacketType type);

/// A parse result: the value, or why the input was refused.
template <class T>
struct Parsed {
  T value{};
  std::optional<DropReason> error;
  bool ok() const { return !error; }
};

struct ConnectionRequest {
  std::uint64_t protocol_id = 0;
  std::vector<std::uint8_t> connect_token;
};
std::vector<std::uint8_t> write_connection_request(std::uint64_t protocol_id,
                                                   std::span<const std::uint8_t> connect_token);
/// Checks size (exactly kConnectionRequestBytes), version, the token length field and that the
/// padding after the token is all zero (else Malformed). The protocol id is returned, not
/// checked: the caller knows which one it serves.
Parsed<ConnectionRequest> read_connection_request(std::span<const std::uint8_t> datagram);

struct EncryptedHeader {
  PacketType type = PacketType::KeepAlive;
  std::uint64_t sequence = 0;
};
/// Type byte and sequence of an encrypted packet; checks the size against the type's minimum.
Parsed<EncryptedHeader> read_encrypted_header(std::span<const std::uint8_t> datagram);
std::vector<std::uint8_t> seal_packet(PacketType type, std::uint64_t sequence,
                                      std::uint64_t protocol_id, const Key& key,
                                      std::span<const std::uint8_t> body);
/// The same in one buffer: begin_packet writes the header into `packet` (emptied first), the
/// caller appends the body, seal_packet_in_place encrypts the body where it is and appends the
/// tag. A sent payload costs one allocation this way.
void begin_packet(PacketType type, std::uint64_t sequence, std::vector<std::uint8_t>& packet);
void seal_packet_in_place(std::uint64_t protocol_id, const Key& key,
                          std::vector<std::uint8_t>& packet);
/// Decrypts the body of a packet whose header read_encrypted_header accepted.
bool open_packet(std::span<const std::uint8_t> datagram, std::uint64_t protocol_id, const Key& key,
                 std::vector<std::uint8_t>& body);

// ---- bodies (the plaintext inside the encryption) ----

/// Acknowledges the newest sequence received (low 16 bits) and, in bit i, sequence ack - 1 - i.
struct AckHeader {
  std::uint16_t ack = 0;
  std::uint32_t ack_bits = 0;
  friend bool operator==(const AckHeader&, const AckHeader&) = default;
};

inline constexpr std::size_t kChallengeTokenPlainBytes = 8 + 4 + kMacBytes + 16 + 2 + 1;
inline constexpr std::size_t kChallengeTokenBytes = kChallengeTokenPlainBytes + kMacBytes;
/// Body of both the challenge and the response: the response echoes the challenge's body.
struct ChallengeBody {
  std::uint64_t challenge_sequence = 0;
  std::array<std::uint8_t, kChallengeTokenBytes> challenge_token{};
};
std::vector<std::uint8_t> write_challenge_body(const ChallengeBody& body);
Parsed<ChallengeBody> read_challenge_body(std::span<const std::uint8_t> body);

std::vector<std::uint8_t> write_denied_body(DisconnectReason reason);
Parsed<DisconnectReason> read_denied_body(std::span<const std::uint8_t> body);

std::vector<std::uint8_t> write_keep_alive_body(const AckHeader& ack);
Parsed<AckHeader> read_keep_alive_body(std::span<const std::uint8_t> body);

struct DisconnectBody {
  AckHeader ack;
  DisconnectReason reason = DisconnectReason::Requested;
};
std::vector<std::uint8_t> write_disconnect_body(const DisconnectBody& body);
Parsed<DisconnectBody> read_disconnect_body(std::span<const std::uint8_t> body);

/// One reliable-ordered message inside a payload packet.
struct ReliableMessage {
  std::uint16_t id = 0;
  std::vector<std::uint8_t> bytes;
  friend bool operator==(const ReliableMessage&, const ReliableMessage&) = default;
};
inline constexpr std::size_t kReliableMessageHeaderBytes = 2 + 2;
/// Largest reliable message, so that one always fits a payload packet beside the headers.
inline constexpr std::size_t kMaxReliableMessageBytes = 1024;
/// Payload body: ack header | u8 count | count × (u16 id | u16 len | bytes) | unreliable bytes.
struct PayloadBody {
  AckHeader ack;
  std::vector<ReliableMessage> reliable;
  std::vector<std::uint8_t> unreliable;
};
inline constexpr std::size_t kPayloadFixedBytes = kAckHeaderBytes + 1;
/// Largest unreliable payload in a packet without reliable messages.
inline constexpr std::size_t kMaxUnreliableBytes = kMaxBodyBytes - kPayloadFixedBytes;
std::vector<std::uint8_t> write_payload_body(const PayloadBody& body);
/// Appends the body write_payload_body writes to `out`.
void append_payload_body(const AckHeader& ack, std::span<const ReliableMessage> reliable,
                         std::span<const std::uint8_t> unreliable, std::vector<std::uint8_t>& out);
Parsed<PayloadBody> read_payload_body(std::span<const std::uint8_t> body);
/// The same from a decrypted body it takes: the unreliable bytes stay in its buffer (moved to
/// `unreliable`), which saves an allocation and a copy per packet.
Parsed<PayloadBody> read_payload_body(std::vector<std::uint8_t>&& body);

}  // namespace ricochet::proto
