package io.ricochet.client;

import com.google.protobuf.ByteString;
import io.ricochet.client.core.control.Assignment;
import io.ricochet.client.core.control.ControlSession;
import io.ricochet.client.core.control.ControlState;
import io.ricochet.client.core.control.RequestRefusal;
import io.ricochet.client.core.control.ResumeBackoff;
import io.ricochet.client.core.control.ResumeState;
import io.ricochet.wire.ControlProto.ChatRequest;
import io.ricochet.wire.ControlProto.ClientMessage;
import io.ricochet.wire.ControlProto.CreateMatchRequest;
import io.ricochet.wire.ControlProto.ErrorCode;
import io.ricochet.wire.ControlProto.FindMatchRequest;
import io.ricochet.wire.ControlProto.JoinMatchRequest;
import io.ricochet.wire.ControlProto.LeaveMatchRequest;
import io.ricochet.wire.ControlProto.ListMatchesRequest;
import io.ricochet.wire.ControlProto.LoginRequest;
import io.ricochet.wire.ControlProto.LogoutRequest;
import io.ricochet.wire.ControlProto.MatchResults;
import io.ricochet.wire.ControlProto.RegisterRequest;
import io.ricochet.wire.ControlProto.ResumeRequest;
import io.ricochet.wire.ControlProto.ServerMessage;
import io.ricochet.wire.ControlProto.SessionReply;
import java.security.Provider;
import java.util.ArrayDeque;
import java.util.ArrayList;
import java.util.Collections;
import java.util.List;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.CompletionException;
import java.util.concurrent.Executor;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.RejectedExecutionException;
import java.util.concurrent.ScheduledThreadPoolExecutor;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicReference;
import java.util.function.DoubleSupplier;

/**
 * A client of a Ricochet server's control channel (PROTOCOL.md, Control channel): accounts,
 * sessions, the match directory, chat. Every call returns a {@link CompletableFuture} that
 * completes with a typed result, or fails with a {@link RicochetException} carrying the server's
 * error code. Made by {@link #builder()}; thread-safe; call it from any thread (it never blocks).
 *
 * <p>The first call connects (TCP, TLS 1.3, the certificate pin) on a background thread. When a
 * connection signed in (by {@link #login} or {@link #resume}) is lost, the client resumes by
 * itself: it reconnects after a back-off with jitter ({@link Builder#resumeBackoffMs}) and signs
 * the new connection in with the session token ({@link Listener#onDisconnected}, then {@link
 * Listener#onResumed}, or {@link Listener#onResumeFailed} once it gives up); calls made meanwhile
 * wait for it and go out on the resumed connection, or fail with the reason it gave up. It does
 * not resume after {@link #close()} or {@link #logout}, nor when the server ended the session (a
 * ban, an expired or revoked token). Any other ended connection: the next call connects again,
 * unauthenticated. A running {@link GameConnection} (UDP) goes on meanwhile. Futures complete, and
 * the
 * {@link Listener} is called, on the listener executor only (by default one thread of the client's
 * own), never on the caller's thread or an I/O thread. {@link #close()} ends every thread the
 * client started.
 */
public final class RicochetClient implements AutoCloseable {
  /** What the server says unasked. Called on the listener executor; every method a no-op. */
  public interface Listener {
    /** A match this account played ended; the connection is back out of the match. */
    default void onMatchResults(MatchResults results) {}

    /**
     * The control connection ended, {@code disconnect} says why. When it was signed in and lost
     * (not closed, not refused by the server), the client now resumes the session by itself:
     * {@link #onResumed} or {@link #onResumeFailed} follows. Otherwise the next call opens a new,
     * unauthenticated connection.
     */
    default void onDisconnected(Disconnect disconnect) {}

    /**
     * After a lost connection the client reconnected and resumed {@code session} (the same account
     * and token) by itself; the calls made meanwhile go out now. Seats are the game channel's: a
     * match joined before is still joined, and the resumed connection is back in it ({@link
     * Session#matchId()}, {@link #state()} IN_MATCH: {@link #leave} and {@link #chat} work, its
     * results arrive; the running {@link GameConnection} is not touched). {@code matchId} 0: the
     * seat was given up meanwhile (the server's 30 s grace ran out, or the match ended).
     */
    default void onResumed(Session session) {}

    /**
     * The client gave up resuming after a lost connection: the server refused the session ({@link
     * RicochetException#errorCode()}: UNKNOWN_SESSION when revoked, EXPIRED_SESSION,
     * ACCOUNT_BANNED), the certificate no longer matched the pin, or none of the attempts
     * connected. The calls made meanwhile failed with {@code failure}; sign in again ({@link
     * RicochetClient#login}).
     */
    default void onResumeFailed(RicochetException failure) {}
  }

  /** Sets up a {@link RicochetClient}. */
  public static final class Builder {
    private String host;
    private int controlPort = 7777;
    private String pinSha256;
    private PinStore pinStore;
    private Provider tlsProvider;
    private Executor listenerExecutor;
    private Listener listener = new Listener() {};
    private int connectTimeoutMs = 10_000;
    private long requestTimeoutMs = ControlSession.DEFAULT_REQUEST_TIMEOUT_MS;
    private long keepAliveMs = ControlSession.DEFAULT_KEEP_ALIVE_MS;
    private ControlTransport transport; // null: TLS as configured
    private long resumeBaseMs = ResumeBackoff.DEFAULT_BASE_MS;
    private long resumeMaxMs = ResumeBackoff.DEFAULT_MAX_MS;
    private int resumeAttempts = ResumeBackoff.DEFAULT_MAX_ATTEMPTS;
    private DoubleSupplier resumeJitter = Math::random;

    private Builder() {}

    /** These settings for another server (its own connector: not the test transport). */
    private Builder copyFor(String otherHost, int otherControlPort, String otherPin) {
      Builder copy = new Builder();
      copy.host = otherHost;
      copy.controlPort = otherControlPort;
      copy.pinSha256 = otherPin;
      copy.tlsProvider = tlsProvider;
      copy.listenerExecutor = listenerExecutor;
      copy.listener = listener;
      copy.connectTimeoutMs = connectTimeoutMs;
      copy.requestTimeoutMs = requestTimeoutMs;
      copy.keepAliveMs = keepAliveMs;
      copy.resumeBaseMs = resumeBaseMs;
      copy.resumeMaxMs = resumeMaxMs;
      copy.resumeAttempts = resumeAttempts;
      copy.resumeJitter = resumeJitter;
      return copy;
    }

    /** Draws the resume back-off's jitter from {@code jitter} (values in [0, 1]; tests). */
    Builder resumeJitterForTest(DoubleSupplier jitter) {
      this.resumeJitter = jitter;
      return this;
    }

    /**
     * The back-off between attempts to resume a lost connection: attempt n (from 0) waits a
     * uniformly random time up to min({@code maxMs}, {@code baseMs} * 2^n) (ms; default 500 and
     * 30 000; 1 <= baseMs <= maxMs).
     */
    public Builder resumeBackoffMs(long baseMs, long maxMs) {
      this.resumeBaseMs = baseMs;
      this.resumeMaxMs = maxMs;
      return this;
    }

    /**
     * How many attempts to resume a lost connection before {@link Listener#onResumeFailed}
     * (default 10: with the default back-off at most 151.5 s of waiting in all; 0: never resume by
     * itself, the next call connects unauthenticated).
     */
    public Builder resumeAttempts(int attempts) {
      this.resumeAttempts = attempts;
      return this;
    }

    /** Replaces TLS by {@code transport} (tests that play the server themselves). */
    Builder transportForTest(ControlTransport transport) {
      this.transport = transport;
      return this;
    }

    /** The server's host name or address (required). */
    public Builder host(String host) {
      this.host = host;
      return this;
    }

    /** The control channel's TCP port (default 7777). */
    public Builder controlPort(int controlPort) {
      this.controlPort = controlPort;
      return this;
    }

    /**
     * Pins the server's certificate: its SHA-256 as the server logs it (32 hex pairs, with or
     * without colons). Chain validation is skipped; any other certificate is refused before
     * anything is sent.
     */
    public Builder pinSha256(String pinSha256) {
      this.pinSha256 = pinSha256;
      return this;
    }

    /**
     * Trusts on first use: the first connection saves the certificate's pin into {@code store},
     * later ones must match it. A {@link #pinSha256} given as well takes precedence.
     */
    public Builder pinStore(PinStore store) {
      this.pinStore = store;
      return this;
    }

    /**
     * The JSSE provider for TLS 1.3 where the platform has none (Android before 10): pass an
     * instance, {@code new org.bouncycastle.jsse.provider.BouncyCastleJsseProvider()}. Default:
     * the platform's.
     */
    public Builder tlsProvider(Provider provider) {
      this.tlsProvider = provider;
      return this;
    }

    /** Where futures complete and the listener is called (default: one thread of its own). */
    public Builder listenerExecutor(Executor executor) {
      this.listenerExecutor = executor;
      return this;
    }

    /** Gets what the server says unasked (default: ignores it). */
    public Builder listener(Listener listener) {
      this.listener = listener;
      return this;
    }

    /** Bound on the TCP connect and on the TLS handshake, each (ms; default 10 000). */
    public Builder connectTimeoutMs(int connectTimeoutMs) {
      this.connectTimeoutMs = connectTimeoutMs;
      return this;
    }

    /** A request with no reply this long closes the connection (ms; default 60 000; 0: never). */
    public Builder requestTimeoutMs(long requestTimeoutMs) {
      this.requestTimeoutMs = requestTimeoutMs;
      return this;
    }

    /** A ping is sent when nothing was for this long (ms; default 30 000; 0: never). */
    public Builder keepAliveMs(long keepAliveMs) {
      this.keepAliveMs = keepAliveMs;
      return this;
    }

    /** The client; it connects on its first call. Throws IllegalArgumentException on bad input. */
    public RicochetClient build() {
      if (host == null || host.isEmpty()) throw new IllegalArgumentException("host is required");
      if (controlPort < 1 || controlPort > 65535) {
        throw new IllegalArgumentException("controlPort must be 1..65535, got " + controlPort);
      }
      if (connectTimeoutMs < 1 || requestTimeoutMs < 0 || keepAliveMs < 0) {
        throw new IllegalArgumentException("timeouts must be positive");
      }
      if (listener == null) throw new IllegalArgumentException("listener is null");
      if (resumeAttempts < 0 || resumeBaseMs < 1 || resumeMaxMs < resumeBaseMs) {
        throw new IllegalArgumentException(
            "resume needs attempts >= 0 and 1 <= baseMs <= maxMs, got " + resumeAttempts + ", "
            + resumeBaseMs + ", " + resumeMaxMs);
      }
      return new RicochetClient(this);
    }
  }

  /** A builder with the defaults. */
  public static Builder builder() {
    return new Builder();
  }

  private final String host;
  private final Builder settings; // a copy, for the clients of other servers (follow)
  private final ControlTransport transport;
  private final long requestTimeoutMs;
  private final long keepAliveMs;
  private final Listener listener;
  private final Executor executor;
  private final ExecutorService ownedExecutor; // null when the app supplied the executor
  private ControlConnection connection; // the newest; null before the first call
  private final List<ControlConnection> retired = new ArrayList<>(); // over, threads maybe alive
  private volatile Thread listenerThread; // the owned executor's thread, once started
  private boolean closed;
  private final List<GameConnection> games = new ArrayList<>(); // started, not yet ended
  private final ResumeBackoff backoff; // null: never resume by itself
  // Resume attempts wait and run here ("ricochet-control-resume", started on the first loss).
  private final ScheduledThreadPoolExecutor resumer;
  private volatile Thread resumerThread;
  // The connection signed in and its session; set and cleared by the replies on its I/O thread.
  private final AtomicReference<SignedIn> signedIn = new AtomicReference<>();
  private Session resuming; // the session being resumed, while backoff is not IDLE
  private final ArrayDeque<Call> waitingForResume = new ArrayDeque<>();

  /** A connection and the session it signed in with. */
  private static final class SignedIn {
    final ControlConnection connection;
    final Session session;

    SignedIn(ControlConnection connection, Session session) {
      this.connection = connection;
      this.session = session;
    }
  }

  /** A request and who gets its reply. */
  private static final class Call {
    final ClientMessage message;
    final ControlConnection.ReplyHandler handler;

    Call(ClientMessage message, ControlConnection.ReplyHandler handler) {
      this.message = message;
      this.handler = handler;
    }
  }

  private RicochetClient(Builder builder) {
    host = builder.host;
    settings = builder.copyFor(builder.host, builder.controlPort, builder.pinSha256);
    String pin = builder.pinSha256 == null ? null : CertificatePin.normalize(builder.pinSha256);
    transport = builder.transport != null
        ? builder.transport
        : new TlsConnector(builder.host, builder.controlPort, pin, builder.pinStore,
            builder.tlsProvider, builder.connectTimeoutMs);
    requestTimeoutMs = builder.requestTimeoutMs;
    keepAliveMs = builder.keepAliveMs;
    listener = builder.listener;
    if (builder.listenerExecutor != null) {
      executor = builder.listenerExecutor;
      ownedExecutor = null;
    } else {
      ownedExecutor = Executors.newSingleThreadExecutor(runnable -> {
        Thread thread = new Thread(runnable, "ricochet-listener");
        thread.setDaemon(true);
        listenerThread = thread;
        return thread;
      });
      executor = ownedExecutor;
    }
    backoff = builder.resumeAttempts == 0
        ? null
        : new ResumeBackoff(builder.resumeBaseMs, builder.resumeMaxMs, builder.resumeAttempts,
            builder.resumeJitter);
    resumer = new ScheduledThreadPoolExecutor(1, runnable -> {
      Thread thread = new Thread(runnable, "ricochet-control-resume");
      thread.setDaemon(true);
      resumerThread = thread;
      return thread;
    });
    resumer.setKeepAliveTime(5, TimeUnit.SECONDS);
    resumer.allowCoreThreadTimeOut(true);
  }

  /** Creates an account (it does not sign in); completes with its account id. */
  public CompletableFuture<Long> register(String username, String password) {
    ClientMessage message =
        ClientMessage.newBuilder()
            .setRegisterAccount(
                RegisterRequest.newBuilder().setUsername(username).setPassword(password))
            .build();
    return send(message, (reply, nowMs) -> reply.getRegisterAccount().getAccountId());
  }

  /** Signs in with a password; completes with the session (keep its token to resume). */
  public CompletableFuture<Session> login(String username, String password) {
    ClientMessage message =
        ClientMessage.newBuilder()
            .setLogin(LoginRequest.newBuilder().setUsername(username).setPassword(password))
            .build();
    return send(message, (reply, nowMs) -> session(reply.getSession(), null));
  }

  /**
   * Signs in with the token of an earlier login (after a reconnect); no password needed. When that
   * sign-in still holds a seat, this connection is back in the match ({@link Session#matchId()}).
   */
  public CompletableFuture<Session> resume(String sessionToken) {
    ClientMessage message = ClientMessage.newBuilder()
                                .setResume(ResumeRequest.newBuilder().setSessionToken(sessionToken))
                                .build();
    return send(message, (reply, nowMs) -> session(reply.getSession(), sessionToken));
  }

  /** The server's matches. */
  public CompletableFuture<List<MatchInfo>> listMatches() {
    ClientMessage message =
        ClientMessage.newBuilder().setListMatches(ListMatchesRequest.getDefaultInstance()).build();
    return send(message, (reply, nowMs) -> {
      List<MatchInfo> matches = new ArrayList<>();
      for (io.ricochet.wire.ControlProto.MatchInfo match :
          reply.getListMatches().getMatchesList()) {
        matches.add(MatchInfo.of(match));
      }
      return Collections.unmodifiableList(matches);
    });
  }

  /**
   * Creates a match ({@code name} 1..32 bytes, {@code maxPlayers} 1..64 or 0 for the default 16,
   * {@code map} empty for the default); the creator is not joined.
   */
  public CompletableFuture<MatchInfo> createMatch(String name, int maxPlayers, String map) {
    ClientMessage message =
        ClientMessage.newBuilder()
            .setCreateMatch(
                CreateMatchRequest.newBuilder().setName(name).setMaxPlayers(maxPlayers).setMap(map))
            .build();
    return send(message, (reply, nowMs) -> MatchInfo.of(reply.getCreateMatch().getMatch()));
  }

  /**
   * Takes a seat in match {@code matchId}; completes with what the game channel needs to connect
   * within {@link JoinTicket#tokenExpiresInMs()}. Joining the match again gives a fresh ticket
   * (how a client reconnects its game channel from a new address).
   */
  public CompletableFuture<JoinTicket> joinMatch(long matchId) {
    ClientMessage message =
        ClientMessage.newBuilder()
            .setJoinMatch(JoinMatchRequest.newBuilder().setMatchId((int) matchId))
            .build();
    return send(message, this::joinTicket);
  }

  private JoinTicket joinTicket(ServerMessage reply, long nowMs) throws RicochetException {
    String[] why = new String[1];
    JoinTicket ticket = JoinTicket.of(host, reply.getJoinMatch(), nowMs, why);
    if (ticket == null) {
      throw new RicochetException(RicochetException.Kind.INVALID_REPLY, null, null, why[0]);
    }
    return ticket;
  }

  /**
   * Joins match {@code matchId} and connects its game channel: completes with the {@link
   * GameConnection} once the handshake is done (after {@link GameListener#onConnected}), or fails
   * with the join's error or {@link RicochetException.Kind#GAME_CONNECT_FAILED}. Calling it again
   * while in the match gives a fresh token: how a client reconnects from a new address.
   */
  public CompletableFuture<GameConnection> joinMatch(long matchId, GameListener listener) {
    if (listener == null) throw new NullPointerException("listener");
    return joinMatch(matchId).thenCompose(ticket -> connectGame(ticket, listener));
  }

  /**
   * Connects the game channel with a ticket of {@link #joinMatch(long)} (within its {@link
   * JoinTicket#tokenExpiresInMs()}); completes as {@link #joinMatch(long, GameListener)} does. The
   * listener is called on this client's listener executor. {@link #close()} closes it as well.
   */
  public CompletableFuture<GameConnection> connectGame(JoinTicket ticket, GameListener listener) {
    if (ticket == null || listener == null) throw new NullPointerException("ticket or listener");
    synchronized (this) {
      GameConnection game;
      try {
        if (closed) {
          throw new RicochetException(RicochetException.Kind.CLOSED, null, null, "client closed");
        }
        long matchId = ticket.matchId();
        game = GameConnection.create(ticket, listener, executor, System.nanoTime() / 1_000_000,
            () -> joinMatch(matchId), this::forgetEndedGames);
      } catch (RicochetException e) {
        CompletableFuture<GameConnection> failed = new CompletableFuture<>();
        post(() -> failed.completeExceptionally(e));
        return failed;
      }
      games.add(game);
      return game.start();
    }
  }

  /**
   * Asks the fleet for a seat in a match of {@code mode} ("ffa", "tdm") on {@code map} (empty: any
   * map): completes with where to play (PROTOCOL.md, Placement), possibly on another server of the
   * fleet; then {@link #follow} it and {@link #joinMatch(Assignment, GameListener)} there before
   * {@link Assignment#expiresAtMs()}. A new findMatch drops the account's earlier unused ticket.
   * Fails with the server's NO_SERVER_AVAILABLE (no seat anywhere, or placement is off on this
   * server: retry later, or use {@link #listMatches}), UNKNOWN_MODE_OR_MAP, FIND_MATCH_RATE_LIMITED
   * (retry later), INVALID_REQUEST or SERVER_BUSY, or with INVALID_REPLY when the assignment cannot
   * be followed ({@link io.ricochet.client.core.control.AssignmentRefusal} in the message).
   */
  public CompletableFuture<Assignment> findMatch(String mode, String map) {
    ClientMessage message =
        ClientMessage.newBuilder()
            .setFindMatch(FindMatchRequest.newBuilder().setMode(mode).setMap(map))
            .build();
    return send(message, (reply, nowMs) -> {
      Assignment.Result result = Assignment.of(reply.getFindMatch().getAssignment(), nowMs);
      if (result.assignment() == null) {
        throw new RicochetException(RicochetException.Kind.INVALID_REPLY, null, null,
            "find_match reply refused (" + result.refusal().counterName()
                + "): " + result.detail());
      }
      return result.assignment();
    });
  }

  /**
   * The client to join {@code assignment}'s match with: this one when the assignment is on this
   * server; otherwise a new client of the server it names, built with this one's settings
   * (listener, listener executor, timeouts, TLS provider, resume back-off) and pinned to the
   * assignment's certificate fingerprint, signed in by resuming this client's session (the same
   * token: the fleet's servers share their sessions). The pin is trusted as the assignment is: it
   * came over this client's own pinned (or validated) connection, from a server of the same
   * fleet. Completes once the resume is answered; then {@link #joinMatch(Assignment,
   * GameListener)} on the client it gives, before the ticket expires. A new client is the
   * caller's to close, and calls the same {@link Listener} (its MatchResults, its disconnects);
   * this one stays open and signed in (close it when done with it). Fails
   * with REFUSED_LOCALLY when this client is not signed in ({@link
   * io.ricochet.client.core.control.RequestRefusal#WRONG_STATE}) or the ticket has already
   * expired (errorCode EXPIRED_TICKET: nothing was sent; {@link #findMatch} again), or with what
   * ended the resume there, or CLOSED when this client was closed meanwhile (the new client is
   * then closed).
   */
  public CompletableFuture<RicochetClient> follow(Assignment assignment) {
    if (assignment == null) throw new NullPointerException("assignment");
    CompletableFuture<RicochetClient> future = new CompletableFuture<>();
    RicochetException refused = null;
    SignedIn was = signedIn.get();
    synchronized (this) {
      if (closed) {
        refused = new RicochetException(RicochetException.Kind.CLOSED, null, null, "client closed");
      } else if (was == null || was.connection != connection) {
        refused = new RicochetException(RicochetException.Kind.REFUSED_LOCALLY, null,
            RequestRefusal.WRONG_STATE, "follow needs a signed-in client: login or resume first");
      } else if (assignment.expiredAt(nowMs())) {
        refused = new RicochetException(RicochetException.Kind.REFUSED_LOCALLY,
            ErrorCode.EXPIRED_TICKET, null,
            "the assignment's ticket expired " + (nowMs() - assignment.expiresAtMs())
                + " ms ago: find a match again");
      }
    }
    if (refused != null) {
      RicochetException failure = refused;
      post(() -> future.completeExceptionally(failure));
      return future;
    }
    if (assignment.onThisServer()) {
      post(() -> future.complete(this));
      return future;
    }
    RicochetClient there = new RicochetClient(settings.copyFor(
        assignment.host(), assignment.controlPort(), assignment.certificateSha256()));
    there.resume(was.session.sessionToken()).whenComplete((session, failure) -> {
      boolean closedMeanwhile;
      synchronized (this) {
        closedMeanwhile = closed;
      }
      if (failure == null && !closedMeanwhile) {
        post(() -> future.complete(there));
        return;
      }
      there.close();
      Throwable cause = closedMeanwhile
          ? new RicochetException(RicochetException.Kind.CLOSED, null, null, "client closed")
          : failure instanceof CompletionException&& failure.getCause() != null ? failure.getCause()
                                                                                : failure;
      post(() -> future.completeExceptionally(cause));
    });
    return future;
  }

  /**
   * Joins the match of {@code assignment} with its ticket, on the server it names (this client
   * when {@link Assignment#onThisServer()}, else the client {@link #follow} gave): completes as
   * {@link #joinMatch(long)} does. Fails with the server's UNKNOWN_TICKET (already used, another
   * server's or account's), EXPIRED_TICKET ({@link #findMatch} again), MATCH_FULL or
   * MATCH_NOT_FOUND (the match filled up or ended meanwhile: find again) or any join_match error.
   */
  public CompletableFuture<JoinTicket> joinMatch(Assignment assignment) {
    ClientMessage message = ClientMessage.newBuilder()
                                .setJoinMatch(JoinMatchRequest.newBuilder().setTicket(
                                    ByteString.copyFrom(assignment.ticket())))
                                .build();
    return send(message, this::joinTicket);
  }

  /**
   * Joins {@code assignment}'s match with its ticket and connects its game channel: completes as
   * {@link #joinMatch(long, GameListener)} does. A reconnect of that game channel joins the match
   * again by its id, as any joined match's does.
   */
  public CompletableFuture<GameConnection> joinMatch(Assignment assignment, GameListener listener) {
    if (listener == null) throw new NullPointerException("listener");
    return joinMatch(assignment).thenCompose(ticket -> connectGame(ticket, listener));
  }

  /** Says {@code text} (1..200 bytes of UTF-8, no control or format characters) to the match. */
  public CompletableFuture<Void> chat(String text) {
    ClientMessage message =
        ClientMessage.newBuilder().setChat(ChatRequest.newBuilder().setText(text)).build();
    return send(message, (reply, nowMs) -> null);
  }

  /** Gives up the seat in the match. */
  public CompletableFuture<Void> leave() {
    ClientMessage message =
        ClientMessage.newBuilder().setLeaveMatch(LeaveMatchRequest.getDefaultInstance()).build();
    return send(message, (reply, nowMs) -> null);
  }

  /** Revokes this connection's session token (and leaves the match, if in one). */
  public CompletableFuture<Void> logout() {
    ClientMessage message =
        ClientMessage.newBuilder().setLogout(LogoutRequest.getDefaultInstance()).build();
    return send(message, (reply, nowMs) -> null);
  }

  /**
   * The control connection's state as the replies have set it; CLOSED while none is open (before
   * the first call, while connecting, after a disconnect).
   */
  public synchronized ControlState state() {
    return connection == null ? ControlState.CLOSED : connection.state();
  }

  /**
   * Closes the connection (pending futures fail with {@link RicochetException.Kind#CLOSED}), waits
   * for its threads and, when the client made its own, the listener thread. Later calls fail.
   */
  @Override
  public void close() {
    List<ControlConnection> connections;
    List<GameConnection> openGames;
    List<Call> waiting;
    synchronized (this) {
      if (closed) return;
      closed = true;
      if (backoff != null) backoff.stop();
      waiting = new ArrayList<>(waitingForResume);
      waitingForResume.clear();
      openGames = new ArrayList<>(games);
      games.clear();
      connections = new ArrayList<>(retired);
      retired.clear();
      if (connection != null) connections.add(connection);
    }
    RicochetException closedFailure =
        new RicochetException(RicochetException.Kind.CLOSED, null, null, "client closed");
    for (Call call : waiting) call.handler.onFailure(closedFailure);
    resumer.shutdownNow();
    boolean interrupted = false;
    if (Thread.currentThread() != resumerThread) {
      try {
        resumer.awaitTermination(10, TimeUnit.SECONDS);
        joinEnding(resumerThread);
      } catch (InterruptedException e) {
        interrupted = true;
      }
    }
    for (GameConnection game : openGames) game.close();
    for (ControlConnection each : connections) {
      try {
        each.close();
      } catch (InterruptedException e) {
        interrupted = true;
      }
    }
    if (ownedExecutor != null) {
      ownedExecutor.shutdown();
      // From a listener callback the listener thread cannot wait for itself: it ends after it.
      if (Thread.currentThread() != listenerThread) {
        try {
          if (!ownedExecutor.awaitTermination(10, TimeUnit.SECONDS)) ownedExecutor.shutdownNow();
          joinEnding(listenerThread);
        } catch (InterruptedException e) {
          interrupted = true;
        }
      }
    }
    if (interrupted) Thread.currentThread().interrupt();
  }

  /**
   * Waits (at most 10 s) for a terminated executor's last thread to finish exiting: an executor
   * is terminated a moment before its worker thread is no longer alive.
   */
  private static void joinEnding(Thread thread) throws InterruptedException {
    if (thread != null) thread.join(10_000);
  }

  /** Drops the game connections that ended (called on the I/O thread of one as it ends). */
  private synchronized void forgetEndedGames() {
    games.removeIf(game -> !game.isOpen());
  }

  /** Cuts the current TCP connection as a lost network would (tests of reconnects). */
  synchronized void dropConnectionForTest() {
    if (connection != null) connection.dropForTest();
  }

  /**
   * Runs {@code calls} (calls of this client) so that every request they make is checked by the
   * session before any reply is handled, as if they were made faster than the server answers:
   * the connection's lock is held throughout (tests of a request crossing a reply).
   */
  void pipelineForTest(Runnable calls) {
    synchronized (this) {
      if (connection == null) {
        calls.run();
        return;
      }
      synchronized (connection) {
        calls.run();
      }
    }
  }

  /** Turns a reply into a call's result; may throw to fail the call. */
  private interface Converter<T> {
    T convert(ServerMessage reply, long nowMs) throws RicochetException;
  }

  private static Session session(SessionReply reply, String resumedToken) {
    // A login's match_id means nothing (PROTOCOL.md): only a resume is back in a match.
    return new Session(reply.getAccountId(), reply.getUsername(),
        resumedToken != null ? resumedToken : reply.getSessionToken(), reply.getExpiresUnixMs(),
        resumedToken != null ? reply.getMatchId() & 0xffffffffL : 0);
  }

  private <T> CompletableFuture<T> send(ClientMessage message, Converter<T> converter) {
    CompletableFuture<T> future = new CompletableFuture<>();
    ControlConnection.ReplyHandler handler = new ControlConnection.ReplyHandler() {
      @Override
      public void onReply(ControlConnection from, ServerMessage reply, long nowMs) {
        if (reply.getBodyCase() == ServerMessage.BodyCase.ERROR) {
          io.ricochet.wire.ControlProto.Error error = reply.getError();
          fail(new RicochetException(RicochetException.Kind.SERVER_ERROR, error.getCode(), null,
              error.getCode() + ": " + error.getMessage()));
          return;
        }
        T result;
        try {
          result = converter.convert(reply, nowMs);
        } catch (RicochetException e) {
          fail(e);
          return;
        }
        if (result instanceof Session) {
          signedIn.set(new SignedIn(from, (Session) result)); // login or resume
        } else if (message.hasLogout()) {
          signedIn.set(null);
        }
        post(() -> future.complete(result));
      }

      @Override
      public void onFailure(RicochetException failure) {
        fail(failure);
      }

      private void fail(RicochetException failure) {
        post(() -> future.completeExceptionally(failure));
      }
    };
    synchronized (this) {
      if (closed) {
        handler.onFailure(
            new RicochetException(RicochetException.Kind.CLOSED, null, null, "client closed"));
        return future;
      }
      if (resumingAfter(connection)) {
        waitingForResume.addLast(new Call(message, handler));
      } else {
        submitNow(message, handler);
      }
    }
    return future;
  }

  /**
   * Submits on the current connection, or on a new one when there is none or it is over (lock
   * held).
   */
  private void submitNow(ClientMessage message, ControlConnection.ReplyHandler handler) {
    if (connection == null || connection.isOver()) {
      if (connection != null) {
        retired.removeIf(ControlConnection::finished);
        retired.add(connection);
      }
      ConnectionEvents events = new ConnectionEvents();
      connection = new ControlConnection(transport, requestTimeoutMs, keepAliveMs, events);
      events.connection = connection;
      // Submitted before it starts, so a connection that fails at once fails this call too.
      connection.submit(message, handler);
      connection.start();
    } else {
      connection.submit(message, handler);
    }
  }

  /**
   * Whether the client is resuming, having just started to when {@code ended} (the current
   * connection) is over, was signed in and ended for a reason worth resuming (lock held). Called
   * by the next call and by the connection's end, whichever comes first: the first starts it.
   */
  private boolean resumingAfter(ControlConnection ended) {
    if (backoff == null) return false;
    if (backoff.state() != ResumeState.IDLE) return true;
    if (closed || ended == null || ended != connection || !ended.isOver()) return false;
    SignedIn was = signedIn.get();
    if (was == null || was.connection != ended) return false;
    Disconnect why = ended.disconnect();
    if (why == null || !signedIn.compareAndSet(was, null)) return false;
    if (!ResumeBackoff.worthResuming(why.reason(), why.errorCode())) return false;
    resuming = was.session;
    backoff.lost(nowMs());
    scheduleAttempt();
    return true;
  }

  /** Runs {@link #attemptResume} when the back-off says (lock held). */
  private void scheduleAttempt() {
    long delayMs = Math.max(0, backoff.nextAttemptAtMs() - nowMs());
    try {
      resumer.schedule(this::attemptResume, delayMs, TimeUnit.MILLISECONDS);
    } catch (RejectedExecutionException e) {
      // closing: nothing more to resume
    }
  }

  /** The back-off's time came: connect (or reuse the open connection) and send the resume. */
  private void attemptResume() {
    synchronized (this) {
      if (closed || backoff.state() != ResumeState.WAITING) return;
      if (!backoff.startAttempt(nowMs())) {
        scheduleAttempt(); // early
        return;
      }
      String token = resuming.sessionToken();
      ClientMessage message = ClientMessage.newBuilder()
                                  .setResume(ResumeRequest.newBuilder().setSessionToken(token))
                                  .build();
      submitNow(message, new ControlConnection.ReplyHandler() {
        @Override
        public void onReply(ControlConnection from, ServerMessage reply, long nowMs) {
          onResumer(() -> resumeAnswered(from, reply, null));
        }

        @Override
        public void onFailure(RicochetException failure) {
          onResumer(() -> resumeAnswered(null, null, failure));
        }
      });
    }
  }

  /**
   * An attempt's answer: the {@code reply} on {@code from}, or the {@code failure} that ended it.
   * Signed in: sends the waiting calls. Else tries again after the back-off, or gives up.
   */
  private void resumeAnswered(
      ControlConnection from, ServerMessage reply, RicochetException failure) {
    List<Call> failed = null;
    RicochetException gaveUp = null;
    synchronized (this) {
      if (closed || backoff.state() != ResumeState.ATTEMPTING) return;
      if (reply != null && reply.getBodyCase() == ServerMessage.BodyCase.SESSION) {
        Session session = session(reply.getSession(), resuming.sessionToken());
        signedIn.set(new SignedIn(from, session));
        backoff.resumed();
        resuming = null;
        Call call;
        while ((call = waitingForResume.pollFirst()) != null) submitNow(call.message, call.handler);
        post(() -> listener.onResumed(session));
        return;
      }
      boolean retryable;
      RicochetException why;
      if (reply != null && reply.getBodyCase() == ServerMessage.BodyCase.ERROR) {
        ErrorCode code = reply.getError().getCode();
        retryable = ResumeBackoff.worthRetrying(code);
        why = new RicochetException(RicochetException.Kind.SERVER_ERROR, code, null,
            "resuming the session: " + code + ": " + reply.getError().getMessage());
      } else if (reply != null) {
        retryable = false;
        why = new RicochetException(RicochetException.Kind.INVALID_REPLY, null, null,
            "resume answered with " + reply.getBodyCase());
      } else {
        retryable = failure.kind() != RicochetException.Kind.PIN_MISMATCH;
        why = failure;
      }
      if (backoff.attemptFailed(nowMs(), retryable)) {
        scheduleAttempt();
        return;
      }
      int attempts = backoff.failedAttempts();
      backoff.stop();
      resuming = null;
      gaveUp = new RicochetException(why.kind() == RicochetException.Kind.SERVER_ERROR
              ? RicochetException.Kind.SERVER_ERROR
              : RicochetException.Kind.DISCONNECTED,
          why.errorCode(), null,
          "gave up resuming the session after " + attempts + " attempt(s): " + why.getMessage());
      failed = new ArrayList<>(waitingForResume);
      waitingForResume.clear();
    }
    for (Call call : failed) call.handler.onFailure(gaveUp);
    RicochetException reported = gaveUp;
    post(() -> listener.onResumeFailed(reported));
  }

  /** Runs {@code task} on the resume thread (unless closing). */
  private void onResumer(Runnable task) {
    try {
      resumer.execute(task);
    } catch (RejectedExecutionException e) {
      // closing: nothing more to resume
    }
  }

  /** A connection ended: starts resuming when it should (unless a call already did). */
  private void connectionEnded(ControlConnection ended) {
    synchronized (this) {
      resumingAfter(ended);
    }
  }

  private static long nowMs() {
    return System.nanoTime() / 1_000_000;
  }

  /** What one connection reports, handed on to the listener and the resume thread. */
  private final class ConnectionEvents implements ControlConnection.Callbacks {
    ControlConnection connection; // set before it starts

    @Override
    public void onMatchResults(MatchResults results) {
      post(() -> listener.onMatchResults(results));
    }

    @Override
    public void onDisconnected(Disconnect disconnect) {
      post(() -> listener.onDisconnected(disconnect));
      ControlConnection ended = connection;
      onResumer(() -> connectionEnded(ended));
    }
  }

  /**
   * Runs {@code task} on the listener executor; when it refuses (an app executor already shut
   * down), runs it here so no future is left hanging.
   */
  private void post(Runnable task) {
    try {
      executor.execute(task);
    } catch (RejectedExecutionException e) {
      task.run();
    }
  }
}
