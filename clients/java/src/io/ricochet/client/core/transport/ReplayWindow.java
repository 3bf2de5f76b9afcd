package io.ricochet.client.core.transport;

/**
 * The 256-entry replay window of received sequences (PROTOCOL.md Game channel transport §7): a
 * packet is accepted once, and never when it is 256 or more below the newest accepted sequence.
 * The same window gives the ack header this end sends, and the loss figures of the link towards
 * it. Sequences are unsigned 64-bit values in a long. Mirrors the C++ {@code proto::ReplayWindow}.
 */
final class ReplayWindow {
  /** Sequences the window remembers. */
  public static final int SIZE = 256;

  private static final int WORDS = SIZE / 64;

  /** Bit k (word k / 64, bit k % 64): sequence newest - k was accepted. */
  private final long[] received = new long[WORDS];
  private long newest;
  private boolean any;
  private long missing;
  private long late;

  /** True when {@code sequence} was accepted before or is too old to tell: refuse it. */
  public boolean alreadyReceived(long sequence) {
    if (!any || Long.compareUnsigned(sequence, newest) > 0) return false;
    long behind = newest - sequence;
    return Long.compareUnsigned(behind, SIZE) >= 0 || bit((int) behind);
  }

  /** Marks {@code sequence} accepted; call only after its packet authenticated. */
  public void markReceived(long sequence) {
    if (!any) {
      missing = sequence; // the peer's sequences start at 0
      newest = sequence;
    } else if (Long.compareUnsigned(sequence, newest) > 0) {
      missing += sequence - newest - 1;
      slide(sequence - newest);
      newest = sequence;
    } else {
      --missing; // a gap below the newest filled
      ++late;
    }
    any = true;
    long behind = newest - sequence;
    if (Long.compareUnsigned(behind, SIZE) < 0) {
      received[(int) behind / 64] |= 1L << (behind % 64);
    }
  }

  /** The u16 ack of the newest accepted sequence (0 before any). */
  public int ack() {
    return any ? (int) (newest & 0xFFFF) : 0;
  }

  /** Bit i set when sequence newest - 1 - i was accepted, i = 0..31 (0 before any). */
  public int ackBits() {
    return any ? (int) (received[0] >>> 1) : 0;
  }

  /** Whether any sequence was accepted. */
  public boolean anyReceived() {
    return any;
  }

  /** The newest accepted sequence (0 before any). */
  public long newest() {
    return newest;
  }

  /**
   * Sequences below the newest accepted one never accepted: lost, too late, or still on the way.
   * missing() / (newest() + 1) is the link's loss towards this end.
   */
  public long missing() {
    return missing;
  }

  /** Packets accepted after a newer one (reordered or delayed). */
  public long late() {
    return late;
  }

  private boolean bit(int behind) {
    return (received[behind / 64] >>> (behind % 64) & 1) != 0;
  }

  /** The newest moves up by {@code by}: every bit moves further behind; the oldest fall out. */
  private void slide(long by) {
    if (Long.compareUnsigned(by, SIZE) >= 0) {
      java.util.Arrays.fill(received, 0);
      return;
    }
    int words = (int) by / 64;
    int bits = (int) by % 64;
    for (int i = WORDS - 1; i >= 0; --i) {
      long moved = 0;
      if (i >= words) {
        moved = received[i - words] << bits;
        if (bits != 0 && i > words) moved |= received[i - words - 1] >>> (64 - bits);
      }
      received[i] = moved;
    }
  }
}
