package io.ricochet.client;

import static io.ricochet.client.ClientTesting.await;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.core.transport.DisconnectReason;
import io.ricochet.client.testing.RealServer;
import io.ricochet.client.testing.ServerProcess;
import io.ricochet.wire.GameProto.GameEvent;
import java.util.List;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.Timeout;
import org.junit.jupiter.api.extension.RegisterExtension;

/**
 * A phone's network change against the real server: mid-match the game connection moves to a new
 * local port with a fresh token and keeps its entity, where it stood; the server says the player
 * reconnected. Bounded waits only.
 */
@Timeout(value = 90, unit = TimeUnit.SECONDS)
class GameReconnectTest {
  @RegisterExtension final RealServer realServer = RealServer.arena(ClientTesting.FAST_ACCOUNTS);

  private static final long WAIT_MS = ClientTesting.WAIT_MS;

  /** The own entity in one snapshot. */
  private static final class Own {
    final long entity;
    final float x;
    final float z;

    Own(long entity, float x, float z) {
      this.entity = entity;
      this.x = x;
      this.z = z;
    }
  }

  private static final class Recorder implements GameListener {
    final List<Own> own = new CopyOnWriteArrayList<>();
    final List<GameEvent> events = new CopyOnWriteArrayList<>();
    final List<DisconnectReason> reconnects = new CopyOnWriteArrayList<>();
    final AtomicInteger connections = new AtomicInteger();
    final CountDownLatch disconnected = new CountDownLatch(1);
    volatile DisconnectReason reason;

    @Override
    public void onConnected() {
      connections.incrementAndGet();
    }

    @Override
    public void onSnapshot(GameSnapshot snapshot) {
      int index = snapshot.indexOf(snapshot.yourEntityId());
      if (index < 0) return;
      own.add(new Own(
          snapshot.yourEntityId(), snapshot.positionM(index, 0), snapshot.positionM(index, 2)));
    }

    @Override
    public void onEvent(GameEvent event) {
      events.add(event);
    }

    @Override
    public void onReconnecting(DisconnectReason why) {
      reconnects.add(why);
    }

    @Override
    public void onDisconnected(DisconnectReason reason) {
      this.reason = reason;
      disconnected.countDown();
    }
  }

  /** Polls {@code condition} every 10 ms for at most {@link #WAIT_MS}. */
  private static boolean eventually(Recorder recorder, java.util.function.BooleanSupplier condition)
      throws InterruptedException {
    long deadline = System.currentTimeMillis() + WAIT_MS;
    while (!condition.getAsBoolean()) {
      if (System.currentTimeMillis() > deadline) return false;
      recorder.disconnected.await(10, TimeUnit.MILLISECONDS);
    }
    return true;
  }

  private static boolean rejoined(List<GameEvent> events, long entity) {
    for (GameEvent event : events) {
      if (event.getEventCase() == GameEvent.EventCase.PLAYER_JOINED
          && event.getPlayerJoined().getEntityId() == entity
          && event.getPlayerJoined().getReconnected()) {
        return true;
      }
    }
    return false;
  }

  @Test
  void aNewLocalPortMidMatchKeepsTheEntity() throws Exception {
    Recorder recorder = new Recorder();
    ServerProcess server = realServer.get();
    RicochetClient client = ClientTesting.signedIn(server, "java_roamer");
    try {
      long matchId = await(client.listMatches()).get(0).matchId();
      GameConnection game = await(client.joinMatch(matchId, recorder));
      int firstPort = game.localPort();
      assertTrue(eventually(recorder, () -> recorder.own.size() >= 30), "no snapshots");
      long entity = recorder.own.get(0).entity;
      assertTrue(entity > 0);
      assertTrue(!rejoined(recorder.events, entity), "rejoined before a reconnect");

      game.reconnect();
      assertTrue(eventually(recorder, () -> recorder.connections.get() == 2), "not back");
      int before = recorder.own.size();
      Own last = recorder.own.get(before - 1);
      assertTrue(eventually(recorder, () -> recorder.own.size() >= before + 30),
          "no snapshots after the reconnect");
      assertNotEquals(firstPort, game.localPort());
      assertEquals(1, recorder.reconnects.size());
      assertEquals(null, recorder.reconnects.get(0), "asked by the app");
      assertTrue(eventually(recorder, () -> rejoined(recorder.events, entity)),
          "no PlayerJoined{reconnected} for entity " + entity + ": " + recorder.events);
      Own after = recorder.own.get(recorder.own.size() - 1);
      assertEquals(entity, after.entity, "the same entity");
      double moved = Math.hypot(after.x - last.x, after.z - last.z);
      assertTrue(moved < 0.5, "the entity moved " + moved + " m: not where it stood");
      assertTrue(game.isOpen());
      assertEquals(1, recorder.disconnected.getCount(), "ended: " + recorder.reason);

      game.close();
      assertEquals(DisconnectReason.REQUESTED, game.disconnectReason());
    } finally {
      client.close();
    }
    for (Thread thread : Thread.getAllStackTraces().keySet()) {
      assertTrue(!thread.isAlive() || !thread.getName().equals("ricochet-game"), "left behind");
    }
  }
}
