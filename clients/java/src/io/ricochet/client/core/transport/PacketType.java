package io.ricochet.client.core.transport;

/**
 * The type byte that starts every game packet (PROTOCOL.md Game channel transport §5), with the
 * smallest body each encrypted type can have. Any other byte is {@link DropReason#MALFORMED}.
 */
enum PacketType {
  /** Client → server, unencrypted, exactly 1200 bytes. */
  CONNECTION_REQUEST("connection_request", 0),
  /** Server → client: u8 reason. */
  CONNECTION_DENIED("connection_denied", 1),
  /** Server → client: the challenge body. */
  CHALLENGE("challenge", Packets.CHALLENGE_BODY_BYTES),
  /** Client → server: the challenge body echoed. */
  RESPONSE("response", Packets.CHALLENGE_BODY_BYTES),
  /** Both ways: the ack header. */
  KEEP_ALIVE("keep_alive", Packets.ACK_HEADER_BYTES),
  /** Both ways: ack header, reliable messages, unreliable bytes. */
  PAYLOAD("payload", Packets.PAYLOAD_FIXED_BYTES),
  /** Both ways: ack header, u8 reason. */
  DISCONNECT("disconnect", Packets.ACK_HEADER_BYTES + 1);

  private static final PacketType[] BY_WIRE = values();

  private final String logName;
  private final int minBodyBytes;

  PacketType(String logName, int minBodyBytes) {
    this.logName = logName;
    this.minBodyBytes = minBodyBytes;
  }

  /** The type's name in logs and vectors, the same as the C++ end's. */
  public String logName() {
    return logName;
  }

  /** The type byte. */
  public int wireValue() {
    return ordinal();
  }

  /** Smallest body (bytes, before encryption) of an encrypted packet of this type. */
  int minBodyBytes() {
    return minBodyBytes;
  }

  /** The encrypted type a packet's first byte (0..255) names, or null (malformed). */
  static PacketType encryptedFromWire(int value) {
    return value >= 1 && value < BY_WIRE.length ? BY_WIRE[value] : null;
  }
}
