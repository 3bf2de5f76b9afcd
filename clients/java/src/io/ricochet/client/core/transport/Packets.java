package io.ricochet.client.core.transport;

import java.nio.charset.StandardCharsets;

/**
 * The game channel's packet layout (PROTOCOL.md Game channel transport §1, §2, §5): sizes, the
 * version string, the connection request, and little-endian integers. Every integer on the game
 * channel is little endian. Used by {@link GameClient} and its parts; public for the constants an
 * I/O layer needs (the largest datagram).
 */
public final class Packets {
  private Packets() {}

  /** The protocol id of this Ricochet build ("RICOCHET" in ASCII), in every request and token. */
  public static final long PROTOCOL_ID = 0x5249434F43484554L;
  /** Every datagram, both directions, is at most this many bytes. */
  public static final int MAX_DATAGRAM_BYTES = 1200;
  /** The connection request is exactly this long, so no reply is ever larger. */
  public static final int CONNECTION_REQUEST_BYTES = MAX_DATAGRAM_BYTES;
  /** The opaque connect token from the join reply. */
  public static final int CONNECT_TOKEN_BYTES = 128;
  /** A session key (client_to_server, server_to_client). */
  public static final int KEY_BYTES = 32;
  /** The Poly1305 tag at the end of every encrypted packet. */
  public static final int MAC_BYTES = 16;
  /** Type byte and u64 sequence before an encrypted body. */
  public static final int HEADER_BYTES = 1 + 8;
  /** The largest body of an encrypted packet. */
  public static final int MAX_BODY_BYTES = MAX_DATAGRAM_BYTES - HEADER_BYTES - MAC_BYTES;
  /** u16 ack, u32 ack_bits. */
  public static final int ACK_HEADER_BYTES = 2 + 4;
  /** The ack header and the u8 count of reliable messages that start a payload body. */
  public static final int PAYLOAD_FIXED_BYTES = ACK_HEADER_BYTES + 1;
  /** The largest unreliable payload (a packet without reliable messages), 1168 bytes. */
  public static final int MAX_UNRELIABLE_BYTES = MAX_BODY_BYTES - PAYLOAD_FIXED_BYTES;
  /** The largest reliable message; the smallest is 1 byte. */
  public static final int MAX_RELIABLE_MESSAGE_BYTES = 1024;
  /** u16 id, u16 length before each reliable message. */
  public static final int RELIABLE_MESSAGE_HEADER_BYTES = 2 + 2;
  /** The server's sealed challenge token, echoed by the client. */
  public static final int CHALLENGE_TOKEN_BYTES = 47 + MAC_BYTES;
  /** u64 challenge_sequence and the challenge token. */
  public static final int CHALLENGE_BODY_BYTES = 8 + CHALLENGE_TOKEN_BYTES;
  /** Set in the sequences of challenge and denied packets (a server-wide counter). */
  public static final long HANDSHAKE_SEQUENCE_BIT = 1L << 63;
  /** Disconnect packets are sent this many times back to back. */
  public static final int DISCONNECT_COPIES = 3;

  /** "RICOCHET GAME 01": the 16 version bytes. */
  static final byte[] VERSION = "RICOCHET GAME 01".getBytes(StandardCharsets.US_ASCII);

  /**
   * The 1200-byte connection request (§5.1): type 0, version, protocol id, token length, the token,
   * zero padding. Built once per connect token; the client sends the same bytes every time.
   */
  static byte[] connectionRequest(long protocolId, byte[] connectToken) {
    byte[] out = new byte[CONNECTION_REQUEST_BYTES];
    out[0] = (byte) PacketType.CONNECTION_REQUEST.wireValue();
    System.arraycopy(VERSION, 0, out, 1, VERSION.length);
    putU64(out, 1 + VERSION.length, protocolId);
    putU16(out, 1 + VERSION.length + 8, connectToken.length);
    System.arraycopy(connectToken, 0, out, 1 + VERSION.length + 8 + 2, connectToken.length);
    return out;
  }

  static void putU16(byte[] out, int at, int value) {
    out[at] = (byte) value;
    out[at + 1] = (byte) (value >>> 8);
  }

  static void putU32(byte[] out, int at, int value) {
    for (int i = 0; i < 4; ++i) out[at + i] = (byte) (value >>> (8 * i));
  }

  static void putU64(byte[] out, int at, long value) {
    for (int i = 0; i < 8; ++i) out[at + i] = (byte) (value >>> (8 * i));
  }

  static int getU16(byte[] in, int at) {
    return (in[at] & 0xFF) | (in[at + 1] & 0xFF) << 8;
  }

  /** The u32 at {@code at}, its bits in an int. */
  static int getU32(byte[] in, int at) {
    return (in[at] & 0xFF) | (in[at + 1] & 0xFF) << 8 | (in[at + 2] & 0xFF) << 16
        | (in[at + 3] & 0xFF) << 24;
  }

  /** The u64 at {@code at}, its bits in a long. */
  static long getU64(byte[] in, int at) {
    long value = 0;
    for (int i = 7; i >= 0; --i) value = value << 8 | (in[at + i] & 0xFF);
    return value;
  }
}
