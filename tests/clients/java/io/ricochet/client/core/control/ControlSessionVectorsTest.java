package io.ricochet.client.core.control;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.testing.Hex;
import io.ricochet.client.testing.Vectors;
import io.ricochet.wire.ControlProto.ClientMessage;
import io.ricochet.wire.ControlProto.ServerMessage;
import java.util.ArrayList;
import java.util.List;
import java.util.Locale;
import org.junit.jupiter.api.Test;

/**
 * tests/vectors/control_session.txt, written by the C++ end (proto::ControlClient): every scenario
 * replayed step by step on a {@link ControlSession} gives the same frames, events and states.
 */
class ControlSessionVectorsTest {
  /** A record the client produces after a step, in the file's words. */
  private static String expected(Vectors.Record record) {
    switch (record.kind) {
      case "transmit":
        return "transmit bytes=" + record.word("bytes");
      case "reply":
        return "reply id=" + record.word("id") + " kind=" + record.word("kind") + " body="
            + record.word("body") + (record.has("code") ? " code=" + record.word("code") : "");
      case "match_results":
        return "match_results match_id=" + record.word("match_id");
      case "closed":
        return "closed reason=" + record.word("reason")
            + (record.has("code") ? " code=" + record.word("code") : "");
      case "state":
        return "state value=" + record.word("value") + " pending=" + record.word("pending");
      default:
        throw new IllegalArgumentException("not an outcome: " + record);
    }
  }

  /** What the Java session produced after a step, in the file's words. */
  private static List<String> outcomes(ControlSession session) {
    List<String> out = new ArrayList<>();
    byte[] bytes = session.pollTransmit();
    if (bytes != null) out.add("transmit bytes=" + Hex.encode(bytes));
    ControlEvent event;
    while ((event = session.pollEvent()) != null) {
      if (event instanceof ControlEvent.Reply) {
        ControlEvent.Reply reply = (ControlEvent.Reply) event;
        ServerMessage message = reply.message();
        out.add("reply id=" + reply.requestId() + " kind=" + reply.kind().counterName()
            + " body=" + message.getBodyCase().name().toLowerCase(Locale.ROOT)
            + (reply.isError() ? " code=" + message.getError().getCode().name() : ""));
      } else if (event instanceof ControlEvent.MatchResultsArrived) {
        out.add("match_results match_id="
            + ((ControlEvent.MatchResultsArrived) event).results().getMatchId());
      } else {
        ControlEvent.Closed closed = (ControlEvent.Closed) event;
        out.add("closed reason=" + closed.reason().counterName()
            + (closed.serverError() != null ? " code=" + closed.serverError().getCode().name()
                                            : ""));
      }
    }
    out.add("state value=" + session.state().counterName() + " pending=" + session.pending());
    return out;
  }

  @Test
  void everyScenarioOfTheCppClientPlaysTheSameInJava() throws Exception {
    List<Vectors.Record> records = Vectors.read("control_session");
    ControlSession session = null;
    String scenario = null;
    List<String> want = new ArrayList<>();
    List<String> got = new ArrayList<>();
    int scenarios = 0;
    int steps = 0;
    for (Vectors.Record record : records) {
      switch (record.kind) {
        case "scenario":
          scenario = record.word("name");
          session = new ControlSession(0);
          want.add("scenario " + scenario);
          got.add("scenario " + scenario);
          ++scenarios;
          continue;
        case "request": {
          ++steps;
          ClientMessage message = ClientMessage.parseFrom(record.bytes("message"));
          RequestResult result = session.request(message, record.number("at_ms"));
          if (record.has("id")) {
            assertTrue(result.queued(), scenario + " " + record + ": " + result);
            assertEquals(record.number("id"), result.requestId(), scenario + " " + record);
          } else {
            assertEquals(
                record.word("refusal"), result.refusal().counterName(), scenario + " " + record);
          }
          got.addAll(outcomes(session));
          continue;
        }
        case "receive": {
          ++steps;
          byte[] bytes = record.bytes("bytes");
          session.receive(bytes, 0, bytes.length);
          got.addAll(outcomes(session));
          continue;
        }
        case "update":
          ++steps;
          session.update(record.number("at_ms"));
          got.addAll(outcomes(session));
          continue;
        default:
          want.add(expected(record));
      }
    }
    assertEquals(String.join("\n", want), String.join("\n", got));
    assertTrue(scenarios >= 10, scenarios + " scenarios");
    assertTrue(steps >= 60, steps + " steps");
  }
}
