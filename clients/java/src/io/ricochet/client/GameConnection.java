package io.ricochet.client;

import io.ricochet.client.core.game.GameSession;
import io.ricochet.client.core.game.GameSessionListener;
import io.ricochet.client.core.game.InputState;
import io.ricochet.client.core.game.PayloadRefusal;
import io.ricochet.client.core.game.ServerPayloadReader;
import io.ricochet.client.core.snapshot.QuantizationSpec;
import io.ricochet.client.core.snapshot.SnapshotRejection;
import io.ricochet.client.core.snapshot.SnapshotView;
import io.ricochet.client.core.transport.ConnectGrant;
import io.ricochet.client.core.transport.ConnectionState;
import io.ricochet.client.core.transport.DisconnectReason;
import io.ricochet.client.core.transport.DropReason;
import io.ricochet.client.core.transport.Outbox;
import io.ricochet.client.core.transport.TransportCounters;
import io.ricochet.wire.GameProto.GameEvent;
import java.io.IOException;
import java.net.InetSocketAddress;
import java.net.SocketAddress;
import java.nio.ByteBuffer;
import java.nio.channels.DatagramChannel;
import java.nio.channels.SelectionKey;
import java.nio.channels.Selector;
import java.util.concurrent.ArrayBlockingQueue;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.Executor;
import java.util.concurrent.RejectedExecutionException;

/**
 * A match being played: the game channel (UDP) of one join, what an app plays with. Made by {@link
 * RicochetClient#joinMatch(long, GameListener)} or {@link RicochetClient#connectGame}, whose future
 * completes with it once the handshake is done.
 *
 * <p>{@link #setInput} may be called at any time from any thread; one thread of the connection's
 * own sends the newest controls once per tick of the match's rate (each payload repeating the last
 * few inputs and acknowledging the newest snapshot, PROTOCOL.md ClientPayload), receives the
 * server's datagrams on a connected non-blocking {@link DatagramChannel}, decodes the snapshots
 * and events and hands them to the {@link GameListener} on the client's listener executor. {@link
 * #close()} sends the disconnect and ends the thread. Bad bytes from the network are counted by
 * reason ({@link GameStats}), never thrown.
 */
public final class GameConnection implements AutoCloseable {
  /** Button bit of {@link #setInput}: jump. */
  public static final int BUTTON_JUMP = InputState.BUTTON_JUMP;
  /** Button bit of {@link #setInput}: fire. */
  public static final int BUTTON_FIRE = InputState.BUTTON_FIRE;
  /** Button bit of {@link #setInput}: alternative fire. */
  public static final int BUTTON_ALT_FIRE = InputState.BUTTON_ALT_FIRE;
  /** Inputs repeated per payload (the protocol allows 8; the reference bot sends 4). */
  static final int INPUTS_PER_PAYLOAD = 4;
  /** Snapshots in flight to the listener at most; more are skipped until one comes back. */
  static final int SNAPSHOT_POOL = 4;
  /** How often {@link GameListener#onStats} is called, µs. */
  static final long STATS_PERIOD_US = 1_000_000;
  /** How long {@link #close()} waits for the thread, ms. */
  private static final long CLOSE_WAIT_MS = 10_000;

  private final SocketAddress server;
  private final ConnectGrant grant;
  private final QuantizationSpec spec;
  private final int tickRateHz;
  private final int snapshotRateHz;
  private final GameListener listener;
  private final Executor executor;
  private final CompletableFuture<GameConnection> connected = new CompletableFuture<>();
  private final Runnable onEnded;
  private final Thread thread;
  private final Object inputLock = new Object();
  private final InputState appInput = new InputState(); // guarded by inputLock
  private boolean inputChanged; // guarded by inputLock
  private final ArrayBlockingQueue<Delivery> freeDeliveries =
      new ArrayBlockingQueue<>(SNAPSHOT_POOL);
  private volatile boolean closeRequested;
  private volatile Selector selector;
  private volatile int localPort;
  private volatile GameStats stats;
  private volatile DisconnectReason disconnectReason;
  private volatile boolean ended;

  // The I/O thread's own.
  private final InputState ioInput = new InputState();
  private final byte[] receiveBuffer = new byte[2048];
  private GameSession session;
  private long snapshotsSkipped;
  private long statsAtUs;
  private long statsBytesIn;
  private long statsBytesOut;
  private long statsSnapshots;
  private long statsMissed;

  private GameConnection(SocketAddress server, ConnectGrant grant, QuantizationSpec spec,
      int tickRateHz, int snapshotRateHz, GameListener listener, Executor executor,
      Runnable onEnded) {
    this.server = server;
    this.grant = grant;
    this.spec = spec;
    this.tickRateHz = tickRateHz;
    this.snapshotRateHz = snapshotRateHz;
    this.listener = listener;
    this.executor = executor;
    this.onEnded = onEnded;
    for (int i = 0; i < SNAPSHOT_POOL; ++i)
      freeDeliveries.add(new Delivery(new GameSnapshot(spec)));
    thread = new Thread(this::run, "ricochet-game");
    thread.setDaemon(true);
  }

  /**
   * Checks {@code ticket} and makes the connection (not started); throws a RicochetException
   * ({@link RicochetException.Kind#INVALID_REPLY}, or GAME_CONNECT_FAILED when the token has
   * expired at {@code nowMs}, on the {@code System.nanoTime()} clock in ms). {@code onEnded} runs
   * on the I/O thread as it ends. Called by {@link RicochetClient}.
   */
  static GameConnection create(JoinTicket ticket, GameListener listener, Executor executor,
      long nowMs, Runnable onEnded) throws RicochetException {
    return create(InetSocketAddress.createUnresolved(ticket.host(), ticket.udpPort()), ticket,
        listener, executor, nowMs, onEnded);
  }

  /** As above with the server's address given (resolved on the I/O thread when unresolved). */
  static GameConnection create(SocketAddress server, JoinTicket ticket, GameListener listener,
      Executor executor, long nowMs, Runnable onEnded) throws RicochetException {
    if (listener == null) throw new NullPointerException("listener");
    QuantizationSpec spec = QuantizationSpec.fromWire(ticket.quantization());
    String problem = spec == null ? QuantizationSpec.problemWith(ticket.quantization()) : null;
    int tick = ticket.tickRateHz();
    int snapshots = ticket.snapshotRateHz();
    if (problem == null && (tick < 10 || tick > 128 || snapshots < 1 || snapshots > tick)) {
      problem = "join reply with tick rate " + tick + " Hz and snapshot rate " + snapshots + " Hz";
    }
    ConnectGrant grant = null;
    if (problem == null) {
      try {
        grant = new ConnectGrant(ticket.connectToken(), ticket.clientToServerKey(),
            ticket.serverToClientKey(),
            (int) Math.min(Integer.MAX_VALUE, ticket.timeoutMs() / 1000));
      } catch (IllegalArgumentException e) {
        problem = "join reply: " + e.getMessage();
      }
    }
    if (problem != null) {
      throw new RicochetException(RicochetException.Kind.INVALID_REPLY, null, null, problem);
    }
    if (nowMs - ticket.receivedAtMs() >= ticket.tokenExpiresInMs()) {
      throw new RicochetException(
          (DisconnectReason) null, "the connect token expired before the game channel connected");
    }
    return new GameConnection(server, grant, spec, tick, snapshots, listener, executor, onEnded);
  }

  /** Starts the thread; the future completes on the executor once connected, or fails. Once. */
  CompletableFuture<GameConnection> start() {
    thread.start();
    return connected;
  }

  /**
   * The controls from now on, sent at every tick until changed: {@code moveRight} and {@code
   * moveForward} -1..1 (a full stick; clamped), {@code yawRad} (0 looks along -Z, positive turns
   * left; wrapped into ±π), {@code pitchRad} (positive looks up; clamped to ±π/2), {@code buttons}
   * ({@link #BUTTON_JUMP} | {@link #BUTTON_FIRE} | {@link #BUTTON_ALT_FIRE}), {@code weaponSlot}
   * 0..9 (0 keeps the weapon; 1 rifle, 2 rocket launcher, 3 grenade launcher). Any thread; never
   * blocks for long, allocates nothing. Throws IllegalArgumentException for a non-finite value,
   * another button bit or slot.
   */
  public void setInput(float moveRight, float moveForward, float yawRad, float pitchRad,
      int buttons, int weaponSlot) {
    synchronized (inputLock) {
      appInput.set(moveRight, moveForward, yawRad, pitchRad, buttons, weaponSlot);
      inputChanged = true;
    }
  }

  /** The newest figures (as last given to {@link GameListener#onStats}); null before the first. */
  public GameStats stats() {
    return stats;
  }

  /** Why the connection ended; null while it lasts. */
  public DisconnectReason disconnectReason() {
    return disconnectReason;
  }

  /** False once the connection has ended (its thread is then ending or gone). */
  public boolean isOpen() {
    return !ended;
  }

  /** The local UDP port the connection sends from (0 before its socket is open). */
  public int localPort() {
    return localPort;
  }

  /**
   * Leaves the game channel: the disconnect goes out (three packets), {@link
   * GameListener#onDisconnected} gets {@link DisconnectReason#REQUESTED}, and this waits for the
   * connection's thread to end (at most 10 s). Any thread; idempotent. Does not leave the match on
   * the control channel ({@link RicochetClient#leave}): the player is away until it reconnects.
   */
  @Override
  public void close() {
    closeRequested = true;
    Selector waiting = selector;
    if (waiting != null) waiting.wakeup();
    if (Thread.currentThread() == thread || thread.getState() == Thread.State.NEW) return;
    try {
      thread.join(CLOSE_WAIT_MS);
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
    }
  }

  private static long nowUs() {
    return System.nanoTime() / 1000;
  }

  private void run() {
    DatagramChannel channel = null;
    Selector opened = null;
    try {
      try {
        channel = DatagramChannel.open();
        channel.configureBlocking(false);
        SocketAddress target = server;
        if (target instanceof InetSocketAddress && ((InetSocketAddress) target).isUnresolved()) {
          InetSocketAddress named = (InetSocketAddress) target;
          target = new InetSocketAddress(named.getHostString(), named.getPort()); // DNS, here
        }
        channel.connect(target);
        opened = Selector.open();
        channel.register(opened, SelectionKey.OP_READ);
        localPort = ((InetSocketAddress) channel.getLocalAddress()).getPort();
      } catch (IOException | RuntimeException e) {
        post(()
                 -> connected.completeExceptionally(
                     new RicochetException(RicochetException.Kind.GAME_CONNECT_FAILED,
                         "cannot open a UDP socket to " + server + ": " + e, e)));
        return;
      }
      selector = opened;
      play(channel, opened);
    } catch (IOException e) {
      // The selector failed (the system ran out of something): the session ends as timed out.
      end(DisconnectReason.TIMED_OUT);
    } finally {
      closeQuietly(channel);
      closeQuietly(opened);
      ended = true;
      if (onEnded != null) onEnded.run();
    }
  }

  private void play(DatagramChannel channel, Selector selector) throws IOException {
    long now = nowUs();
    session = new GameSession(
        grant, spec, tickRateHz, snapshotRateHz, INPUTS_PER_PAYLOAD, new SessionEvents(), now);
    statsAtUs = now;
    send(channel);
    ByteBuffer in = ByteBuffer.wrap(receiveBuffer);
    while (session.state() != ConnectionState.DISCONNECTED) {
      now = nowUs();
      if (closeRequested || connected.isCancelled()) {
        session.disconnect(now);
        send(channel);
        break;
      }
      synchronized (inputLock) {
        if (inputChanged) {
          ioInput.copyFrom(appInput);
          inputChanged = false;
        }
      }
      session.setInput(ioInput);
      session.update(now);
      send(channel);
      if (now - statsAtUs >= STATS_PERIOD_US) publishStats(now);
      long wakeUs = Math.min(session.nextWakeUs(), statsAtUs + STATS_PERIOD_US);
      long waitMs = (wakeUs - now + 999) / 1000;
      if (waitMs > 0) {
        selector.select(waitMs);
      } else {
        selector.selectNow();
      }
      selector.selectedKeys().clear();
      for (int i = 0; i < 64 && session.state() != ConnectionState.DISCONNECTED; ++i) {
        in.clear();
        int length;
        try {
          length = channel.read(in);
        } catch (IOException e) {
          continue; // an ICMP error of an earlier send: the transport's timeout decides
        }
        if (length <= 0) break;
        session.receive(receiveBuffer, length, nowUs());
        send(channel);
      }
    }
  }

  private void send(DatagramChannel channel) {
    Outbox outbox = session.outbox();
    for (int i = 0; i < outbox.size(); ++i) {
      try {
        channel.write(ByteBuffer.wrap(outbox.datagram(i), 0, outbox.length(i)));
      } catch (IOException e) {
        // Unreachable for now (no route, ICMP): like a lost datagram; the timeout decides.
      }
    }
    outbox.clear();
  }

  private void publishStats(long nowUs) {
    TransportCounters counters = session.transportCounters();
    double periodS = (nowUs - statsAtUs) / 1e6;
    long snapshots = session.snapshotsReceived();
    long missed = session.snapshotsMissed();
    long[] refusals = new long[PayloadRefusal.values().length];
    for (PayloadRefusal reason : PayloadRefusal.values()) {
      refusals[reason.ordinal()] = session.refusals(reason);
    }
    long[] rejections = new long[SnapshotRejection.values().length];
    for (SnapshotRejection reason : SnapshotRejection.values()) {
      rejections[reason.ordinal()] = session.decoder().rejections(reason);
    }
    long[] drops = new long[DropReason.values().length];
    for (DropReason reason : DropReason.values())
      drops[reason.ordinal()] = counters.dropped(reason);
    long connectedAt = session.connectedAtUs();
    long firstAt = session.firstSnapshotAtUs();
    GameStats next =
        new GameStats(periodS, session.rttUs() / 1000.0, (snapshots - statsSnapshots) / periodS,
            (missed - statsMissed) / periodS, (counters.bytesIn() - statsBytesIn) / periodS,
            (counters.bytesOut() - statsBytesOut) / periodS,
            firstAt < 0 || connectedAt < 0 ? -1 : (firstAt - connectedAt) / 1000.0, snapshots,
            missed, snapshotsSkipped, refusals, rejections, drops);
    statsAtUs = nowUs;
    statsSnapshots = snapshots;
    statsMissed = missed;
    statsBytesIn = counters.bytesIn();
    statsBytesOut = counters.bytesOut();
    stats = next;
    post(() -> listener.onStats(next));
  }

  private void end(DisconnectReason reason) {
    disconnectReason = reason;
    post(() -> {
      if (!connected.isDone()) {
        connected.completeExceptionally(new RicochetException(
            reason, "the game channel ended before it connected: " + reason.counterName()));
      }
      listener.onDisconnected(reason);
    });
  }

  /** Runs {@code task} on the listener executor; an executor that refuses drops it. */
  private boolean post(Runnable task) {
    try {
      executor.execute(task);
      return true;
    } catch (RejectedExecutionException e) {
      return false;
    }
  }

  private static void closeQuietly(java.io.Closeable closeable) {
    if (closeable == null) return;
    try {
      closeable.close();
    } catch (IOException e) {
      // closing: nothing left to do with it
    }
  }

  /** The session's events, on the I/O thread, handed to the listener executor. */
  private final class SessionEvents implements GameSessionListener {
    @Override
    public void onConnected() {
      post(() -> {
        listener.onConnected();
        connected.complete(GameConnection.this);
      });
    }

    @Override
    public void onSnapshot(SnapshotView view, ServerPayloadReader payload) {
      Delivery delivery = freeDeliveries.poll();
      if (delivery == null) {
        ++snapshotsSkipped;
        return;
      }
      delivery.snapshot.fill(view, payload);
      if (!post(delivery)) freeDeliveries.offer(delivery);
    }

    @Override
    public void onEvent(GameEvent event) {
      post(() -> listener.onEvent(event));
    }

    @Override
    public void onDisconnected(DisconnectReason reason) {
      end(reason);
    }
  }

  /** One pooled snapshot and the task that hands it over and returns it to the pool. */
  private final class Delivery implements Runnable {
    final GameSnapshot snapshot;

    Delivery(GameSnapshot snapshot) {
      this.snapshot = snapshot;
    }

    @Override
    public void run() {
      try {
        listener.onSnapshot(snapshot);
      } finally {
        freeDeliveries.offer(this);
      }
    }
  }
}
