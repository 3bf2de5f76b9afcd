package io.ricochet.client.core.transport;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.core.game.GameSession;
import io.ricochet.client.core.game.GameSessionListener;
import io.ricochet.client.core.game.InputState;
import io.ricochet.client.core.game.PayloadRefusal;
import io.ricochet.client.core.snapshot.QuantizationSpec;
import io.ricochet.wire.GameProto.ChatMessage;
import io.ricochet.wire.GameProto.ClientPayload;
import io.ricochet.wire.GameProto.GameEvent;
import io.ricochet.wire.GameProto.ServerPayload;
import io.ricochet.wire.SnapshotProto.Snapshot;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;
import org.junit.jupiter.api.Test;

/**
 * The sans-IO game session (io.ricochet.client.core.game) over the fake server end, with fake
 * time: one ClientPayload per tick at the match's rate, the last four inputs repeated oldest
 * first, refusals counted, events delivered. In this package for {@link FakeServer}.
 */
class GameSessionTicksTest {
  private static final long START_US = 5_000_000;

  private final List<GameEvent> events = new ArrayList<>();
  private final List<DisconnectReason> ends = new ArrayList<>();
  private final FakeServer server = new FakeServer();
  private final GameSession session = new GameSession(
      FakeServer.grant(5), QuantizationSpec.defaults(), 60, 60, 4, new GameSessionListener() {
        @Override
        public void onEvent(GameEvent event) {
          events.add(event);
        }

        @Override
        public void onDisconnected(DisconnectReason reason) {
          ends.add(reason);
        }
      }, START_US);

  /** The ClientPayloads the session sent since the last call (other packets skipped). */
  private List<ClientPayload> sent() throws Exception {
    List<ClientPayload> payloads = new ArrayList<>();
    Outbox outbox = session.outbox();
    for (int i = 0; i < outbox.size(); ++i) {
      if (!server.open(outbox.datagram(i), outbox.length(i))) continue;
      if (server.openedType != PacketType.PAYLOAD) continue;
      byte[] body = server.openedBody;
      int at = Packets.PAYLOAD_FIXED_BYTES; // no reliable messages from this client
      payloads.add(ClientPayload.parseFrom(Arrays.copyOfRange(body, at, body.length)));
    }
    outbox.clear();
    return payloads;
  }

  private void deliver(byte[] datagram, long nowUs) {
    session.receive(datagram, datagram.length, nowUs);
  }

  private void connect() throws Exception {
    session.outbox().clear();
    deliver(server.challenge(), START_US);
    session.outbox().clear();
    deliver(server.keepAlive(), START_US);
    assertEquals(ConnectionState.CONNECTED, session.state());
  }

  @Test
  void sendsOneInputPerTickRepeatingTheLastFour() throws Exception {
    connect();
    InputState input = new InputState();
    List<ClientPayload> payloads = new ArrayList<>();
    long now = START_US;
    for (int step = 0; step < 60; ++step) {
      input.set(0f, step / 60f, 0f, 0f, 0, 0);
      session.setInput(input);
      long wake = session.nextWakeUs();
      assertTrue(wake >= now && wake <= now + 16_667, "wakes at " + wake + " after " + now);
      now = wake;
      session.update(now);
      payloads.addAll(sent());
    }
    assertEquals(60, payloads.size());
    assertEquals(60, session.inputsSent());
    for (int n = 0; n < payloads.size(); ++n) {
      ClientPayload payload = payloads.get(n);
      assertEquals(Math.min(n + 1, 4), payload.getInputsCount(), "payload " + n);
      for (int i = 0; i < payload.getInputsCount(); ++i) {
        int sequence = n + 2 - payload.getInputsCount() + i;
        assertEquals(sequence, payload.getInputs(i).getSequence());
        assertEquals(Math.round((sequence - 1) / 60f * 127), payload.getInputs(i).getMoveForward());
      }
      assertEquals(0, payload.getAckSnapshotTick(), "no snapshot decoded");
    }
    // A stalled thread sends the one input due, not a burst of the ticks it missed.
    session.update(now + 500_000);
    assertEquals(1, sent().size());
    assertTrue(session.nextWakeUs() > now + 500_000);
  }

  @Test
  void countsWhatItRefusesAndDeliversEvents() throws Exception {
    connect();
    session.update(START_US);
    sent();
    byte[] garbage = {(byte) 0xFF, (byte) 0xFF};
    deliver(server.payload(new int[0], new byte[0][], garbage), START_US + 1000);
    ServerPayload mismatch = ServerPayload.newBuilder()
                                 .setServerTick(12)
                                 .setSnapshot(Snapshot.newBuilder().setTick(11))
                                 .build();
    deliver(server.payload(new int[0], new byte[0][], mismatch.toByteArray()), START_US + 2000);
    ServerPayload unsent = ServerPayload.newBuilder().setLastInputSequence(99).build();
    deliver(server.payload(new int[0], new byte[0][], unsent.toByteArray()), START_US + 3000);
    GameEvent chat =
        GameEvent.newBuilder()
            .setChat(ChatMessage.newBuilder().setEntityId(3).setName("a").setText("hi"))
            .build();
    deliver(server.payload(
                new int[] {0, 1}, new byte[][] {{(byte) 0xFF}, chat.toByteArray()}, new byte[0]),
        START_US + 4000);
    assertEquals(1, session.refusals(PayloadRefusal.MALFORMED_PAYLOAD));
    assertEquals(1, session.refusals(PayloadRefusal.SNAPSHOT_TICK_MISMATCH));
    assertEquals(1, session.refusals(PayloadRefusal.UNSENT_INPUT_ACKED));
    assertEquals(1, session.refusals(PayloadRefusal.MALFORMED_EVENT));
    assertEquals(1, events.size());
    assertEquals("hi", events.get(0).getChat().getText());
    assertEquals(0, session.snapshotsReceived());
    assertEquals(ConnectionState.CONNECTED, session.state());

    session.disconnect(START_US + 5000);
    assertEquals(Arrays.asList(DisconnectReason.REQUESTED), ends);
    assertEquals(Long.MAX_VALUE, session.nextWakeUs());
  }
}
