package io.ricochet.client.core.transport;

/**
 * The receiving half of the reliable-ordered channel (PROTOCOL.md Game channel transport §8):
 * delivers messages in id order, each once. A message less than 256 ids ahead of the next expected
 * one is buffered; one already delivered (up to 32768 behind) is a duplicate; one 256 or more ahead
 * is out of the window. Ids are u16 and wrap. Mirrors the C++ {@code proto::ReliableReceiver}.
 */
final class ReliableReceiver {
  /** How far ahead of the next expected id a message is buffered. */
  public static final int WINDOW = 256;

  /** What {@link #receive} did with a message. */
  public enum Outcome {
    /** Buffered for {@link #pop}. */
    ACCEPTED,
    /** Delivered or buffered already: ignored. */
    DUPLICATE,
    /** 256 or more ids ahead: dropped (the sender never has that many in flight). */
    OUT_OF_WINDOW
  }

  private final byte[][] window = new byte[WINDOW][];
  private int buffered;
  private int nextId;

  /** Takes message {@code id} (0..65535), copying {@code bytes[offset, offset + length)}. */
  public Outcome receive(int id, byte[] bytes, int offset, int length) {
    int ahead = (id - nextId) & 0xFFFF;
    if (ahead >= 0x8000) return Outcome.DUPLICATE; // behind the next expected id: delivered
    if (ahead >= WINDOW) return Outcome.OUT_OF_WINDOW;
    int slot = id % WINDOW;
    if (window[slot] != null) return Outcome.DUPLICATE;
    byte[] message = new byte[length];
    System.arraycopy(bytes, offset, message, 0, length);
    window[slot] = message;
    ++buffered;
    return Outcome.ACCEPTED;
  }

  /** The next message in order (the caller owns it), or null when it has not arrived. */
  public byte[] pop() {
    if (buffered == 0) return null;
    int slot = nextId % WINDOW;
    byte[] message = window[slot];
    if (message == null) return null;
    window[slot] = null;
    --buffered;
    nextId = (nextId + 1) & 0xFFFF;
    return message;
  }
}
