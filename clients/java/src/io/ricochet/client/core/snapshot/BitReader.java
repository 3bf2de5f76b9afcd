package io.ricochet.client.core.snapshot;

/**
 * Reads the packed snapshot stream (PROTOCOL.md, Snapshots §3; proto/bit_stream.h): most
 * significant bit first, raw fields of n bits and order-k Exp-Golomb codes. It never reads past its
 * input: a read beyond the end, or an Exp-Golomb body wider than {@link #MAX_EXP_GOLOMB_WIDTH}
 * bits, sets a sticky failure and yields 0, so a caller reads a whole section and checks {@link
 * #failed()} once. Reused: {@link #reset} points it at the next stream without allocating.
 */
final class BitReader {
  /** Widest Exp-Golomb code body accepted (bits): every value read is below 2^42. */
  static final int MAX_EXP_GOLOMB_WIDTH = 42;

  private byte[] bytes = new byte[0];
  private int offset;
  private int length;
  /** The input as big-endian 64-bit words, zeros after it (two more words than it covers). */
  private long[] words = new long[2];
  private long totalBits;
  private long position; // bits read
  private boolean failed;
  private boolean malformed;

  /** Reads {@code bytes[offset, offset + length)} from its first bit. */
  void reset(byte[] bytes, int offset, int length) {
    this.bytes = bytes;
    this.offset = offset;
    this.length = length;
    this.totalBits = 8L * length;
    this.position = 0;
    this.failed = false;
    this.malformed = false;
    int whole = length >>> 3;
    int needed = whole + 2;
    if (words.length < needed) words = new long[Math.max(needed, 2 * words.length)];
    int at = offset;
    for (int w = 0; w < whole; ++w, at += 8) {
      words[w] = (bytes[at] & 0xFFL) << 56 | (bytes[at + 1] & 0xFFL) << 48
          | (bytes[at + 2] & 0xFFL) << 40 | (bytes[at + 3] & 0xFFL) << 32
          | (bytes[at + 4] & 0xFFL) << 24 | (bytes[at + 5] & 0xFFL) << 16
          | (bytes[at + 6] & 0xFFL) << 8 | (bytes[at + 7] & 0xFFL);
    }
    long last = 0;
    for (int k = 0; k < 8; ++k) {
      last = (last << 8) | (whole * 8 + k < length ? bytes[at + k] & 0xFFL : 0);
    }
    words[whole] = last;
    words[whole + 1] = 0;
  }

  /** The next {@code bits} (0..64) bits as an unsigned value; 0 and failed() past the end. */
  long readBits(int bits) {
    if (failed || bits > totalBits - position) {
      failed = true;
      return 0;
    }
    if (bits == 0) return 0;
    long value = peek64() >>> (64 - bits);
    position += bits;
    return value;
  }

  boolean readBool() {
    return readBits(1) != 0;
  }

  /** An order-{@code order} (0..31) Exp-Golomb code's value; 0 and failed() when malformed. */
  long readExpGolomb(int order) {
    if (failed) return 0;
    long left = totalBits - position;
    // More zeros before the leading 1 than this make the code malformed; a code that ends before
    // its 1 is truncated, and malformed too once the zeros read and the missing bit are more.
    long mostZeros = MAX_EXP_GOLOMB_WIDTH - order - 1;
    long next = peek64();
    long zeros = Math.min(Long.numberOfLeadingZeros(next), left);
    if (zeros == left) {
      failed = true;
      malformed = left >= mostZeros;
      return 0;
    }
    if (zeros > mostZeros) {
      failed = true;
      malformed = true;
      return 0;
    }
    long width = 2 * zeros + order + 1; // the zeros, then v + 2^order in zeros + order + 1 bits
    if (width > left) {
      failed = true;
      return 0;
    }
    long base = 1L << order;
    if (width <= 64) {
      position += width;
      return (next >>> (64 - width)) - base;
    }
    position += zeros + 1; // the zeros and the leading 1; the rest follows
    int rest = (int) zeros + order;
    return ((1L << rest) | readBits(rest)) - base;
  }

  /** A signed Exp-Golomb code: the zig-zag value mapped back (0, -1, 1, -2 ...). */
  static long unzigzag(long value) {
    return (value >>> 1) ^ -(value & 1);
  }

  boolean failed() {
    return failed;
  }

  /** The failure came from an over-long Exp-Golomb code rather than the end of the input. */
  boolean malformed() {
    return malformed;
  }

  long bitsLeft() {
    return failed ? 0 : totalBits - position;
  }

  /** True when fewer than 8 bits are left and all are zero (the last byte's padding). */
  boolean onlyPaddingLeft() {
    if (failed) return false;
    long left = totalBits - position;
    if (left >= 8) return false;
    if (left == 0) return true;
    int mask = (1 << (int) left) - 1;
    return (bytes[offset + length - 1] & mask) == 0;
  }

  /** The next 64 bits from the position, zeros past the end. */
  private long peek64() {
    int word = (int) (position >>> 6);
    int shift = (int) (position & 63);
    long high = words[word];
    return shift == 0 ? high : high << shift | words[word + 1] >>> (64 - shift);
  }
}
