package io.ricochet.client.core.transport;

/**
 * What this end sent, so that the peer's ack headers (PROTOCOL.md Game channel transport §7) tell
 * which packets arrived, which reliable messages they carried, and the round trip (smoothed, 1/8
 * gain). Remembers the last 256 packets. Mirrors the C++ {@code proto::SentPacketWindow}.
 */
final class SentPacketWindow {
  /** Packets remembered. */
  public static final int SIZE = 256;

  private final long[] sequences = new long[SIZE];
  private final long[] sentAtUs = new long[SIZE];
  private final boolean[] awaiting = new boolean[SIZE];
  private final boolean[] written = new boolean[SIZE];
  private final int[][] carriedIds = new int[SIZE][];
  private final int[] carriedCounts = new int[SIZE];
  private long rttUs;

  /** Packet {@code sequence} left at {@code nowUs} with reliable messages {@code ids[0, count)}. */
  public void onSent(long sequence, long nowUs, int[] ids, int count) {
    int slot = (int) (sequence & (SIZE - 1));
    sequences[slot] = sequence;
    sentAtUs[slot] = nowUs;
    awaiting[slot] = true;
    written[slot] = true;
    if (carriedIds[slot] == null || carriedIds[slot].length < count) {
      carriedIds[slot] = new int[Math.max(count, 4)];
    }
    System.arraycopy(ids, 0, carriedIds[slot], 0, count);
    carriedCounts[slot] = count;
  }

  /**
   * The peer's ack header: the newest sent sequence whose low 16 bits are {@code ack}, and the 32
   * before it named by {@code ackBits}. {@code nextSequence}: the sequence this end sends next.
   * Messages of packets acked for the first time are acknowledged to {@code sender}.
   */
  public void onAck(int ack, int ackBits, long nextSequence, long nowUs, ReliableSender sender) {
    if (nextSequence == 0) return; // nothing sent: an ack of nothing
    long newest = ((nextSequence - 1) & ~0xFFFFL) | (ack & 0xFFFF);
    if (Long.compareUnsigned(newest, nextSequence) >= 0) {
      if (Long.compareUnsigned(newest, 0x10000) < 0) return; // a sequence never sent
      newest -= 0x10000;
    }
    acknowledge(newest, nowUs, sender);
    for (int bits = ackBits; bits != 0; bits &= bits - 1) {
      long i = Integer.numberOfTrailingZeros(bits);
      if (Long.compareUnsigned(i, newest) >= 0) break;
      acknowledge(newest - 1 - i, nowUs, sender);
    }
  }

  /** True once {@code sequence} was acknowledged (false when unknown or too old). */
  public boolean acked(long sequence) {
    int slot = (int) (sequence & (SIZE - 1));
    return written[slot] && !awaiting[slot] && sequences[slot] == sequence;
  }

  /** Smoothed round trip in microseconds, 0 before the first ack. */
  public long rttUs() {
    return rttUs;
  }

  private void acknowledge(long sequence, long nowUs, ReliableSender sender) {
    int slot = (int) (sequence & (SIZE - 1));
    if (!awaiting[slot] || sequences[slot] != sequence) return;
    awaiting[slot] = false;
    for (int i = 0; i < carriedCounts[slot]; ++i) sender.acknowledge(carriedIds[slot][i]);
    carriedCounts[slot] = 0;
    long sample = nowUs - sentAtUs[slot];
    rttUs = rttUs == 0 ? sample : rttUs + (sample - rttUs) / 8;
  }
}
