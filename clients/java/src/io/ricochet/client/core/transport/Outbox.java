package io.ricochet.client.core.transport;

/**
 * The datagrams a {@link GameClient} wants sent, in order, in buffers it reuses: after every call
 * into the client, the I/O layer writes {@code datagram(i)[0, length(i))} for i in [0, size()) to
 * the server and then calls {@link #clear}. Buffers are {@link Packets#MAX_DATAGRAM_BYTES} long and
 * are allocated only when more datagrams are pending at once than ever before.
 */
public final class Outbox {
  private byte[][] buffers = new byte[4][];
  private int[] lengths = new int[4];
  private int size;

  /** Datagrams waiting. */
  public int size() {
    return size;
  }

  /** The buffer of datagram {@code index}; its bytes are {@code [0, length(index))}. */
  public byte[] datagram(int index) {
    check(index);
    return buffers[index];
  }

  /** The length in bytes of datagram {@code index}. */
  public int length(int index) {
    check(index);
    return lengths[index];
  }

  /** Forgets the datagrams (the caller sent them); their buffers are reused. */
  public void clear() {
    size = 0;
  }

  /** A buffer for the next datagram; {@link #commit} adds it. */
  byte[] next() {
    if (size == buffers.length) {
      buffers = java.util.Arrays.copyOf(buffers, size * 2);
      lengths = java.util.Arrays.copyOf(lengths, size * 2);
    }
    if (buffers[size] == null) buffers[size] = new byte[Packets.MAX_DATAGRAM_BYTES];
    return buffers[size];
  }

  /** Adds the datagram written into {@link #next}'s buffer, {@code length} bytes. */
  void commit(int length) {
    lengths[size++] = length;
  }

  private void check(int index) {
    if (index < 0 || index >= size) {
      throw new IndexOutOfBoundsException("datagram " + index + " of " + size);
    }
  }
}
