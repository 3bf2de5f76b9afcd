package io.ricochet.client.core;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNull;

import io.ricochet.wire.ControlProto.ClientMessage;
import io.ricochet.wire.ControlProto.Ping;
import java.util.Arrays;
import org.junit.jupiter.api.Test;

class FrameReaderTest {
  private static byte[] pingFrame(int requestId) {
    ClientMessage message = ClientMessage.newBuilder()
                                .setRequestId(requestId)
                                .setPing(Ping.newBuilder().setClientTimeUs(1234))
                                .build();
    return Frames.frame(message);
  }

  @Test
  void framesSplitAnywhereComeOutWholeAndInOrder() throws Exception {
    byte[] first = pingFrame(1);
    byte[] second = pingFrame(2);
    byte[] stream = new byte[first.length + second.length];
    System.arraycopy(first, 0, stream, 0, first.length);
    System.arraycopy(second, 0, stream, first.length, second.length);
    for (int split = 0; split <= stream.length; ++split) {
      FrameReader reader = new FrameReader();
      reader.feed(stream, 0, split);
      int seen = 0;
      while (reader.next() == FrameReader.Status.FRAME) {
        assertEquals(++seen, ClientMessage.parseFrom(reader.payload()).getRequestId());
      }
      reader.feed(stream, split, stream.length - split);
      while (reader.next() == FrameReader.Status.FRAME) {
        assertEquals(++seen, ClientMessage.parseFrom(reader.payload()).getRequestId());
      }
      assertEquals(2, seen, "split at " + split);
      assertEquals(0, reader.buffered());
    }
  }

  @Test
  void aFrameIsItsBigEndianLengthThenTheMessage() {
    byte[] frame = pingFrame(7);
    byte[] body = ClientMessage.newBuilder()
                      .setRequestId(7)
                      .setPing(Ping.newBuilder().setClientTimeUs(1234))
                      .build()
                      .toByteArray();
    assertArrayEquals(new byte[] {0, 0, 0, (byte) body.length}, Arrays.copyOf(frame, 4));
    assertArrayEquals(body, Arrays.copyOfRange(frame, 4, frame.length));
  }

  @Test
  void anOversizeLengthIsRefusedFromItsHeaderAlone() {
    FrameReader reader = new FrameReader();
    reader.feed(new byte[] {0, 1, 0, 1}); // 65537
    assertEquals(FrameReader.Status.REFUSED, reader.next());
    assertEquals(FrameRefusal.OVERSIZE, reader.refusal());
    assertEquals(65537, reader.refusedLength());
    assertEquals(0, reader.buffered());
    reader.feed(pingFrame(1));
    assertEquals(FrameReader.Status.REFUSED, reader.next(), "a refused stream stays refused");
    assertEquals(0, reader.buffered(), "nothing is buffered after a refusal");
  }

  @Test
  void anEmptyFrameIsRefused() {
    FrameReader reader = new FrameReader();
    reader.feed(new byte[] {0, 0, 0, 0});
    assertEquals(FrameReader.Status.REFUSED, reader.next());
    assertEquals(FrameRefusal.EMPTY, reader.refusal());
    assertEquals("frame_empty", reader.refusal().counterName());
  }

  @Test
  void theLargestPayloadIsAcceptedAndOneMoreIsNot() {
    FrameReader reader = new FrameReader();
    byte[] frame = new byte[4 + FrameReader.MAX_PAYLOAD_BYTES];
    frame[1] = 1; // 65536
    reader.feed(frame);
    assertEquals(FrameReader.Status.FRAME, reader.next());
    assertEquals(FrameReader.MAX_PAYLOAD_BYTES, reader.payload().length);
    assertNull(reader.refusal());
  }

  @Test
  void anEmptyMessageMakesNoFrame() {
    assertNull(Frames.frame(ClientMessage.getDefaultInstance()));
  }
}
