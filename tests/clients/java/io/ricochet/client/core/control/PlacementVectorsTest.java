package io.ricochet.client.core.control;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotNull;

import io.ricochet.client.core.FrameReader;
import io.ricochet.client.testing.Vectors;
import io.ricochet.wire.ControlProto.ErrorCode;
import io.ricochet.wire.ControlProto.ServerMessage;
import java.nio.charset.StandardCharsets;
import org.junit.jupiter.api.Test;

/**
 * tests/vectors/control_frames.txt's placement records, written by the C++ end: each find_match
 * reply decodes to the {@link Assignment} it carries, field for field, and each placement error
 * to its code.
 */
class PlacementVectorsTest {
  private static ServerMessage parse(byte[] frame) throws Exception {
    FrameReader reader = new FrameReader();
    reader.feed(frame);
    assertEquals(FrameReader.Status.FRAME, reader.next());
    return ServerMessage.parseFrom(reader.payload());
  }

  @Test
  void everyAssignmentOfTheCppEndDecodesToTheSameFields() throws Exception {
    int assignments = 0;
    int onThisServer = 0;
    for (Vectors.Record record : Vectors.read("control_frames")) {
      if (!record.kind.equals("assignment")) continue;
      ++assignments;
      ServerMessage message = parse(record.bytes("bytes"));
      assertEquals(ServerMessage.BodyCase.FIND_MATCH, message.getBodyCase(), record.toString());
      Assignment.Result result = Assignment.of(message.getFindMatch().getAssignment(), 1_000);
      Assignment assignment = result.assignment();
      assertNotNull(assignment, record + ": " + result.detail());
      assertEquals(new String(record.bytes("connection"), StandardCharsets.UTF_8),
          assignment.connection(), record.toString());
      assertEquals(record.word("host"), assignment.host(), record.toString());
      assertEquals(record.number("control_port"), assignment.controlPort(), record.toString());
      assertEquals(record.number("game_port"), assignment.gamePort(), record.toString());
      assertEquals(record.word("certificate_sha256"), assignment.certificateSha256());
      assertEquals(record.number("match_id"), assignment.matchId(), record.toString());
      assertEquals(record.word("mode"), assignment.mode(), record.toString());
      assertEquals(
          record.has("map") ? record.word("map") : "", assignment.map(), record.toString());
      assertArrayEquals(record.bytes("ticket"), assignment.ticket(), record.toString());
      assertEquals(record.number("ticket_expires_in_ms"), assignment.ticketExpiresInMs());
      assertEquals(1_000 + record.number("ticket_expires_in_ms"), assignment.expiresAtMs());
      assertEquals(record.number("on_this_server") == 1, assignment.onThisServer());
      if (assignment.onThisServer()) ++onThisServer;
    }
    assertEquals(3, assignments, "elsewhere, on this server, on an IPv6 host");
    assertEquals(1, onThisServer);
  }

  @Test
  void everyPlacementErrorOfTheCppEndDecodesToItsCode() throws Exception {
    int errors = 0;
    for (Vectors.Record record : Vectors.read("control_frames")) {
      if (!record.kind.equals("placement_error")) continue;
      ++errors;
      ServerMessage message = parse(record.bytes("bytes"));
      assertEquals(ServerMessage.BodyCase.ERROR, message.getBodyCase(), record.toString());
      ErrorCode code = message.getError().getCode();
      assertEquals(record.word("code"), code.name(), record.toString());
      assertEquals(record.number("value"), code.getNumber(), record.toString());
    }
    assertEquals(5, errors, "NO_SERVER_AVAILABLE .. EXPIRED_TICKET");
  }
}
