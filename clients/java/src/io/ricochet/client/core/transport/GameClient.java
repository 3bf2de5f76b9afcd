package io.ricochet.client.core.transport;

/**
 * The client end of the game channel (PROTOCOL.md Game channel transport, UDP 7778) as a sans-IO
 * state machine, the Java twin of the C++ {@code proto::GameClient}: {@link
 * ConnectionState#SENDING_REQUEST} → {@link ConnectionState#SENDING_RESPONSE} → {@link
 * ConnectionState#CONNECTED} → {@link ConnectionState#DISCONNECTED} with a {@link
 * DisconnectReason}. No sockets, threads or clocks: time comes in as {@code nowUs} (microseconds
 * on the caller's monotonic clock), datagrams in through {@link #receive}, datagrams out through
 * {@link #outbox}, events out through the {@link GameClientListener}.
 *
 * <p>An I/O loop: {@code receive} each datagram from the server's address (a connected socket
 * drops the rest), call {@code update} at {@link #nextUpdateUs} or more often (it resends the
 * handshake at 10 Hz, sends keep-alives when nothing else went out for 100 ms, resends reliable
 * messages and times out), and after every call write the outbox's datagrams and clear it. Once
 * warm, a connected client's unreliable traffic (receive, sendPayload, update) allocates nothing;
 * each reliable message is copied once each way. One client per connect
 * token: a reconnect takes a new token and a new client. Not thread-safe. Untrusted bytes never
 * throw: each refused datagram is counted by reason in {@link #counters}.
 */
public final class GameClient {
  /** Request and response resend interval: 10 Hz. */
  public static final long HANDSHAKE_RESEND_US = 100_000;
  /** A keep-alive goes out when nothing was sent for this long: 10 Hz. */
  public static final long KEEP_ALIVE_US = 100_000;
  /** An unacked reliable message is sent again after this long. */
  public static final long RELIABLE_RESEND_US = 100_000;
  /** Reliable messages in flight at most (the server's receive window). */
  public static final int MAX_RELIABLE_IN_FLIGHT = 256;
  /** Reliable messages held at most; one more disconnects with reliable_overflow. */
  public static final int MAX_RELIABLE_QUEUED = 256;

  private final GameClientListener listener;
  private final Session session;
  private final TransportCounters counters = new TransportCounters();
  private final Outbox outbox = new Outbox();
  private final byte[] request;
  private final byte[] challengeBody = new byte[Packets.CHALLENGE_BODY_BYTES];
  private final byte[] body = new byte[Packets.MAX_DATAGRAM_BYTES];
  private final long timeoutUs;
  private ConnectionState state = ConnectionState.SENDING_REQUEST;
  private DisconnectReason disconnectReason;
  private long lastHandshakeSendUs;
  private long handshakeDeadlineUs;

  /** Starts the handshake: the first connection request is in the outbox at once. */
  public GameClient(ConnectGrant grant, GameClientListener listener, long nowUs) {
    this.listener = listener;
    timeoutUs = grant.timeoutS() * 1_000_000L;
    session = new Session(grant, timeoutUs, KEEP_ALIVE_US, RELIABLE_RESEND_US,
        MAX_RELIABLE_IN_FLIGHT, MAX_RELIABLE_QUEUED, nowUs);
    request = Packets.connectionRequest(grant.protocolId(), grant.connectToken());
    handshakeDeadlineUs = nowUs + timeoutUs;
    listener.onTransition(state, state, "connect token received");
    sendHandshake(nowUs);
  }

  /**
   * One datagram from the server, {@code datagram[0, length)}; untrusted. Throws only when {@code
   * length} is outside the array (a caller's bug).
   */
  public void receive(byte[] datagram, int length, long nowUs) {
    if (length < 0 || length > datagram.length) {
      throw new IndexOutOfBoundsException("length " + length + " of " + datagram.length);
    }
    counters.countIn(length);
    if (length == 0) {
      drop(DropReason.EMPTY);
      return;
    }
    if (length > Packets.MAX_DATAGRAM_BYTES) {
      drop(DropReason.OVERSIZED);
      return;
    }
    PacketType type = PacketType.encryptedFromWire(datagram[0] & 0xFF);
    if (type == null) {
      drop(DropReason.MALFORMED);
      return;
    }
    if (length < Packets.HEADER_BYTES + type.minBodyBytes() + Packets.MAC_BYTES) {
      drop(DropReason.TRUNCATED);
      return;
    }
    if (!state.accepts(type)) {
      drop(DropReason.WRONG_STATE);
      return;
    }
    long sequence = Packets.getU64(datagram, 1);
    if (type == PacketType.CHALLENGE || type == PacketType.CONNECTION_DENIED) {
      onHandshakePacket(type, datagram, length, sequence, nowUs);
    } else {
      onSessionPacket(type, datagram, length, sequence, nowUs);
    }
  }

  /** Handshake resends and its timeout; when connected: timeout, reliable resends, keep-alive. */
  public void update(long nowUs) {
    switch (state) {
      case SENDING_REQUEST:
      case SENDING_RESPONSE:
        if (nowUs >= handshakeDeadlineUs) {
          end(DisconnectReason.HANDSHAKE_TIMED_OUT);
        } else if (nowUs - lastHandshakeSendUs >= HANDSHAKE_RESEND_US) {
          sendHandshake(nowUs);
        }
        return;
      case CONNECTED:
        if (session.timedOut(nowUs)) {
          end(DisconnectReason.TIMED_OUT);
          return;
        }
        if (session.reliableDue(nowUs)) {
          send(session.makePayload(body, 0, 0, nowUs, outbox.next()));
        } else if (session.keepAliveDue(nowUs)) {
          send(session.makeKeepAlive(nowUs, outbox.next()));
        }
        counters.setReliableResends(session.reliableResends());
        return;
      default:
        return;
    }
  }

  /**
   * The earliest time (µs) at which {@link #update} has something to do (a handshake resend, a
   * keep-alive, a reliable resend, a timeout), so that an I/O loop can sleep until then or until a
   * datagram arrives; {@code Long.MAX_VALUE} once disconnected. Calls to {@code sendPayload},
   * {@code sendReliable} and {@code receive} may move it earlier: ask again after each.
   */
  public long nextUpdateUs() {
    switch (state) {
      case SENDING_REQUEST:
      case SENDING_RESPONSE:
        return Math.min(lastHandshakeSendUs + HANDSHAKE_RESEND_US, handshakeDeadlineUs);
      case CONNECTED:
        return session.nextDueUs();
      default:
        return Long.MAX_VALUE;
    }
  }

  /**
   * Connected only: one payload packet with {@code payload[offset, offset + length)} (a {@code
   * ClientPayload}, at most {@link Packets#MAX_UNRELIABLE_BYTES}) and the reliable messages due
   * that fit beside it. False (nothing sent) when not connected or the payload is too large.
   */
  public boolean sendPayload(byte[] payload, int offset, int length, long nowUs) {
    if (state != ConnectionState.CONNECTED || length < 0 || length > Packets.MAX_UNRELIABLE_BYTES) {
      return false;
    }
    send(session.makePayload(payload, offset, length, nowUs, outbox.next()));
    return true;
  }

  /**
   * Queues a reliable-ordered message (1..1024 bytes, copied), sent with the next payload or by
   * {@link #update} once connected. False when empty, too large or disconnected; false and a
   * disconnect ({@link DisconnectReason#RELIABLE_OVERFLOW}) when {@link #MAX_RELIABLE_QUEUED} are
   * held unacked.
   */
  public boolean sendReliable(byte[] message, int offset, int length, long nowUs) {
    if (state == ConnectionState.DISCONNECTED || length < 1
        || length > Packets.MAX_RELIABLE_MESSAGE_BYTES) {
      return false;
    }
    if (session.queueReliable(message, offset, length)) return true;
    leave(DisconnectReason.RELIABLE_OVERFLOW, nowUs);
    return false;
  }

  /**
   * The one exit: when connected, three disconnect packets go out; then Disconnected(requested).
   */
  public void disconnect(long nowUs) {
    if (state != ConnectionState.DISCONNECTED) leave(DisconnectReason.REQUESTED, nowUs);
  }

  /** The datagrams to send after a call; the I/O layer sends and clears them. */
  public Outbox outbox() {
    return outbox;
  }

  /** The current state. */
  public ConnectionState state() {
    return state;
  }

  /** Why the connection ended; null until {@link ConnectionState#DISCONNECTED}. */
  public DisconnectReason disconnectReason() {
    return disconnectReason;
  }

  /** Smoothed round trip from the server's acks, in microseconds; 0 before the first. */
  public long rttUs() {
    return session.rttUs();
  }

  /** Reliable messages queued and not yet acked. */
  public int reliablePending() {
    return session.reliablePending();
  }

  /** Packets the server sent on this session so far: its newest sequence accepted + 1, or 0. */
  public long serverPacketsSent() {
    ReplayWindow received = session.received();
    return received.anyReceived() ? received.newest() + 1 : 0;
  }

  /** Of {@link #serverPacketsSent}, those never accepted (lost, or too late): the link's loss. */
  public long serverPacketsMissing() {
    return session.received().missing();
  }

  /** Server packets accepted after a newer one. */
  public long serverPacketsLate() {
    return session.received().late();
  }

  /** What this client counted. */
  public TransportCounters counters() {
    return counters;
  }

  private void onHandshakePacket(
      PacketType type, byte[] datagram, int length, long sequence, long nowUs) {
    // Challenge and denied carry server-wide sequences outside the session's replay window; a
    // replayed one is harmless (a second challenge is ignored, denied ends anyway).
    if ((sequence & Packets.HANDSHAKE_SEQUENCE_BIT) == 0) {
      drop(DropReason.MALFORMED);
      return;
    }
    int bytes = session.openHandshake(datagram, length, body);
    if (bytes < 0) {
      drop(DropReason.FORGED_MAC);
      return;
    }
    if (type == PacketType.CONNECTION_DENIED) {
      DisconnectReason reason = bytes == 1 ? DisconnectReason.fromWire(body[0] & 0xFF) : null;
      if (reason == null) {
        drop(DropReason.MALFORMED);
        return;
      }
      end(reason); // denied (server full) or host_full
      return;
    }
    if (bytes != Packets.CHALLENGE_BODY_BYTES) {
      drop(DropReason.MALFORMED);
      return;
    }
    if (state != ConnectionState.SENDING_REQUEST) return; // a duplicate: the response goes out
    System.arraycopy(body, 0, challengeBody, 0, bytes);
    enter(ConnectionState.SENDING_RESPONSE, "challenge received");
    handshakeDeadlineUs = nowUs + timeoutUs;
    sendHandshake(nowUs);
  }

  private void onSessionPacket(
      PacketType type, byte[] datagram, int length, long sequence, long nowUs) {
    DropReason refused = session.open(datagram, length, sequence, body, nowUs);
    if (refused != null) {
      drop(refused);
      return;
    }
    int bytes = session.openedBytes();
    switch (type) {
      case KEEP_ALIVE:
        if (bytes != Packets.ACK_HEADER_BYTES) {
          drop(DropReason.MALFORMED);
          return;
        }
        if (state == ConnectionState.SENDING_RESPONSE) becomeConnected();
        session.onAck(Packets.getU16(body, 0), Packets.getU32(body, 2), nowUs);
        return;
      case PAYLOAD:
        onPayload(bytes, nowUs);
        return;
      case DISCONNECT:
        DisconnectReason reason = bytes == Packets.ACK_HEADER_BYTES + 1
            ? DisconnectReason.fromWire(body[Packets.ACK_HEADER_BYTES] & 0xFF)
            : null;
        if (reason == null) {
          drop(DropReason.MALFORMED);
          return;
        }
        end(reason); // the server's reason (kicked, replaced, server_shutdown ...)
        return;
      default:
        drop(DropReason.WRONG_STATE);
    }
  }

  /** A payload body in {@code body[0, bytes)}: checked whole before anything is acted on. */
  private void onPayload(int bytes, long nowUs) {
    int count = body[Packets.ACK_HEADER_BYTES] & 0xFF;
    int position = Packets.PAYLOAD_FIXED_BYTES;
    for (int i = 0; i < count; ++i) {
      if (bytes - position < Packets.RELIABLE_MESSAGE_HEADER_BYTES) {
        drop(DropReason.TRUNCATED);
        return;
      }
      int messageBytes = Packets.getU16(body, position + 2);
      if (messageBytes == 0 || messageBytes > Packets.MAX_RELIABLE_MESSAGE_BYTES) {
        drop(DropReason.MALFORMED);
        return;
      }
      position += Packets.RELIABLE_MESSAGE_HEADER_BYTES;
      if (bytes - position < messageBytes) {
        drop(DropReason.TRUNCATED);
        return;
      }
      position += messageBytes;
    }
    if (state == ConnectionState.SENDING_RESPONSE) becomeConnected();
    session.onAck(Packets.getU16(body, 0), Packets.getU32(body, 2), nowUs);
    boolean allInWindow = true;
    position = Packets.PAYLOAD_FIXED_BYTES;
    for (int i = 0; i < count; ++i) {
      int id = Packets.getU16(body, position);
      int messageBytes = Packets.getU16(body, position + 2);
      position += Packets.RELIABLE_MESSAGE_HEADER_BYTES;
      if (session.receiveReliable(id, body, position, messageBytes)
          == ReliableReceiver.Outcome.OUT_OF_WINDOW) {
        allInWindow = false;
      }
      position += messageBytes;
    }
    if (!allInWindow) drop(DropReason.RELIABLE_OUT_OF_WINDOW);
    for (byte[] message = session.popReliable(); message != null; message = session.popReliable()) {
      listener.onReliable(message);
    }
    if (position < bytes) listener.onUnreliable(body, position, bytes - position);
  }

  private void sendHandshake(long nowUs) {
    lastHandshakeSendUs = nowUs;
    if (state == ConnectionState.SENDING_REQUEST) {
      byte[] out = outbox.next();
      System.arraycopy(request, 0, out, 0, request.length);
      send(request.length);
    } else {
      send(session.seal(
          PacketType.RESPONSE, challengeBody, challengeBody.length, nowUs, outbox.next()));
    }
  }

  /** Adds the datagram just written into outbox.next() and counts it. */
  private void send(int length) {
    outbox.commit(length);
    counters.countOut(length);
  }

  private void becomeConnected() {
    enter(ConnectionState.CONNECTED, "first keep-alive or payload from the server");
    counters.countConnection();
    listener.onConnected();
  }

  /** This end's decision to stop: tells the server when connected, then ends. */
  private void leave(DisconnectReason reason, long nowUs) {
    if (state == ConnectionState.CONNECTED) {
      for (int copy = 0; copy < Packets.DISCONNECT_COPIES; ++copy) {
        send(session.makeDisconnect(reason, nowUs, outbox.next()));
      }
    }
    end(reason);
  }

  private void end(DisconnectReason reason) {
    counters.countDisconnect(reason);
    disconnectReason = reason;
    enter(ConnectionState.DISCONNECTED, reason.counterName());
    listener.onDisconnected(reason);
  }

  private void enter(ConnectionState to, String why) {
    ConnectionState from = state;
    state = to;
    listener.onTransition(from, to, why);
  }

  private void drop(DropReason reason) {
    counters.countDrop(reason);
    listener.onDrop(reason);
  }
}
