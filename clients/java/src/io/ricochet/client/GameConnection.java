package io.ricochet.client;

import io.ricochet.client.core.game.GameSession;
import io.ricochet.client.core.game.GameSessionListener;
import io.ricochet.client.core.game.InputState;
import io.ricochet.client.core.game.ServerPayloadReader;
import io.ricochet.client.core.predict.CollisionWorld;
import io.ricochet.client.core.snapshot.QuantizationSpec;
import io.ricochet.client.core.snapshot.SnapshotView;
import io.ricochet.client.core.transport.ConnectGrant;
import io.ricochet.client.core.transport.ConnectionState;
import io.ricochet.client.core.transport.DisconnectReason;
import io.ricochet.client.core.transport.Outbox;
import io.ricochet.wire.GameProto.GameEvent;
import java.io.IOException;
import java.net.InetSocketAddress;
import java.net.SocketAddress;
import java.nio.ByteBuffer;
import java.nio.channels.DatagramChannel;
import java.nio.channels.SelectionKey;
import java.nio.channels.Selector;
import java.nio.channels.UnresolvedAddressException;
import java.nio.channels.UnsupportedAddressTypeException;
import java.util.concurrent.ArrayBlockingQueue;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.ExecutionException;
import java.util.concurrent.Executor;
import java.util.concurrent.RejectedExecutionException;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.TimeoutException;
import java.util.function.Supplier;

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
 * #close()} sends the disconnect and ends the thread; {@link #reconnect()} (the network changed),
 * or a silence, moves it to a new socket with a fresh token and the same entity. Bad bytes from
 * the network are counted by reason ({@link GameStats}), never thrown.
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
  /** A lost connection is reconnected within this long, µs (the server's grace: 30 s). */
  static final long RECONNECT_WINDOW_US = 30_000_000;
  /** The first reconnect attempt after a timeout waits about this long, µs (then doubling). */
  static final long RECONNECT_FIRST_DELAY_US = 250_000;
  /** Reconnect attempts wait at most about this long, µs. */
  static final long RECONNECT_MAX_DELAY_US = 4_000_000;
  /** How long {@link #close()} waits for the thread, ms. */
  private static final long CLOSE_WAIT_MS = 10_000;

  private final SocketAddress server;
  private final ConnectGrant grant;
  private final QuantizationSpec spec;
  private final CollisionWorld world; // null: the join reply had none
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
  private volatile boolean reconnectRequested;
  private final Object wakeLock = new Object();
  private final Supplier<CompletableFuture<JoinTicket>> ticketSource; // null: no reconnects
  private volatile Selector selector;
  private volatile int localPort;
  private volatile GameStats stats;
  private volatile DisconnectReason disconnectReason;
  private volatile boolean ended;

  // The I/O thread's own.
  private final InputState ioInput = new InputState();
  private final byte[] receiveBuffer = new byte[2048];
  private byte[][] wrappedArrays = new byte[4][];
  private ByteBuffer[] wrappers = new ByteBuffer[4];
  private GameSession session;
  private long snapshotsSkipped;
  private long statsAtUs;
  private long statsBytesIn;
  private long statsBytesOut;
  private long statsSnapshots;
  private long statsMissed;
  private double firstSnapshotAfterMs = -1;
  private final double[] predictionErrors = new double[3];
  private long statsOffTick; // the session's count at the last stats
  private final SessionTotals totals = new SessionTotals();
  private final java.util.Random random = new java.util.Random();
  private DisconnectReason sessionEnd; // set by the session as it ends
  private boolean everConnected;
  private boolean reconnecting;
  private DisconnectReason outageReason;
  private long outageStartUs;
  private int reconnectAttempts;

  private GameConnection(SocketAddress server, ConnectGrant grant, QuantizationSpec spec,
      CollisionWorld world, int tickRateHz, int snapshotRateHz, GameListener listener,
      Executor executor, Supplier<CompletableFuture<JoinTicket>> ticketSource, Runnable onEnded) {
    this.server = server;
    this.ticketSource = ticketSource;
    this.grant = grant;
    this.spec = spec;
    this.world = world;
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
   * expired at {@code nowMs}, on the {@code System.nanoTime()} clock in ms). {@code ticketSource}
   * asks the control channel for a fresh ticket of the same match when the connection must
   * reconnect (null: it never does). {@code onEnded} runs on the I/O thread as it ends. Called by
   * {@link RicochetClient}.
   */
  static GameConnection create(JoinTicket ticket, GameListener listener, Executor executor,
      long nowMs, Supplier<CompletableFuture<JoinTicket>> ticketSource, Runnable onEnded)
      throws RicochetException {
    return create(InetSocketAddress.createUnresolved(ticket.host(), ticket.udpPort()), ticket,
        listener, executor, nowMs, ticketSource, onEnded);
  }

  /** As above with the server's address given (resolved on the I/O thread when unresolved). */
  static GameConnection create(SocketAddress server, JoinTicket ticket, GameListener listener,
      Executor executor, long nowMs, Supplier<CompletableFuture<JoinTicket>> ticketSource,
      Runnable onEnded) throws RicochetException {
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
    CollisionWorld world =
        ticket.hasCollisionWorld() ? CollisionWorld.parse(ticket.collisionWorldBytes()) : null;
    return new GameConnection(
        server, grant, spec, world, tick, snapshots, listener, executor, ticketSource, onEnded);
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
   * The network changed (a phone moved from Wi-Fi to cellular, or back): drops this socket and
   * connects again from a new one (a new local port) with a fresh token from the control channel,
   * as PROTOCOL.md's reconnect says; the player keeps its entity and score, the input sequence
   * starts again at 1 and the first snapshot is a full one. {@link GameListener#onReconnecting}
   * and then {@link GameListener#onConnected} follow; when no ticket comes (the match is over, the
   * control channel refuses) {@link GameListener#onDisconnected} ends it. A connection lost to
   * silence ({@link DisconnectReason#TIMED_OUT}) reconnects the same way by itself, with
   * jittered, doubling back-off, for up to 30 s. Any thread; returns at once.
   */
  public void reconnect() {
    reconnectRequested = true;
    Selector waiting = selector;
    if (waiting != null) waiting.wakeup();
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
    synchronized (wakeLock) {
      wakeLock.notifyAll();
    }
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
    ConnectGrant nextGrant = grant;
    try {
      while (true) {
        DisconnectReason reason;
        try {
          reason = playOnNewSocket(nextGrant);
        } catch (IOException e) {
          if (!everConnected) {
            post(()
                     -> connected.completeExceptionally(
                         new RicochetException(RicochetException.Kind.GAME_CONNECT_FAILED,
                             "cannot open a UDP socket to " + server + ": " + e, e)));
            return;
          }
          reason = DisconnectReason.TIMED_OUT; // no network right now: an attempt that failed
        }
        nextGrant = reconnectGrant(reason);
        if (nextGrant == null) return;
      }
    } finally {
      ended = true;
      if (onEnded != null) onEnded.run();
    }
  }

  /**
   * After a session ended with {@code reason} (null: the app asked to reconnect): the grant of the
   * next attempt, after the back-off, or null when the connection is over (the listener told).
   */
  private ConnectGrant reconnectGrant(DisconnectReason reason) {
    boolean lost = reason == null
        || (everConnected
            && (reason == DisconnectReason.TIMED_OUT
                || reason == DisconnectReason.HANDSHAKE_TIMED_OUT));
    if (closeRequested || connected.isCancelled() || ticketSource == null || !lost) {
      end(closeRequested ? DisconnectReason.REQUESTED : reason);
      return null;
    }
    long now = nowUs();
    if (!reconnecting) {
      reconnecting = true;
      outageStartUs = now;
      outageReason = reason == null ? DisconnectReason.TIMED_OUT : reason;
      post(() -> listener.onReconnecting(reason));
    }
    if (now - outageStartUs > RECONNECT_WINDOW_US) {
      end(outageReason);
      return null;
    }
    long delayUs = reason == null ? 0 : backoffUs(reconnectAttempts);
    ++reconnectAttempts;
    if (!pause(delayUs)) {
      end(DisconnectReason.REQUESTED);
      return null;
    }
    JoinTicket ticket = awaitTicket(outageStartUs + RECONNECT_WINDOW_US);
    if (ticket == null) {
      end(closeRequested ? DisconnectReason.REQUESTED : outageReason);
      return null;
    }
    try {
      return new ConnectGrant(ticket.connectToken(), ticket.clientToServerKey(),
          ticket.serverToClientKey(), (int) Math.min(60, ticket.timeoutMs() / 1000));
    } catch (IllegalArgumentException e) {
      end(outageReason);
      return null;
    }
  }

  /** The wait before reconnect attempt {@code attempt} (0, 1, ...): doubling, capped, jittered. */
  private long backoffUs(int attempt) {
    long base = Math.min(RECONNECT_MAX_DELAY_US, RECONNECT_FIRST_DELAY_US << Math.min(attempt, 16));
    return (long) (base * (0.5 + random.nextDouble())); // ±50 %: phones of a cell do not align
  }

  /** Waits {@code delayUs} unless closed first; false when closed. */
  private boolean pause(long delayUs) {
    long deadline = System.nanoTime() + delayUs * 1000;
    synchronized (wakeLock) {
      while (!closeRequested) {
        long leftNs = deadline - System.nanoTime();
        if (leftNs <= 0) return true;
        try {
          wakeLock.wait(Math.max(1, leftNs / 1_000_000));
        } catch (InterruptedException e) {
          Thread.currentThread().interrupt();
          return false;
        }
      }
    }
    return false;
  }

  /** A fresh ticket from the control channel, or null (refused, failed, closed, too late). */
  private JoinTicket awaitTicket(long deadlineUs) {
    CompletableFuture<JoinTicket> future;
    try {
      future = ticketSource.get();
    } catch (RuntimeException e) {
      return null;
    }
    while (!closeRequested && nowUs() < deadlineUs) {
      try {
        return future.get(50, TimeUnit.MILLISECONDS);
      } catch (TimeoutException e) {
        // still asking; look at closeRequested again
      } catch (ExecutionException e) {
        return null;
      } catch (InterruptedException e) {
        Thread.currentThread().interrupt();
        return null;
      }
    }
    future.cancel(false);
    return null;
  }

  /**
   * Opens a new socket (a new local port) and plays one session with {@code grant} on it until it
   * ends: its reason, or null when the app asked to reconnect (the session is abandoned without a
   * disconnect: the server replaces it when the new one connects).
   */
  private DisconnectReason playOnNewSocket(ConnectGrant grant) throws IOException {
    DatagramChannel channel = null;
    Selector opened = null;
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
      selector = opened;
      return play(grant, channel, opened);
    } catch (UnresolvedAddressException | UnsupportedAddressTypeException e) {
      throw new IOException("cannot resolve " + server, e);
    } finally {
      closeQuietly(channel);
      closeQuietly(opened);
    }
  }

  private DisconnectReason play(ConnectGrant grant, DatagramChannel channel, Selector selector)
      throws IOException {
    long now = nowUs();
    if (session != null) totals.fold(session);
    sessionEnd = null;
    session = new GameSession(
        grant, spec, tickRateHz, snapshotRateHz, INPUTS_PER_PAYLOAD, new SessionEvents(), now);
    if (world != null) session.predictIn(world);
    statsOffTick = 0;
    if (statsAtUs == 0) statsAtUs = now;
    send(channel);
    ByteBuffer in = ByteBuffer.wrap(receiveBuffer);
    while (sessionEnd == null) {
      now = nowUs();
      if (closeRequested || connected.isCancelled()) {
        session.disconnect(now);
        send(channel);
        break;
      }
      if (reconnectRequested) {
        reconnectRequested = false;
        return null;
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
      for (int i = 0; i < 64 && sessionEnd == null; ++i) {
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
    return sessionEnd != null ? sessionEnd : DisconnectReason.REQUESTED;
  }

  private void send(DatagramChannel channel) {
    Outbox outbox = session.outbox();
    for (int i = 0; i < outbox.size(); ++i) {
      try {
        channel.write(wrapped(outbox.datagram(i), outbox.length(i)));
      } catch (IOException e) {
        // Unreachable for now (no route, ICMP): like a lost datagram; the timeout decides.
      }
    }
    outbox.clear();
  }

  /**
   * {@code array[0, length)} as a ByteBuffer, reusing one wrapper per outbox buffer (the outbox
   * reuses a few arrays), so that sending allocates nothing once warm.
   */
  private ByteBuffer wrapped(byte[] array, int length) {
    int slot = 0;
    while (slot < wrappedArrays.length && wrappedArrays[slot] != null
        && wrappedArrays[slot] != array) {
      ++slot;
    }
    if (slot == wrappedArrays.length) {
      wrappedArrays = java.util.Arrays.copyOf(wrappedArrays, slot * 2);
      wrappers = java.util.Arrays.copyOf(wrappers, slot * 2);
    }
    if (wrappedArrays[slot] == null) {
      wrappedArrays[slot] = array;
      wrappers[slot] = ByteBuffer.wrap(array);
    }
    ByteBuffer buffer = wrappers[slot];
    buffer.clear();
    buffer.limit(length);
    return buffer;
  }

  private void publishStats(long nowUs) {
    double periodS = (nowUs - statsAtUs) / 1e6;
    long snapshots = totals.snapshots(session);
    long missed = totals.missed(session);
    long bytesIn = totals.bytesIn(session);
    long bytesOut = totals.bytesOut(session);
    if (firstSnapshotAfterMs < 0 && session.firstSnapshotAtUs() >= 0) {
      firstSnapshotAfterMs = (session.firstSnapshotAtUs() - session.connectedAtUs()) / 1000.0;
    }
    int errorSamples = 0;
    long resets = 0;
    double recentP99 = 0;
    long offTick = 0;
    if (session.predictor() != null) {
      offTick = session.predictor().inputsOffTick() - statsOffTick;
      statsOffTick = session.predictor().inputsOffTick();
      recentP99 = session.predictor().errors().recentP99();
      errorSamples = session.predictor().errors().count();
      resets = session.predictor().resets();
      session.predictor().errors().summarise(predictionErrors);
    } else {
      java.util.Arrays.fill(predictionErrors, 0);
    }
    GameStats next = new GameStats(periodS, session.rttUs() / 1000.0,
        (snapshots - statsSnapshots) / periodS, (missed - statsMissed) / periodS,
        (bytesIn - statsBytesIn) / periodS, (bytesOut - statsBytesOut) / periodS,
        firstSnapshotAfterMs, snapshots, missed, snapshotsSkipped, totals.refusals(session),
        totals.rejections(session), totals.drops(session),
        new GameStats.Prediction(session.predictor() != null, errorSamples, predictionErrors[0],
            predictionErrors[1], predictionErrors[2], recentP99, offTick, resets,
            world == null || world.refusal() == null ? null : world.refusal().counterName()));
    statsAtUs = nowUs;
    statsSnapshots = snapshots;
    statsMissed = missed;
    statsBytesIn = bytesIn;
    statsBytesOut = bytesOut;
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
      everConnected = true;
      reconnecting = false;
      reconnectAttempts = 0;
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
      delivery.snapshot.fillShown(session.predictor(), session.interpolator(), nowUs());
      if (!post(delivery)) freeDeliveries.offer(delivery);
    }

    @Override
    public void onEvent(GameEvent event) {
      post(() -> listener.onEvent(event));
    }

    @Override
    public void onDisconnected(DisconnectReason reason) {
      sessionEnd = reason; // the run loop decides: the end, or a reconnect
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
