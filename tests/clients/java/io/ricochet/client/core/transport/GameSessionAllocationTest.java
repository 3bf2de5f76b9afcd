package io.ricochet.client.core.transport;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.core.game.GameSession;
import io.ricochet.client.core.game.GameSessionListener;
import io.ricochet.client.core.game.InputState;
import io.ricochet.client.core.game.ServerPayloadReader;
import io.ricochet.client.core.snapshot.QuantizationSpec;
import io.ricochet.client.core.snapshot.SnapshotView;
import io.ricochet.client.testing.Vectors;
import io.ricochet.wire.GameProto.PlayerStatus;
import io.ricochet.wire.GameProto.ServerPayload;
import io.ricochet.wire.SnapshotProto.Quantization;
import io.ricochet.wire.SnapshotProto.Snapshot;
import java.lang.management.ManagementFactory;
import java.util.ArrayList;
import java.util.List;
import org.junit.jupiter.api.Test;

/**
 * A warm game session allocates nothing per received snapshot payload or per input tick: sealed
 * ServerPayloads carrying the 64-player vector stream (ticks moved on each round by a multiple of
 * the ring) are received, decoded and handed to the listener, and one ClientPayload is sealed per
 * tick, with 0 bytes allocated on the thread, measured with com.sun.management.ThreadMXBean as the
 * snapshot decoder's allocation test does. In this package for {@link FakeServer}.
 */
class GameSessionAllocationTest {
  private static final long ROUND_TICKS = 1L << 20; // a multiple of the ring's 64 slots
  private static final long TICK_US = 16_667;
  private static final int WARM_ROUNDS = 6;
  private static final int MEASURED_ROUNDS = 3;

  private final com.sun.management.ThreadMXBean threads =
      (com.sun.management.ThreadMXBean) ManagementFactory.getThreadMXBean();
  private final FakeServer server = new FakeServer();
  private long snapshots;
  private long entitiesSeen;
  private long nowUs = 1_000_000;

  @Test
  void aWarmSessionAllocatesNothingPerSnapshotOrInput() throws Exception {
    assertTrue(threads.isThreadAllocatedMemorySupported());
    threads.setThreadAllocatedMemoryEnabled(true);
    List<Vectors.Record> records = Vectors.read("snapshots_players64");
    QuantizationSpec spec =
        QuantizationSpec.fromWire(Quantization.parseFrom(records.get(0).bytes("bytes")));
    List<Snapshot> stream = new ArrayList<>();
    for (Vectors.Record record : records) {
      if (record.kind.equals("snapshot")) stream.add(Snapshot.parseFrom(record.bytes("bytes")));
    }
    GameSession session =
        new GameSession(FakeServer.grant(5), spec, 60, 60, 4, new GameSessionListener() {
          @Override
          public void onSnapshot(SnapshotView view, ServerPayloadReader payload) {
            ++snapshots;
            entitiesSeen += view.count() + payload.status().ammoCount();
          }
        }, nowUs);
    session.outbox().clear();
    deliver(session, server.challenge());
    deliver(session, server.keepAlive());
    assertEquals(ConnectionState.CONNECTED, session.state());
    InputState input = new InputState();
    input.set(0.5f, 1f, 0.25f, 0f, InputState.BUTTON_FIRE, 1);
    session.setInput(input);

    int round = 0;
    for (int warm = 0; warm < WARM_ROUNDS; ++warm) {
      byte[][] datagrams = round(stream, round++);
      assertEquals(datagrams.length, play(session, datagrams));
    }
    long allocated = Long.MAX_VALUE;
    for (int measured = 0; measured < MEASURED_ROUNDS; ++measured) {
      byte[][] datagrams = round(stream, round++);
      long before = threads.getThreadAllocatedBytes(Thread.currentThread().getId());
      long accepted = play(session, datagrams);
      long after = threads.getThreadAllocatedBytes(Thread.currentThread().getId());
      assertEquals(datagrams.length, accepted, "every snapshot accepted");
      allocated = Math.min(allocated, after - before);
    }
    assertTrue(entitiesSeen > 0);
    assertTrue(session.inputsSent() >= (long) stream.size() * (WARM_ROUNDS + MEASURED_ROUNDS));
    assertEquals(0, allocated, "bytes allocated over " + stream.size() + " payloads and ticks");
  }

  /** Receives each datagram and runs one input tick after it; the snapshots accepted. */
  private long play(GameSession session, byte[][] datagrams) {
    long before = snapshots;
    for (byte[] datagram : datagrams) {
      session.receive(datagram, datagram.length, nowUs);
      session.outbox().clear();
      nowUs += TICK_US;
      session.update(nowUs);
      session.outbox().clear();
    }
    return snapshots - before;
  }

  private void deliver(GameSession session, byte[] datagram) {
    session.receive(datagram, datagram.length, nowUs);
    session.outbox().clear();
  }

  /** The stream as sealed payloads with its ticks moved on by {@code round} rounds. */
  private byte[][] round(List<Snapshot> stream, int round) {
    byte[][] datagrams = new byte[stream.size()][];
    for (int i = 0; i < stream.size(); ++i) {
      Snapshot snapshot = stream.get(i);
      int tick = (int) ((snapshot.getTick() & 0xFFFFFFFFL) + round * ROUND_TICKS);
      ServerPayload payload =
          ServerPayload.newBuilder()
              .setSnapshot(snapshot.toBuilder().setTick(tick))
              .setServerTick(tick)
              .setYourEntityId(3)
              .setStatus(PlayerStatus.newBuilder().setHealth(80).addAmmo(10).addAmmo(2).addAmmo(1))
              .build();
      datagrams[i] = server.payload(new int[0], new byte[0][], payload.toByteArray());
    }
    return datagrams;
  }
}
