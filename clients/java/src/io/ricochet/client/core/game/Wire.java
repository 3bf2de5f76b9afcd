package io.ricochet.client.core.game;

/**
 * The few protobuf encodings a ClientPayload needs, written into a caller's array as protobuf's
 * own serialiser writes them (proto3: a field at its default is left out; a float is left out
 * only when its bits are all zero, so -0.0 is written).
 */
final class Wire {
  static final int VARINT = 0;
  static final int LENGTH_DELIMITED = 2;
  static final int FIXED32 = 5;

  private Wire() {}

  static int putTag(byte[] out, int at, int field, int wireType) {
    return putVarint(out, at, (field << 3) | wireType);
  }

  static int putVarint(byte[] out, int at, long value) {
    while ((value & ~0x7FL) != 0) {
      out[at++] = (byte) ((value & 0x7F) | 0x80);
      value >>>= 7;
    }
    out[at++] = (byte) value;
    return at;
  }

  static int varintBytes(long value) {
    int bytes = 1;
    while ((value & ~0x7FL) != 0) {
      value >>>= 7;
      ++bytes;
    }
    return bytes;
  }

  /** sint32's zig-zag code, as an unsigned 32-bit value. */
  static long zigZag(int value) {
    return ((value << 1) ^ (value >> 31)) & 0xFFFFFFFFL;
  }

  /** A uint32 field (value unsigned), left out when 0. */
  static int putUnsignedField(byte[] out, int at, int field, int value) {
    if (value == 0) return at;
    at = putTag(out, at, field, VARINT);
    return putVarint(out, at, value & 0xFFFFFFFFL);
  }

  /** A float field, little-endian, left out when its bits are 0. */
  static int putFloatField(byte[] out, int at, int field, float value) {
    int bits = Float.floatToRawIntBits(value);
    if (bits == 0) return at;
    at = putTag(out, at, field, FIXED32);
    out[at] = (byte) bits;
    out[at + 1] = (byte) (bits >>> 8);
    out[at + 2] = (byte) (bits >>> 16);
    out[at + 3] = (byte) (bits >>> 24);
    return at + 4;
  }
}
