package io.ricochet.client.core.game;

import com.google.protobuf.InvalidProtocolBufferException;
import io.ricochet.client.core.predict.CollisionWorld;
import io.ricochet.client.core.predict.Interpolator;
import io.ricochet.client.core.predict.Predictor;
import io.ricochet.client.core.snapshot.EntityFlags;
import io.ricochet.client.core.snapshot.QuantizationSpec;
import io.ricochet.client.core.snapshot.SnapshotDecoder;
import io.ricochet.client.core.snapshot.SnapshotView;
import io.ricochet.client.core.transport.ConnectGrant;
import io.ricochet.client.core.transport.ConnectionState;
import io.ricochet.client.core.transport.DisconnectReason;
import io.ricochet.client.core.transport.GameClient;
import io.ricochet.client.core.transport.GameClientListener;
import io.ricochet.client.core.transport.Outbox;
import io.ricochet.client.core.transport.TransportCounters;
import io.ricochet.wire.GameProto.GameEvent;

/**
 * One game connection's play above the transport (PROTOCOL.md Game payloads), sans-IO: a {@link
 * GameClient}, the {@link SnapshotDecoder} of the match's quantisation and the {@link
 * InputHistory}. Once connected it sends one ClientPayload per tick of the match's rate (the
 * newest {@code inputsPerPayload} inputs, oldest first, and the newest decoded snapshot tick as
 * {@code ack_snapshot_tick}); each ServerPayload acknowledges inputs and feeds the decoder; each
 * reliable message is parsed as a GameEvent. Time comes in as {@code nowUs} (microseconds of the
 * caller's monotonic clock); datagrams go out through {@link #outbox}.
 *
 * <p>The I/O layer: {@link #receive} each datagram, call {@link #update} at {@link #nextWakeUs},
 * write and clear the outbox after every call. Untrusted bytes never throw: refusals are counted
 * ({@link #refusals}, the decoder's rejections, the transport's drops). Once warm nothing is
 * allocated per payload or snapshot (events, being rare, are parsed into messages). Not
 * thread-safe.
 */
public final class GameSession {
  /** A tick later than this behind its due time is skipped rather than sent late in a burst. */
  private static final int MAX_TICKS_BEHIND = 2;

  private final GameSessionListener listener;
  private final GameClient client;
  private final SnapshotDecoder decoder;
  private final ServerPayloadReader payload = new ServerPayloadReader();
  private final InputHistory history = new InputHistory();
  private final InputState input = new InputState();
  private final byte[] payloadBytes = new byte[ClientPayloadWriter.MAX_BYTES];
  private final long[] refusals = new long[PayloadRefusal.values().length];
  private final int tickRateHz;
  private final QuantizationSpec spec;
  private final Interpolator interpolator;
  private Predictor predictor; // null: no (valid) collision world, no prediction
  private final float[] ownPosition = new float[3];
  private final float[] ownVelocity = new float[3];
  private final int inputsPerPayload;
  private final double ticksPerSnapshot;
  private long nowUs;
  private long connectedAtUs = -1;
  private long firstSnapshotAtUs = -1;
  private long inputTicks; // input ticks since connectedAtUs: the next one is due at its time
  private long snapshotsMissed;
  private long inputsSent;

  /**
   * Starts the handshake with {@code grant} (the first request is in the outbox at once). {@code
   * tickRateHz} 10..128 and {@code snapshotRateHz} 1..tick rate: the join reply's; {@code
   * inputsPerPayload} 1..8 (4 is the reference bot's). Throws IllegalArgumentException when out of
   * range.
   */
  public GameSession(ConnectGrant grant, QuantizationSpec spec, int tickRateHz, int snapshotRateHz,
      int inputsPerPayload, GameSessionListener listener, long nowUs) {
    if (tickRateHz < 10 || tickRateHz > 128) {
      throw new IllegalArgumentException("tick rate must be 10..128 Hz, got " + tickRateHz);
    }
    if (snapshotRateHz < 1 || snapshotRateHz > tickRateHz) {
      throw new IllegalArgumentException(
          "snapshot rate must be 1..tick rate, got " + snapshotRateHz);
    }
    if (inputsPerPayload < 1 || inputsPerPayload > InputHistory.MAX_PER_PAYLOAD) {
      throw new IllegalArgumentException(
          "inputs per payload must be 1..8, got " + inputsPerPayload);
    }
    this.listener = listener;
    this.tickRateHz = tickRateHz;
    this.inputsPerPayload = inputsPerPayload;
    this.ticksPerSnapshot = (double) tickRateHz / snapshotRateHz;
    this.decoder = new SnapshotDecoder(spec);
    this.spec = spec;
    this.interpolator = new Interpolator(tickRateHz);
    this.nowUs = nowUs;
    this.client = new GameClient(grant, new TransportEvents(), nowUs);
  }

  /** One datagram from the server, {@code datagram[0, length)}; untrusted. */
  public void receive(byte[] datagram, int length, long nowUs) {
    this.nowUs = nowUs;
    client.receive(datagram, length, nowUs);
  }

  /** The transport's resends, keep-alives and timeouts, and the input tick when it is due. */
  public void update(long nowUs) {
    this.nowUs = nowUs;
    client.update(nowUs);
    if (client.state() != ConnectionState.CONNECTED || nowUs < inputDueUs(inputTicks)) return;
    boolean stalled = nowUs >= inputDueUs(inputTicks + MAX_TICKS_BEHIND + 1);
    sendInput(nowUs);
    ++inputTicks;
    if (stalled) { // a stalled thread sends the input due, not a burst of the ticks it missed
      while (inputDueUs(inputTicks) <= nowUs) ++inputTicks;
    }
  }

  /** When {@link #update} has something to do next (µs); {@code Long.MAX_VALUE} once over. */
  public long nextWakeUs() {
    long transport = client.nextUpdateUs();
    if (client.state() != ConnectionState.CONNECTED) return transport;
    return Math.min(transport, inputDueUs(inputTicks));
  }

  /** The controls the next input ticks send (copied). */
  public void setInput(InputState controls) {
    input.copyFrom(controls);
  }

  /** Leaves: the disconnect packets go into the outbox, then Disconnected(requested). */
  public void disconnect(long nowUs) {
    this.nowUs = nowUs;
    client.disconnect(nowUs);
  }

  /**
   * Predicts the own player in {@code world} (the join reply's, checked; a refused one predicts
   * nothing): each input moves it at once, each snapshot reconciles (PROTOCOL.md Prediction and
   * reconciliation). Call before the first input.
   */
  public void predictIn(CollisionWorld world) {
    predictor = world.refusal() == null ? new Predictor(world, spec, tickRateHz) : null;
  }

  /** The own player's prediction; null when not predicting. */
  public Predictor predictor() {
    return predictor;
  }

  /** Where the others are shown (100 ms behind the newest snapshot) and each input's view tick. */
  public Interpolator interpolator() {
    return interpolator;
  }

  /** The datagrams to send after a call; the I/O layer sends and clears them. */
  public Outbox outbox() {
    return client.outbox();
  }

  /** The transport's state. */
  public ConnectionState state() {
    return client.state();
  }

  /** Why it ended; null until {@link ConnectionState#DISCONNECTED}. */
  public DisconnectReason disconnectReason() {
    return client.disconnectReason();
  }

  /** Smoothed round trip, µs; 0 before the first ack. */
  public long rttUs() {
    return client.rttUs();
  }

  /** The transport's counters (bytes and packets in and out, drops by reason). */
  public TransportCounters transportCounters() {
    return client.counters();
  }

  /** The snapshot decoder (its accepted count and rejections by reason). */
  public SnapshotDecoder decoder() {
    return decoder;
  }

  /** What was refused above the transport for {@code reason}. */
  public long refusals(PayloadRefusal reason) {
    return refusals[reason.ordinal()];
  }

  /** Snapshots accepted. */
  public long snapshotsReceived() {
    return decoder.accepted();
  }

  /**
   * Snapshots that never arrived (or came too late), from the gaps between accepted ticks at the
   * match's ticks per snapshot.
   */
  public long snapshotsMissed() {
    return snapshotsMissed;
  }

  /** Payloads sent with inputs (one per input tick). */
  public long inputsSent() {
    return inputsSent;
  }

  /** When the handshake completed (µs), or -1. */
  public long connectedAtUs() {
    return connectedAtUs;
  }

  /** When the first snapshot was accepted (µs), or -1. */
  public long firstSnapshotAtUs() {
    return firstSnapshotAtUs;
  }

  /** The inputs sent and acknowledged. */
  public InputHistory inputs() {
    return history;
  }

  private long inputDueUs(long tick) {
    return connectedAtUs + tick * 1_000_000L / tickRateHz;
  }

  private void sendInput(long nowUs) {
    history.push(input, interpolator.viewTick(nowUs), interpolator.viewFraction(nowUs));
    if (predictor != null) {
      predictor.apply(history.lastSequence(), input.moveRight(), input.moveForward(), input.yaw(),
          input.buttons());
    }
    int count = Math.min(inputsPerPayload, history.held());
    long ackTick = decoder.hasSnapshot() ? decoder.newestTick() : 0;
    int length = ClientPayloadWriter.write(history, count, ackTick, payloadBytes);
    if (client.sendPayload(payloadBytes, 0, length, nowUs)) ++inputsSent;
  }

  private void onPayload(byte[] bytes, int offset, int length) {
    if (!payload.read(bytes, offset, length)) {
      refuse(PayloadRefusal.MALFORMED_PAYLOAD);
      return;
    }
    if (payload.hasSnapshot() && payload.snapshotTick() != payload.serverTick()) {
      refuse(PayloadRefusal.SNAPSHOT_TICK_MISMATCH);
      return;
    }
    if (!history.acknowledge(payload.lastInputSequence())) {
      refuse(PayloadRefusal.UNSENT_INPUT_ACKED);
    }
    if (!payload.hasSnapshot()) return;
    boolean hadSnapshot = decoder.hasSnapshot();
    long previousTick = decoder.newestTick();
    if (!decoder.decode(payload.snapshotTick(), payload.baselineAge(), bytes,
            payload.entitiesOffset(), payload.entitiesLength())) {
      return; // counted by the decoder
    }
    if (hadSnapshot) {
      long expected = Math.round((decoder.newestTick() - previousTick) / ticksPerSnapshot);
      if (expected > 1) snapshotsMissed += expected - 1;
    } else {
      firstSnapshotAtUs = nowUs;
    }
    interpolator.add(decoder.view(), nowUs);
    if (predictor != null) reconcile();
    listener.onSnapshot(decoder.view(), payload);
  }

  /** The own entity's state at the snapshot's tick re-seeds the prediction. */
  private void reconcile() {
    SnapshotView view = decoder.view();
    int own = view.indexOf(payload.yourEntityId());
    int flags = own >= 0 ? view.flags(own) : 0;
    boolean alive = own >= 0 && EntityFlags.kind(flags) == EntityFlags.KIND_PLAYER
        && (flags & (EntityFlags.DEAD | EntityFlags.DISCONNECTED)) == 0;
    if (alive) {
      for (int axis = 0; axis < 3; ++axis) {
        ownPosition[axis] = view.positionM(own, axis);
        ownVelocity[axis] = view.velocityMps(own, axis);
      }
    }
    predictor.reconcile(view.tick(), alive, ownPosition, ownVelocity, payload.lastInputSequence());
  }

  private void readEvent(byte[] message) {
    GameEvent event;
    try {
      event = GameEvent.parseFrom(message);
    } catch (InvalidProtocolBufferException e) {
      refuse(PayloadRefusal.MALFORMED_EVENT);
      return;
    }
    if (event.getEventCase() == GameEvent.EventCase.EVENT_NOT_SET) {
      refuse(PayloadRefusal.MALFORMED_EVENT);
      return;
    }
    listener.onEvent(event);
  }

  private void refuse(PayloadRefusal reason) {
    ++refusals[reason.ordinal()];
  }

  /** The transport's callbacks, turned into the session's. */
  private final class TransportEvents implements GameClientListener {
    @Override
    public void onConnected() {
      connectedAtUs = nowUs;
      inputTicks = 0;
      listener.onConnected();
    }

    @Override
    public void onUnreliable(byte[] bytes, int offset, int length) {
      onPayload(bytes, offset, length);
    }

    @Override
    public void onReliable(byte[] message) {
      readEvent(message);
    }

    @Override
    public void onDisconnected(DisconnectReason reason) {
      listener.onDisconnected(reason);
    }
  }
}
