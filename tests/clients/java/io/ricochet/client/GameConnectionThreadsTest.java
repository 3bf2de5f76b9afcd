package io.ricochet.client;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertSame;
import static org.junit.jupiter.api.Assertions.assertTrue;

import com.google.protobuf.ByteString;
import io.ricochet.client.core.snapshot.QuantizationSpec;
import io.ricochet.client.core.transport.DisconnectReason;
import io.ricochet.client.core.transport.FakeGameServer;
import io.ricochet.wire.ControlProto.JoinMatchReply;
import io.ricochet.wire.GameProto.ChatMessage;
import io.ricochet.wire.GameProto.ClientPayload;
import io.ricochet.wire.GameProto.GameEvent;
import io.ricochet.wire.GameProto.Input;
import io.ricochet.wire.GameProto.ServerPayload;
import io.ricochet.wire.SnapshotProto.Snapshot;
import java.net.InetSocketAddress;
import java.util.List;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.ExecutionException;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.AfterEach;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.Timeout;

/**
 * The game connection's threads against a fake server on loopback (no real server): the
 * hand-off of inputs from any thread, of snapshots and events to the listener executor only, the
 * snapshot pool when the listener falls behind, and the end of the thread on close, on the
 * server's disconnect and on a handshake nobody answers. Every wait is bounded.
 */
@Timeout(value = 60, unit = TimeUnit.SECONDS)
class GameConnectionThreadsTest {
  private static final long WAIT_MS = 20_000;
  private static final byte[] EMPTY_STREAM = {(byte) 0xE0}; // PROTOCOL.md Snapshots §10

  private final ExecutorService executor =
      Executors.newSingleThreadExecutor(runnable -> new Thread(runnable, "app-listener"));
  private final FakeGameServer server;
  private final Recorder recorder = new Recorder();

  GameConnectionThreadsTest() throws Exception {
    server = new FakeGameServer();
  }

  @AfterEach
  void tearDown() throws Exception {
    server.close();
    executor.shutdownNow();
    assertTrue(executor.awaitTermination(10, TimeUnit.SECONDS));
  }

  private static final class Recorder implements GameListener {
    final List<String> wrongThreads = new CopyOnWriteArrayList<>();
    final List<Long> ticks = new CopyOnWriteArrayList<>();
    final List<GameEvent> events = new CopyOnWriteArrayList<>();
    final List<GameStats> stats = new CopyOnWriteArrayList<>();
    final CountDownLatch connected = new CountDownLatch(1);
    final java.util.concurrent.atomic.AtomicInteger connections =
        new java.util.concurrent.atomic.AtomicInteger();
    final List<String> reconnects = new CopyOnWriteArrayList<>();
    final CountDownLatch disconnected = new CountDownLatch(1);
    volatile CountDownLatch blockSnapshots;
    volatile DisconnectReason reason;

    private void onListenerThread() {
      String name = Thread.currentThread().getName();
      if (!name.equals("app-listener")) wrongThreads.add(name);
    }

    @Override
    public void onConnected() {
      onListenerThread();
      connections.incrementAndGet();
      connected.countDown();
    }

    @Override
    public void onReconnecting(DisconnectReason why) {
      onListenerThread();
      reconnects.add(String.valueOf(why));
    }

    @Override
    public void onSnapshot(GameSnapshot snapshot) {
      onListenerThread();
      ticks.add(snapshot.tick());
      CountDownLatch block = blockSnapshots;
      if (block != null) {
        try {
          block.await(WAIT_MS, TimeUnit.MILLISECONDS);
        } catch (InterruptedException e) {
          Thread.currentThread().interrupt();
        }
      }
    }

    @Override
    public void onEvent(GameEvent event) {
      onListenerThread();
      events.add(event);
    }

    @Override
    public void onStats(GameStats stats) {
      onListenerThread();
      this.stats.add(stats);
    }

    @Override
    public void onDisconnected(DisconnectReason reason) {
      onListenerThread();
      this.reason = reason;
      disconnected.countDown();
    }
  }

  private JoinTicket ticket(int timeoutS) {
    JoinMatchReply reply =
        JoinMatchReply.newBuilder()
            .setMatchId(1)
            .setUdpPort(server.port())
            .setConnectToken(ByteString.copyFrom(FakeGameServer.token()))
            .setClientToServerKey(ByteString.copyFrom(FakeGameServer.clientToServerKey()))
            .setServerToClientKey(ByteString.copyFrom(FakeGameServer.serverToClientKey()))
            .setTokenExpiresInMs(10_000)
            .setTimeoutS(timeoutS)
            .setQuantization(QuantizationSpec.defaults().toWire())
            .setTickRateHz(60)
            .setSnapshotRateHz(60)
            .build();
    JoinTicket ticket =
        JoinTicket.of("127.0.0.1", reply, System.nanoTime() / 1_000_000, new String[1]);
    assertNotNull(ticket);
    return ticket;
  }

  private CompletableFuture<GameConnection> start(int timeoutS) throws Exception {
    return GameConnection
        .create(new InetSocketAddress("127.0.0.1", server.port()), ticket(timeoutS), recorder,
            executor, System.nanoTime() / 1_000_000, null, null)
        .start();
  }

  private static void sendSnapshot(FakeGameServer server, long tick, long lastInput)
      throws Exception {
    ServerPayload payload = ServerPayload.newBuilder()
                                .setServerTick((int) tick)
                                .setLastInputSequence((int) lastInput)
                                .setYourEntityId(1)
                                .setSnapshot(Snapshot.newBuilder()
                                                 .setTick((int) tick)
                                                 .setEntities(ByteString.copyFrom(EMPTY_STREAM)))
                                .build();
    server.sendPayload(new int[0], new byte[0][], payload.toByteArray());
  }

  private static int gameThreads() {
    int count = 0;
    for (Thread thread : Thread.getAllStackTraces().keySet()) {
      if (thread.isAlive() && thread.getName().equals("ricochet-game")) ++count;
    }
    return count;
  }

  @Test
  void inputsFromAnyThreadSnapshotsAndEventsOnTheListenerExecutorAndCloseEndsTheThread()
      throws Exception {
    CompletableFuture<GameConnection> future = start(5);
    assertTrue(server.handshake(WAIT_MS), "no handshake");
    GameConnection game = future.get(WAIT_MS, TimeUnit.MILLISECONDS);
    assertTrue(recorder.connected.await(WAIT_MS, TimeUnit.MILLISECONDS));
    assertEquals(1, gameThreads());

    // Four threads set inputs at once, then one last value: it is what goes out.
    Thread[] writers = new Thread[4];
    for (int w = 0; w < writers.length; ++w) {
      final int writer = w;
      writers[w] = new Thread(() -> {
        for (int i = 0; i < 2000; ++i) {
          game.setInput(writer / 4f, -writer / 4f, i * 0.001f, 0f, GameConnection.BUTTON_FIRE, 1);
        }
      });
      writers[w].start();
    }
    for (Thread writer : writers) writer.join(WAIT_MS);
    game.setInput(0f, 0.5f, 1f, -0.25f, GameConnection.BUTTON_JUMP, 3);
    Input newest = null;
    long deadline = System.currentTimeMillis() + WAIT_MS;
    while (System.currentTimeMillis() < deadline) {
      ClientPayload payload = server.nextClientPayload(WAIT_MS);
      assertNotNull(payload);
      assertTrue(payload.getInputsCount() >= 1 && payload.getInputsCount() <= 4);
      for (int i = 1; i < payload.getInputsCount(); ++i) {
        assertEquals(
            payload.getInputs(i - 1).getSequence() + 1, payload.getInputs(i).getSequence());
      }
      newest = payload.getInputs(payload.getInputsCount() - 1);
      if (newest.getWeaponSlot() == 3) break;
    }
    assertNotNull(newest);
    assertEquals(64, newest.getMoveForward());
    assertEquals(1f, newest.getYaw());
    assertEquals(-0.25f, newest.getPitch());
    assertEquals(GameConnection.BUTTON_JUMP, newest.getButtons());

    // Snapshots and an event reach the listener in order; the client acknowledges the newest.
    for (long tick = 1; tick <= 30; ++tick) sendSnapshot(server, tick, newest.getSequence());
    GameEvent chat =
        GameEvent.newBuilder()
            .setChat(ChatMessage.newBuilder().setEntityId(1).setName("a").setText("hi"))
            .build();
    server.sendPayload(new int[] {0}, new byte[][] {chat.toByteArray()}, new byte[0]);
    deadline = System.currentTimeMillis() + WAIT_MS;
    ClientPayload acked = null;
    while (System.currentTimeMillis() < deadline) {
      acked = server.nextClientPayload(WAIT_MS);
      if (acked != null && acked.getAckSnapshotTick() == 30) break;
    }
    assertNotNull(acked);
    assertEquals(30, acked.getAckSnapshotTick());
    deadline = System.currentTimeMillis() + WAIT_MS;
    while (recorder.events.isEmpty() && System.currentTimeMillis() < deadline) {
      recorder.connected.await(10, TimeUnit.MILLISECONDS); // a bounded poll of the listener
    }
    assertEquals(1, recorder.events.size());
    assertEquals("hi", recorder.events.get(0).getChat().getText());
    for (int i = 1; i < recorder.ticks.size(); ++i) {
      assertTrue(recorder.ticks.get(i) > recorder.ticks.get(i - 1), "ticks " + recorder.ticks);
    }

    // A listener that falls behind: a few pooled snapshots wait, the rest are skipped, counted.
    CountDownLatch block = new CountDownLatch(1);
    recorder.blockSnapshots = block;
    sendSnapshot(server, 31, newest.getSequence());
    deadline = System.currentTimeMillis() + WAIT_MS;
    while (!recorder.ticks.contains(31L) && System.currentTimeMillis() < deadline) {
      block.await(10, TimeUnit.MILLISECONDS);
    }
    for (long tick = 32; tick <= 50; ++tick) sendSnapshot(server, tick, newest.getSequence());
    deadline = System.currentTimeMillis() + WAIT_MS;
    GameStats stats = null;
    while (System.currentTimeMillis() < deadline) {
      stats = game.stats();
      if (stats != null && stats.snapshotsReceived() == 50) break;
      block.await(10, TimeUnit.MILLISECONDS);
    }
    assertNotNull(stats);
    assertEquals(50, stats.snapshotsReceived(), "stats: " + stats);
    recorder.blockSnapshots = null;
    block.countDown();
    deadline = System.currentTimeMillis() + WAIT_MS; // the pooled ones are delivered now
    while (recorder.ticks.size() + stats.snapshotsSkipped() < 50
        && System.currentTimeMillis() < deadline) {
      recorder.disconnected.await(10, TimeUnit.MILLISECONDS);
    }
    assertEquals(50, recorder.ticks.size() + stats.snapshotsSkipped(), "ticks " + recorder.ticks);
    long lastDelivered = recorder.ticks.get(recorder.ticks.size() - 1);
    assertTrue(lastDelivered <= 31 + GameConnection.SNAPSHOT_POOL, "ticks " + recorder.ticks);
    // Once the listener caught up, the next snapshot is delivered again.
    sendSnapshot(server, 51, newest.getSequence());
    deadline = System.currentTimeMillis() + WAIT_MS;
    while (!recorder.ticks.contains(51L) && System.currentTimeMillis() < deadline) {
      recorder.disconnected.await(10, TimeUnit.MILLISECONDS);
    }
    assertTrue(recorder.ticks.contains(51L), "ticks " + recorder.ticks);
    assertTrue(stats.snapshotsSkipped() >= 50 - 31 - GameConnection.SNAPSHOT_POOL, "" + stats);

    // Close: the disconnect goes out, the listener hears REQUESTED, the thread is gone.
    game.close();
    assertFalse(game.isOpen());
    assertEquals(0, gameThreads());
    assertEquals(DisconnectReason.REQUESTED, server.awaitDisconnect(WAIT_MS));
    assertTrue(recorder.disconnected.await(WAIT_MS, TimeUnit.MILLISECONDS));
    assertEquals(DisconnectReason.REQUESTED, recorder.reason);
    assertEquals(DisconnectReason.REQUESTED, game.disconnectReason());
    game.close(); // idempotent
    assertTrue(recorder.wrongThreads.isEmpty(), "called on " + recorder.wrongThreads);
  }

  @Test
  void theServersDisconnectEndsTheThread() throws Exception {
    CompletableFuture<GameConnection> future = start(5);
    assertTrue(server.handshake(WAIT_MS));
    GameConnection game = future.get(WAIT_MS, TimeUnit.MILLISECONDS);
    server.sendDisconnect(DisconnectReason.KICKED);
    assertTrue(recorder.disconnected.await(WAIT_MS, TimeUnit.MILLISECONDS));
    assertEquals(DisconnectReason.KICKED, recorder.reason);
    long deadline = System.currentTimeMillis() + WAIT_MS;
    while (gameThreads() > 0 && System.currentTimeMillis() < deadline) {
      recorder.disconnected.await(10, TimeUnit.MILLISECONDS);
    }
    assertEquals(0, gameThreads());
    assertFalse(game.isOpen());
    assertTrue(recorder.wrongThreads.isEmpty(), "called on " + recorder.wrongThreads);
  }

  @Test
  void aHandshakeNobodyAnswersFailsTheFuture() throws Exception {
    CompletableFuture<GameConnection> future = start(1);
    try {
      future.get(WAIT_MS, TimeUnit.MILLISECONDS);
      throw new AssertionError("connected to nobody");
    } catch (ExecutionException e) {
      RicochetException failure = (RicochetException) e.getCause();
      assertSame(RicochetException.Kind.GAME_CONNECT_FAILED, failure.kind());
      assertSame(DisconnectReason.HANDSHAKE_TIMED_OUT, failure.gameReason());
    }
    assertTrue(recorder.disconnected.await(WAIT_MS, TimeUnit.MILLISECONDS));
    assertEquals(1, recorder.connected.getCount(), "never connected");
    assertEquals(DisconnectReason.HANDSHAKE_TIMED_OUT, recorder.reason);
    long deadline = System.currentTimeMillis() + WAIT_MS;
    while (gameThreads() > 0 && System.currentTimeMillis() < deadline) {
      recorder.disconnected.await(10, TimeUnit.MILLISECONDS);
    }
    assertEquals(0, gameThreads());
  }

  /** Polls {@code condition} every 10 ms for at most {@link #WAIT_MS}; its last value. */
  private boolean eventually(java.util.function.BooleanSupplier condition) throws Exception {
    long deadline = System.currentTimeMillis() + WAIT_MS;
    while (!condition.getAsBoolean()) {
      if (System.currentTimeMillis() > deadline) return false;
      recorder.disconnected.await(10, TimeUnit.MILLISECONDS);
    }
    return true;
  }

  @Test
  void aSilentServerOrTheAppsAskReconnectsFromANewPortWithAFreshTicket() throws Exception {
    java.util.concurrent.atomic.AtomicInteger tickets =
        new java.util.concurrent.atomic.AtomicInteger();
    CompletableFuture<GameConnection> future =
        GameConnection
            .create(new InetSocketAddress("127.0.0.1", server.port()), ticket(1), recorder,
                executor, System.nanoTime() / 1_000_000,
                ()
                    -> {
                  tickets.incrementAndGet();
                  return CompletableFuture.completedFuture(ticket(1));
                },
                null)
            .start();
    assertTrue(server.handshake(WAIT_MS));
    GameConnection game = future.get(WAIT_MS, TimeUnit.MILLISECONDS);
    int firstPort = game.localPort();

    // The server goes silent: after timeout_s (1 s) and a back-off, a new handshake, a new port.
    assertTrue(server.handshake(WAIT_MS), "no second handshake");
    assertTrue(eventually(() -> recorder.connections.get() == 2), "not connected again");
    assertEquals(java.util.Arrays.asList("TIMED_OUT"), recorder.reconnects);
    assertEquals(1, tickets.get());
    int secondPort = game.localPort();
    assertTrue(secondPort != firstPort, "the same port " + firstPort);
    assertTrue(game.isOpen());

    // The app asks (the network changed): at once, from another new port.
    game.reconnect();
    assertTrue(server.handshake(WAIT_MS), "no third handshake");
    assertTrue(eventually(() -> recorder.connections.get() == 3), "not connected a third time");
    assertEquals(java.util.Arrays.asList("TIMED_OUT", "null"), recorder.reconnects);
    assertEquals(2, tickets.get());
    assertTrue(game.localPort() != secondPort);

    game.close();
    assertEquals(0, gameThreads());
    assertTrue(recorder.disconnected.await(WAIT_MS, TimeUnit.MILLISECONDS));
    assertEquals(DisconnectReason.REQUESTED, recorder.reason);
    assertTrue(recorder.wrongThreads.isEmpty(), "called on " + recorder.wrongThreads);
  }

  @Test
  void noFreshTicketEndsTheConnectionWithWhyItWasLost() throws Exception {
    CompletableFuture<JoinTicket> refused = new CompletableFuture<>();
    refused.completeExceptionally(new RicochetException(
        RicochetException.Kind.SERVER_ERROR, null, null, "NOT_IN_MATCH: the match is over"));
    CompletableFuture<GameConnection> future =
        GameConnection
            .create(new InetSocketAddress("127.0.0.1", server.port()), ticket(1), recorder,
                executor, System.nanoTime() / 1_000_000, () -> refused, null)
            .start();
    assertTrue(server.handshake(WAIT_MS));
    GameConnection game = future.get(WAIT_MS, TimeUnit.MILLISECONDS);
    assertTrue(recorder.disconnected.await(WAIT_MS, TimeUnit.MILLISECONDS), "never gave up");
    assertEquals(DisconnectReason.TIMED_OUT, recorder.reason);
    assertEquals(java.util.Arrays.asList("TIMED_OUT"), recorder.reconnects);
    assertTrue(eventually(() -> gameThreads() == 0));
    assertFalse(game.isOpen());
  }
}
