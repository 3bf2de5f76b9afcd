package io.ricochet.client.core;

import com.google.protobuf.CodedOutputStream;
import com.google.protobuf.MessageLite;
import java.io.IOException;

/** Writes control frames: the 4-byte big-endian length, then the message (PROTOCOL.md). */
public final class Frames {
  private Frames() {}

  /**
   * One frame holding {@code message}, or null when its encoding is empty or over {@link
   * FrameReader#MAX_PAYLOAD_BYTES} (a frame the server would refuse).
   */
  public static byte[] frame(MessageLite message) {
    int size = message.getSerializedSize();
    if (size == 0 || size > FrameReader.MAX_PAYLOAD_BYTES) return null;
    byte[] out = new byte[FrameReader.HEADER_BYTES + size];
    out[0] = (byte) (size >>> 24);
    out[1] = (byte) (size >>> 16);
    out[2] = (byte) (size >>> 8);
    out[3] = (byte) size;
    CodedOutputStream stream = CodedOutputStream.newInstance(out, FrameReader.HEADER_BYTES, size);
    try {
      message.writeTo(stream);
      stream.checkNoSpaceLeft();
    } catch (IOException e) {
      throw new IllegalStateException("a message changed while it was framed", e);
    }
    return out;
  }
}
