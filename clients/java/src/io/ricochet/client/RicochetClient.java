package io.ricochet.client;

import io.ricochet.client.core.control.ControlSession;
import io.ricochet.client.core.control.ControlState;
import io.ricochet.wire.ControlProto.ChatRequest;
import io.ricochet.wire.ControlProto.ClientMessage;
import io.ricochet.wire.ControlProto.CreateMatchRequest;
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
import java.util.ArrayList;
import java.util.Collections;
import java.util.List;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.Executor;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.RejectedExecutionException;
import java.util.concurrent.TimeUnit;

/**
 * A client of a Ricochet server's control channel (PROTOCOL.md, Control channel): accounts,
 * sessions, the match directory, chat. Every call returns a {@link CompletableFuture} that
 * completes with a typed result, or fails with a {@link RicochetException} carrying the server's
 * error code. Made by {@link #builder()}; thread-safe; call it from any thread (it never blocks).
 *
 * <p>The first call connects (TCP, TLS 1.3, the certificate pin) on a background thread; when the
 * connection ends ({@link Listener#onDisconnected}), the next call connects again, unauthenticated:
 * {@link #resume} with the session token signs the new connection in. Futures complete, and the
 * {@link Listener} is called, on the listener executor only (by default one thread of the client's
 * own), never on the caller's thread or an I/O thread. {@link #close()} ends every thread the
 * client started.
 */
public final class RicochetClient implements AutoCloseable {
  /** What the server says unasked. Called on the listener executor; every method a no-op. */
  public interface Listener {
    /** A match this account played ended; the connection is back out of the match. */
    default void onMatchResults(MatchResults results) {}

    /** The control connection ended (the next call opens a new one). */
    default void onDisconnected(Disconnect disconnect) {}
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

    private Builder() {}

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
      return new RicochetClient(this);
    }
  }

  /** A builder with the defaults. */
  public static Builder builder() {
    return new Builder();
  }

  private final String host;
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

  private RicochetClient(Builder builder) {
    host = builder.host;
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

  /** Signs in with the token of an earlier login (after a reconnect); no password needed. */
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
    return send(message, (reply, nowMs) -> {
      String[] why = new String[1];
      JoinTicket ticket = JoinTicket.of(host, reply.getJoinMatch(), nowMs, why);
      if (ticket == null) {
        throw new RicochetException(RicochetException.Kind.INVALID_REPLY, null, null, why[0]);
      }
      return ticket;
    });
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
    synchronized (this) {
      if (closed) return;
      closed = true;
      openGames = new ArrayList<>(games);
      games.clear();
      connections = new ArrayList<>(retired);
      retired.clear();
      if (connection != null) connections.add(connection);
    }
    for (GameConnection game : openGames) game.close();
    boolean interrupted = false;
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
        } catch (InterruptedException e) {
          interrupted = true;
        }
      }
    }
    if (interrupted) Thread.currentThread().interrupt();
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
    return new Session(reply.getAccountId(), reply.getUsername(),
        resumedToken != null ? resumedToken : reply.getSessionToken(), reply.getExpiresUnixMs());
  }

  private <T> CompletableFuture<T> send(ClientMessage message, Converter<T> converter) {
    CompletableFuture<T> future = new CompletableFuture<>();
    ControlConnection.ReplyHandler handler = new ControlConnection.ReplyHandler() {
      @Override
      public void onReply(ServerMessage reply, long nowMs) {
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
      if (connection == null || connection.isOver()) {
        if (connection != null) {
          retired.removeIf(ControlConnection::finished);
          retired.add(connection);
        }
        // Submitted before it starts, so a connection that fails at once fails this call too.
        connection = new ControlConnection(transport, requestTimeoutMs, keepAliveMs, callbacks());
        connection.submit(message, handler);
        connection.start();
      } else {
        connection.submit(message, handler);
      }
    }
    return future;
  }

  private ControlConnection.Callbacks callbacks() {
    return new ControlConnection.Callbacks() {
      @Override
      public void onMatchResults(MatchResults results) {
        post(() -> listener.onMatchResults(results));
      }

      @Override
      public void onDisconnected(Disconnect disconnect) {
        post(() -> listener.onDisconnected(disconnect));
      }
    };
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
