package io.ricochet.client.core.transport;

/**
 * The sending half of the reliable-ordered channel (PROTOCOL.md Game channel transport §8): keeps
 * each message until a packet that carried it is acked, resends it when it was last sent at least
 * the resend interval ago, and has at most {@code window} messages in flight; later ones wait,
 * unsent. Everything a client sends is must-arrive: a message beyond {@code maxQueued} is refused
 * (the client then disconnects with {@link DisconnectReason#RELIABLE_OVERFLOW}). Mirrors the C++
 * {@code proto::ReliableSender}.
 */
final class ReliableSender {
  private final int window;
  private final byte[][] messages;
  private final int[] lengths;
  private final long[] lastSentUs;
  private final boolean[] sent;
  private final boolean[] acked;
  private int head; // ring slot of the oldest message
  private int count;
  private int nextId;
  private long resends;
  private int takenBytes;

  /**
   * {@code window} (1..256): messages in flight at most, the receiver's window. {@code maxQueued}
   * (window or more): messages held at most, in flight or waiting.
   */
  public ReliableSender(int window, int maxQueued) {
    this.window = Math.max(1, Math.min(window, ReliableReceiver.WINDOW));
    int capacity = Math.max(maxQueued, this.window);
    messages = new byte[capacity][];
    lengths = new int[capacity];
    lastSentUs = new long[capacity];
    sent = new boolean[capacity];
    acked = new boolean[capacity];
  }

  /**
   * Queues a copy of {@code bytes[offset, offset + length)} (1..1024 bytes, checked by the caller);
   * false when {@code maxQueued} messages are held already.
   */
  public boolean push(byte[] bytes, int offset, int length) {
    if (count == messages.length) return false;
    int slot = slot(count);
    byte[] copy = new byte[length];
    System.arraycopy(bytes, offset, copy, 0, length);
    messages[slot] = copy;
    lengths[slot] = length;
    sent[slot] = false;
    acked[slot] = false;
    ++count;
    nextId = (nextId + 1) & 0xFFFF;
    return true;
  }

  /** True when a message among the window's oldest was never sent or is due for a resend. */
  public boolean hasDue(long nowUs, long resendUs) {
    int end = Math.min(window, count);
    for (int i = 0; i < end; ++i) {
      if (due(slot(i), nowUs, resendUs)) return true;
    }
    return false;
  }

  /**
   * Writes the messages due among the window's oldest, oldest first, each as u16 id || u16 length
   * || bytes, into {@code out} from {@code at}, as many as fit in {@code budgetBytes} (at most
   * 255), and marks them sent at {@code nowUs}. Their ids go to {@code ids}; returns how many;
   * {@link #takenBytes} is the bytes written.
   */
  public int takeDue(long nowUs, long resendUs, int budgetBytes, byte[] out, int at, int[] ids) {
    int taken = 0;
    int position = at;
    int end = Math.min(window, count);
    int firstId = (nextId - count) & 0xFFFF;
    for (int i = 0; i < end && taken < 255; ++i) {
      int slot = slot(i);
      if (!due(slot, nowUs, resendUs)) continue;
      int cost = Packets.RELIABLE_MESSAGE_HEADER_BYTES + lengths[slot];
      if (cost > budgetBytes) break; // keep order: a later message must not overtake
      budgetBytes -= cost;
      if (sent[slot]) ++resends;
      sent[slot] = true;
      lastSentUs[slot] = nowUs;
      int id = (firstId + i) & 0xFFFF;
      Packets.putU16(out, position, id);
      Packets.putU16(out, position + 2, lengths[slot]);
      System.arraycopy(messages[slot], 0, out, position + 4, lengths[slot]);
      position += cost;
      ids[taken++] = id;
    }
    takenBytes = position - at;
    return taken;
  }

  /** Bytes the last {@link #takeDue} wrote. */
  public int takenBytes() {
    return takenBytes;
  }

  /**
   * When {@link #hasDue} next turns true: {@code Long.MIN_VALUE} when a message in the window was
   * never sent, the earliest resend time of those in flight, {@code Long.MAX_VALUE} when none.
   */
  public long nextDueUs(long resendUs) {
    long next = Long.MAX_VALUE;
    int end = Math.min(window, count);
    for (int i = 0; i < end; ++i) {
      int slot = slot(i);
      if (acked[slot]) continue;
      if (!sent[slot]) return Long.MIN_VALUE;
      next = Math.min(next, lastSentUs[slot] + resendUs);
    }
    return next;
  }

  /** A packet that carried message {@code id} was acked: it is delivered. */
  public void acknowledge(int id) {
    if (count == 0) return;
    int firstId = (nextId - count) & 0xFFFF;
    int offset = (id - firstId) & 0xFFFF;
    if (offset >= count) return; // acked and gone already, or never sent
    acked[slot(offset)] = true;
    while (count > 0 && acked[head]) {
      messages[head] = null;
      head = (head + 1) % messages.length;
      --count;
    }
  }

  /** Messages held, in flight or waiting. */
  public int pending() {
    return count;
  }

  /** Messages sent again because no ack came within the resend interval. */
  public long resends() {
    return resends;
  }

  private boolean due(int slot, long nowUs, long resendUs) {
    return !acked[slot] && (!sent[slot] || nowUs - lastSentUs[slot] >= resendUs);
  }

  private int slot(int offset) {
    return (head + offset) % messages.length;
  }
}
