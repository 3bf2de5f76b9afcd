package io.ricochet.client.core.transport;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.testing.Hex;
import io.ricochet.client.testing.Vectors;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;
import org.junit.jupiter.api.Test;

/**
 * tests/vectors/game_packets.txt, written by the C++ end (tools/vectors/game_packets_vectors.cpp):
 * the Java client seals and opens the same bytes, keeps the same replay window, and driven through
 * the C++ client's scripted sessions sends the same datagrams, reports the same events and drops
 * the same datagrams for the same reasons.
 */
class GamePacketsVectorsTest {
  private static PacketType type(String name) {
    for (PacketType type : PacketType.values()) {
      if (type.logName().equals(name)) return type;
    }
    throw new IllegalArgumentException(name);
  }

  @Test
  void sealsAndOpensEveryPacketOfTheCppEndByteForByte() throws Exception {
    int sealed = 0;
    for (Vectors.Record record : Vectors.read("game_packets")) {
      if (!record.kind.equals("sealed")) continue;
      ++sealed;
      byte[] body = record.bytes("body");
      byte[] expected = record.bytes("packet");
      PacketAead aead = new PacketAead(record.bytes("key"), record.number("protocol_id"));
      byte[] packet = new byte[Packets.MAX_DATAGRAM_BYTES];
      packet[0] = (byte) type(record.word("type")).wireValue();
      Packets.putU64(packet, 1, record.number("sequence"));
      System.arraycopy(body, 0, packet, Packets.HEADER_BYTES, body.length);
      int length = aead.seal(packet, Packets.HEADER_BYTES + body.length);
      assertEquals(
          Hex.encode(expected), Hex.encode(Arrays.copyOf(packet, length)), record.toString());

      byte[] opened = new byte[Packets.MAX_DATAGRAM_BYTES];
      int openedBytes = aead.open(expected, expected.length, opened);
      assertArrayEquals(body, Arrays.copyOf(opened, openedBytes), record.toString());
      for (int at = 0; at < expected.length; ++at) { // any bit changed anywhere: refused
        byte[] tampered = expected.clone();
        tampered[at] ^= 0x20;
        assertEquals(-1, aead.open(tampered, tampered.length, opened), record + " byte " + at);
      }
      PacketAead otherProtocol =
          new PacketAead(record.bytes("key"), record.number("protocol_id") + 1);
      assertEquals(-1, otherProtocol.open(expected, expected.length, opened), record.toString());
    }
    assertEquals(10, sealed);
  }

  @Test
  void replayWindowAcceptsRefusesAndAcksAsTheCppOne() throws Exception {
    ReplayWindow window = new ReplayWindow();
    int checked = 0;
    for (Vectors.Record record : Vectors.read("game_packets")) {
      if (!record.kind.equals("replay")) continue;
      ++checked;
      long sequence = record.number("sequence");
      boolean accepted = !window.alreadyReceived(sequence);
      if (accepted) window.markReceived(sequence);
      assertEquals(record.number("accepted") == 1, accepted, record.toString());
      assertEquals(record.number("ack"), window.ack(), record.toString());
      assertEquals(record.number("ack_bits"), window.ackBits() & 0xFFFFFFFFL, record.toString());
      assertEquals(record.number("missing"), window.missing(), record.toString());
      assertEquals(record.number("late"), window.late(), record.toString());
    }
    assertTrue(checked > 20);
  }

  /** One scripted session's expectations since its last input. */
  private static final class Expected {
    final List<String> sends = new ArrayList<>();
    final List<String> events = new ArrayList<>();
    final List<String> drops = new ArrayList<>();
  }

  @Test
  void drivenThroughTheCppSessionsTheClientDoesWhatTheCppClientDid() throws Exception {
    List<String> sessions = new ArrayList<>();
    GameClient client = null;
    RecordingListener listener = new RecordingListener();
    Expected expected = new Expected();
    String context = "";
    int inputs = 0;
    for (Vectors.Record record : Vectors.read("game_packets")) {
      switch (record.kind) {
        case "session":
          sessions.add(record.word("name"));
          continue;
        case "client_sends":
          expected.sends.add(record.word("bytes"));
          continue;
        case "client_drop":
          expected.drops.add(record.word("reason"));
          continue;
        case "client_event":
          String kind = record.word("kind");
          if (record.has("bytes")) kind += " " + record.word("bytes");
          if (record.has("reason")) kind += " " + record.word("reason");
          expected.events.add(kind);
          continue;
        default:
          break;
      }
      if (!record.kind.startsWith("client_")) continue;
      // A new input: what the previous one made the client do must match, then the input.
      if (client != null) check(expected, client, listener, context);
      expected = new Expected();
      context = sessions.get(sessions.size() - 1) + ": " + record;
      ++inputs;
      switch (record.kind) {
        case "client_start":
          assertEquals(Packets.PROTOCOL_ID, record.number("protocol_id"));
          listener = new RecordingListener();
          client = new GameClient(
              new ConnectGrant(record.bytes("connect_token"), record.bytes("client_to_server_key"),
                  record.bytes("server_to_client_key"), (int) record.number("timeout_s"),
                  record.number("protocol_id")),
              listener, record.number("t_us"));
          break;
        case "client_update":
          long dueUs = client.nextUpdateUs();
          client.update(record.number("t_us"));
          // update() has work exactly when nextUpdateUs said so: it sends or ends, or does nothing.
          boolean worked = client.outbox().size() > 0 || !listener.events.isEmpty();
          assertEquals(dueUs <= record.number("t_us"), worked, "nextUpdateUs at " + context);
          break;
        case "client_receive":
          byte[] datagram = record.bytes("bytes");
          client.receive(datagram, datagram.length, record.number("t_us"));
          break;
        case "client_send_unreliable":
          byte[] payload = record.bytes("bytes");
          assertTrue(client.sendPayload(payload, 0, payload.length, record.number("t_us")));
          break;
        case "client_send_reliable":
          byte[] message = record.bytes("bytes");
          assertTrue(client.sendReliable(message, 0, message.length, record.number("t_us")));
          break;
        case "client_disconnect":
          client.disconnect(record.number("t_us"));
          break;
        case "client_end":
          assertEquals(record.word("state"), client.state().logName(), context);
          TransportCounters counters = client.counters();
          assertEquals(record.number("packets_in"), counters.packetsIn(), context);
          assertEquals(record.number("packets_out"), counters.packetsOut(), context);
          assertEquals(record.number("bytes_in"), counters.bytesIn(), context);
          assertEquals(record.number("bytes_out"), counters.bytesOut(), context);
          client = null;
          break;
        default:
          throw new AssertionError("unknown record " + record);
      }
    }
    assertEquals(Arrays.asList("handshake", "leave", "timeout", "denied", "silent"), sessions);
    assertTrue(inputs > 80, "inputs " + inputs);
  }

  private static void check(
      Expected expected, GameClient client, RecordingListener listener, String context) {
    assertEquals(
        expected.sends, RecordingListener.drain(client.outbox()), "sends after " + context);
    assertEquals(expected.drops, listener.drops, "drops after " + context);
    assertEquals(expected.events, listener.events, "events after " + context);
    listener.clear();
  }
}
