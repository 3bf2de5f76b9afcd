package io.ricochet.client.core.game;

/**
 * Serialises a {@code ClientPayload} (PROTOCOL.md ClientPayload) from an {@link InputHistory}
 * into a caller's buffer, byte for byte as protobuf's serialiser would, allocating nothing.
 */
public final class ClientPayloadWriter {
  /** Largest payload it writes: 8 inputs of at most 41 bytes each and the ack (well under 1168). */
  public static final int MAX_BYTES = InputHistory.MAX_PER_PAYLOAD * 41 + 6;

  private ClientPayloadWriter() {}

  /**
   * Writes the newest {@code count} inputs of {@code history} (1..8, at most those held), oldest
   * first, and {@code ackSnapshotTick} (unsigned 32-bit; 0: none) into {@code out} (at least
   * {@link #MAX_BYTES} long); returns the payload's length in bytes.
   */
  public static int write(InputHistory history, int count, long ackSnapshotTick, byte[] out) {
    if (count < 0 || count > history.held()) {
      throw new IllegalArgumentException("count " + count + " of " + history.held() + " held");
    }
    int at = history.writeNewest(count, out, 0);
    return Wire.putUnsignedField(out, at, 2, (int) ackSnapshotTick);
  }
}
