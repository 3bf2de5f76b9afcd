package io.ricochet.client.core;

import java.util.Arrays;

/**
 * The control channel's framing, sans-IO: a frame is a 4-byte big-endian payload length followed
 * by that many bytes of one protobuf message (ServerMessage from the server). A payload is 1 ..
 * {@link #MAX_PAYLOAD_BYTES} bytes (PROTOCOL.md, "Framing").
 *
 * <p>Takes bytes as they arrive (any split), yields whole payloads in order, and refuses the
 * stream at the first frame that cannot be right (oversize or empty); an oversize length is
 * refused as soon as its 4 header bytes are in, so a hostile peer never makes it buffer more than
 * one frame. Not thread-safe; one per connection.
 */
public final class FrameReader {
  /** Bytes of the length prefix. */
  public static final int HEADER_BYTES = 4;
  /** The largest payload, 64 KiB. */
  public static final int MAX_PAYLOAD_BYTES = 65536;

  /** What {@link #next()} found. */
  public enum Status {
    /** No whole frame buffered; feed more bytes. */
    NEED_MORE,
    /** {@link #payload()} holds the next frame's payload. */
    FRAME,
    /** The stream is broken; {@link #refusal()} says why; every later call returns REFUSED. */
    REFUSED
  }

  /** Compacts the buffer once the consumed prefix is at least this large (bytes). */
  private static final int COMPACT_THRESHOLD = 16 * 1024;

  private byte[] buffer = new byte[1024];
  private int start; // first byte not yet returned
  private int end; // one past the last byte buffered
  private byte[] payload = new byte[0];
  private FrameRefusal refusal;
  private long refusedLength;

  /** Appends received bytes {@code bytes[offset, offset + length)}; ignored after a refusal. */
  public void feed(byte[] bytes, int offset, int length) {
    if (offset < 0 || length < 0 || offset > bytes.length - length) {
      throw new IndexOutOfBoundsException(
          "feed(" + offset + ", " + length + ") of " + bytes.length);
    }
    if (refusal != null || length == 0) return;
    if (start >= COMPACT_THRESHOLD || (start > 0 && start == end)) {
      System.arraycopy(buffer, start, buffer, 0, end - start);
      end -= start;
      start = 0;
    }
    if (buffer.length - end < length) {
      buffer = Arrays.copyOf(buffer, Math.max(buffer.length * 2, end + length));
    }
    System.arraycopy(bytes, offset, buffer, end, length);
    end += length;
  }

  /** Appends all of {@code bytes}. */
  public void feed(byte[] bytes) {
    feed(bytes, 0, bytes.length);
  }

  /** Takes the next whole frame, if any; its payload is then {@link #payload()}. */
  public Status next() {
    if (refusal != null) return Status.REFUSED;
    if (buffered() < HEADER_BYTES) return Status.NEED_MORE;
    long length = readLength(buffer, start);
    if (length == 0 || length > MAX_PAYLOAD_BYTES) {
      refusal = length == 0 ? FrameRefusal.EMPTY : FrameRefusal.OVERSIZE;
      refusedLength = length;
      buffer = new byte[0];
      start = 0;
      end = 0;
      return Status.REFUSED;
    }
    if (buffered() - HEADER_BYTES < length) return Status.NEED_MORE;
    int from = start + HEADER_BYTES;
    payload = Arrays.copyOfRange(buffer, from, from + (int) length);
    start = from + (int) length;
    return Status.FRAME;
  }

  /** The payload of the frame the last {@link #next()} returned FRAME for. */
  public byte[] payload() {
    return payload;
  }

  /** Why the stream was refused, or null while it is not. */
  public FrameRefusal refusal() {
    return refusal;
  }

  /** The length the peer declared for the refused frame, 0 if none was refused. */
  public long refusedLength() {
    return refusedLength;
  }

  /** Bytes buffered and not yet returned. */
  public int buffered() {
    return end - start;
  }

  private static long readLength(byte[] bytes, int at) {
    return ((bytes[at] & 0xFFL) << 24) | ((bytes[at + 1] & 0xFFL) << 16)
        | ((bytes[at + 2] & 0xFFL) << 8) | (bytes[at + 3] & 0xFFL);
  }
}
