package io.ricochet.client.core.snapshot;

import java.io.ByteArrayOutputStream;

/**
 * Writes a packed entity stream bit by bit for hand-made snapshots (PROTOCOL.md, Snapshots §3):
 * raw fields most significant bit first, Exp-Golomb codes, zig-zag; zero padding at the end.
 */
final class StreamWriter {
  private final ByteArrayOutputStream bytes = new ByteArrayOutputStream();
  private int pending;
  private int pendingBits;

  /** The low {@code count} bits of {@code value}, most significant first. */
  StreamWriter bits(long value, int count) {
    for (int bit = count - 1; bit >= 0; --bit) {
      pending = (pending << 1) | (int) ((value >>> bit) & 1);
      if (++pendingBits == 8) {
        bytes.write(pending);
        pending = 0;
        pendingBits = 0;
      }
    }
    return this;
  }

  /** A string of '0' and '1' (spaces ignored). */
  StreamWriter bits(String pattern) {
    for (char c : pattern.toCharArray()) {
      if (c != ' ') bits(c == '1' ? 1 : 0, 1);
    }
    return this;
  }

  /** EG(order) of {@code value} >= 0. */
  StreamWriter eg(long value, int order) {
    long shifted = value + (1L << order);
    int width = 64 - Long.numberOfLeadingZeros(shifted);
    bits(0, width - order - 1);
    return bits(shifted, width);
  }

  /** A signed value zig-zagged, then EG(order). */
  StreamWriter seg(long value, int order) {
    return eg((value << 1) ^ (value >> 63), order);
  }

  /** The bytes, the last padded with zeros. */
  byte[] bytes() {
    ByteArrayOutputStream out = new ByteArrayOutputStream();
    byte[] written = bytes.toByteArray();
    out.write(written, 0, written.length);
    if (pendingBits > 0) out.write(pending << (8 - pendingBits));
    return out.toByteArray();
  }
}
