package io.ricochet.client.core;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import com.google.protobuf.MessageLite;
import io.ricochet.client.testing.Vectors;
import io.ricochet.wire.ControlProto.ClientMessage;
import io.ricochet.wire.ControlProto.ServerMessage;
import java.util.List;
import java.util.Locale;
import org.junit.jupiter.api.Test;

/** tests/vectors/control_frames.txt, written by the C++ end: read, parsed and written back. */
class ControlFramesVectorsTest {
  @Test
  void everyFrameOfTheCppEndReadsParsesAndWritesBackTheSameBytes() throws Exception {
    List<Vectors.Record> records = Vectors.read("control_frames");
    int frames = 0;
    for (Vectors.Record record : records) {
      if (!record.kind.equals("frame")) continue;
      ++frames;
      byte[] bytes = record.bytes("bytes");
      FrameReader reader = new FrameReader();
      reader.feed(bytes);
      assertEquals(FrameReader.Status.FRAME, reader.next(), record.toString());
      assertEquals(0, reader.buffered(), record.toString());
      MessageLite message;
      String body;
      long requestId;
      if (record.word("direction").equals("client")) {
        ClientMessage client = ClientMessage.parseFrom(reader.payload());
        body = client.getBodyCase().name();
        requestId = client.getRequestId() & 0xFFFFFFFFL;
        message = client;
      } else {
        ServerMessage server = ServerMessage.parseFrom(reader.payload());
        body = server.getBodyCase().name();
        requestId = server.getRequestId() & 0xFFFFFFFFL;
        message = server;
      }
      assertEquals(record.word("body").toUpperCase(Locale.ROOT), body, record.toString());
      assertEquals(record.number("request_id"), requestId, record.toString());
      assertArrayEquals(bytes, Frames.frame(message), record.toString());
    }
    assertTrue(frames >= 20, "every body of both directions: " + frames);
  }

  @Test
  void theHeadersTheCppEndRefusesAreRefusedForTheSameReason() throws Exception {
    int refused = 0;
    for (Vectors.Record record : Vectors.read("control_frames")) {
      if (!record.kind.equals("refused")) continue;
      ++refused;
      FrameReader reader = new FrameReader();
      reader.feed(record.bytes("header"));
      assertEquals(FrameReader.Status.REFUSED, reader.next(), record.toString());
      assertEquals(record.word("reason"), reader.refusal().counterName(), record.toString());
      assertEquals(record.number("length"), reader.refusedLength(), record.toString());
    }
    assertEquals(3, refused);
  }
}
