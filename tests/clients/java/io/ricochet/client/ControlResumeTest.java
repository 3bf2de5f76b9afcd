package io.ricochet.client;

import static io.ricochet.client.ClientTesting.await;
import static io.ricochet.client.ClientTesting.failure;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.core.control.ControlCloseReason;
import io.ricochet.client.core.control.ControlState;
import io.ricochet.client.core.control.RequestRefusal;
import io.ricochet.client.core.transport.DisconnectReason;
import io.ricochet.client.testing.ServerProcess;
import io.ricochet.client.testing.TcpRelay;
import io.ricochet.wire.ControlProto.ErrorCode;
import io.ricochet.wire.ControlProto.MatchResults;
import java.util.ArrayList;
import java.util.HashSet;
import java.util.List;
import java.util.Set;
import java.util.concurrent.BlockingQueue;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.LinkedBlockingQueue;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicInteger;
import java.util.concurrent.atomic.AtomicReference;
import java.util.function.BooleanSupplier;
import org.junit.jupiter.api.AfterAll;
import org.junit.jupiter.api.AfterEach;
import org.junit.jupiter.api.BeforeAll;
import org.junit.jupiter.api.BeforeEach;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.Timeout;

/**
 * A lost control connection against the real server, through a TCP relay the test cuts (both
 * sides see the connection end, as when a phone loses its network) and can keep refusing (the
 * network still down): the client resumes with the session token by itself, calls made meanwhile
 * wait, a revoked or banned session is not retried, attempts that never connect give up, and a
 * game connection plays on while the control channel is away; the resumed connection is back in
 * its match (chat, leave and the match's results work there, nothing is kicked). Bounded waits
 * only.
 */
@Timeout(value = 120, unit = TimeUnit.SECONDS)
class ControlResumeTest {
  private static ServerProcess server;
  private TcpRelay relay;

  /** What the client's listener saw, in order. */
  private static final class Events implements RicochetClient.Listener {
    final BlockingQueue<Object> seen = new LinkedBlockingQueue<>();

    @Override
    public void onDisconnected(Disconnect disconnect) {
      seen.add(disconnect);
    }

    @Override
    public void onResumed(Session session) {
      seen.add(session);
    }

    @Override
    public void onResumeFailed(RicochetException failure) {
      seen.add(failure);
    }

    @Override
    public void onMatchResults(MatchResults results) {
      seen.add(results);
    }

    <T> T next(Class<T> kind) throws InterruptedException {
      Object event = seen.poll(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS);
      assertNotNull(
          event, "no " + kind.getSimpleName() + " within " + ClientTesting.WAIT_MS + " ms");
      return assertInstanceOf(kind, event);
    }
  }

  @BeforeAll
  static void startTheServer() throws Exception {
    server = ServerProcess.arena(ClientTesting.FAST_ACCOUNTS);
  }

  @AfterAll
  static void stopTheServer() throws Exception {
    if (server != null) server.close();
  }

  @BeforeEach
  void startTheRelay() throws Exception {
    relay = new TcpRelay(server.controlPort());
  }

  @AfterEach
  void stopTheRelay() throws Exception {
    relay.close();
  }

  /** A client through the relay, pinned, with a short deterministic back-off (bound 50 ms, ×2). */
  private RicochetClient.Builder viaRelay(Events events) {
    return viaRelay(events, server, relay);
  }

  /** As {@link #viaRelay(Events)}, through {@code through} to {@code pinned}. */
  private static RicochetClient.Builder viaRelay(
      Events events, ServerProcess pinned, TcpRelay through) {
    return RicochetClient.builder()
        .host("127.0.0.1")
        .controlPort(through.port())
        .pinSha256(pinned.fingerprint())
        .listener(events)
        .resumeBackoffMs(50, 400)
        .resumeAttempts(50)
        .resumeJitterForTest(() -> 1.0);
  }

  /** Polls {@code condition} every 10 ms for at most {@link ClientTesting#WAIT_MS}. */
  private static boolean eventually(BooleanSupplier condition) throws InterruptedException {
    long giveUpAt = System.nanoTime() + ClientTesting.WAIT_MS * 1_000_000;
    while (!condition.getAsBoolean()) {
      if (System.nanoTime() > giveUpAt) return false;
      Thread.sleep(10);
    }
    return true;
  }

  /** The live threads named "ricochet-*" (the library's). */
  private static Set<Thread> ricochetThreads() {
    Set<Thread> threads = new HashSet<>();
    for (Thread thread : Thread.getAllStackTraces().keySet()) {
      if (thread.isAlive() && thread.getName().startsWith("ricochet-")) threads.add(thread);
    }
    return threads;
  }

  /**
   * The names of the library's threads alive now that were not in {@code before} (other test
   * classes of the JVM may leave threads ending meanwhile: only new ones count).
   */
  private static String startedSince(Set<Thread> before) {
    List<String> names = new ArrayList<>();
    for (Thread thread : ricochetThreads()) {
      if (!before.contains(thread)) names.add(thread.getName());
    }
    return names.toString();
  }

  /** Cuts the signed-in connection with the network left down; the loss is reported. */
  private void loseTheNetwork(Events events) throws InterruptedException {
    relay.refuse(true);
    relay.cut();
    Disconnect lost = events.next(Disconnect.class);
    assertEquals(ControlCloseReason.CONNECTION_LOST, lost.reason(), lost.toString());
  }

  @Test
  void aCutConnectionIsResumedAndCallsMadeMeanwhileWaitForIt() throws Exception {
    Events events = new Events();
    Set<Thread> threadsBefore = ricochetThreads();
    try (RicochetClient client = viaRelay(events).build()) {
      await(client.register("resumer", "password-resumer"));
      Session session = await(client.login("resumer", "password-resumer"));
      assertEquals(1, relay.accepted());
      loseTheNetwork(events);

      CompletableFuture<List<MatchInfo>> meanwhile = client.listMatches();
      assertTrue(eventually(() -> relay.accepted() >= 4), "attempts while the network is down");
      assertFalse(meanwhile.isDone(), "a call made while resuming waits: " + meanwhile);
      relay.refuse(false);

      assertFalse(await(meanwhile).isEmpty(), "the waiting call went out once resumed");
      Session resumed = events.next(Session.class);
      assertEquals(session.accountId(), resumed.accountId());
      assertEquals("resumer", resumed.username());
      assertEquals(session.sessionToken(), resumed.sessionToken());
      assertEquals(0, resumed.matchId(), "it held no seat");
      assertEquals(ControlState.AUTHENTICATED, client.state());
      // The same account, signed in: a call that needs it succeeds.
      MatchInfo created = await(client.createMatch("resumed_match", 4, ""));
      assertEquals("resumed_match", created.name());
      assertNull(events.seen.poll(), "nothing more: " + events.seen);
    }
    assertEquals("[]", startedSince(threadsBefore), "every thread the client started ended");
  }

  @Test
  void aSessionRevokedWhileAwayIsNotRetried() throws Exception {
    Events events = new Events();
    try (RicochetClient client = viaRelay(events).build();
         RicochetClient other = ClientTesting.pinned(server).build()) {
      await(client.register("revoked", "password-revoked"));
      Session session = await(client.login("revoked", "password-revoked"));
      loseTheNetwork(events);
      CompletableFuture<List<MatchInfo>> meanwhile = client.listMatches();

      // Elsewhere the token is resumed and logged out: revoked.
      await(other.resume(session.sessionToken()));
      await(other.logout());
      relay.refuse(false);

      RicochetException gaveUp = events.next(RicochetException.class);
      assertEquals(ErrorCode.UNKNOWN_SESSION, gaveUp.errorCode(), gaveUp.getMessage());
      RicochetException waited = failure(meanwhile);
      assertEquals(ErrorCode.UNKNOWN_SESSION, waited.errorCode(), waited.getMessage());
      // No more attempts: the next call goes out at once on the open, unauthenticated connection.
      int accepted = relay.accepted();
      RicochetException refused = failure(client.listMatches());
      assertEquals(RequestRefusal.WRONG_STATE, refused.refusal(), refused.getMessage());
      assertEquals(accepted, relay.accepted());
      assertEquals(ControlState.UNAUTHENTICATED, client.state());
      assertNull(events.seen.poll(), "no resume after the refusal: " + events.seen);
      // Signing in again works.
      await(client.login("revoked", "password-revoked"));
      assertFalse(await(client.listMatches()).isEmpty());
    }
  }

  @Test
  void aBannedAccountIsNotResumed() throws Exception {
    Events events = new Events();
    try (RicochetClient client = viaRelay(events).build()) {
      await(client.register("banned_roamer", "password-banned"));
      await(client.login("banned_roamer", "password-banned"));
      assertEquals(200, server.ban("banned_roamer"));
      Disconnect banned = events.next(Disconnect.class);
      assertEquals(ControlCloseReason.SERVER_ERROR, banned.reason());
      assertEquals(ErrorCode.ACCOUNT_BANNED, banned.errorCode());
      // The next call opens a new connection, unauthenticated; no resume was tried.
      RicochetException refused = failure(client.listMatches());
      assertEquals(RequestRefusal.WRONG_STATE, refused.refusal(), refused.getMessage());
      assertEquals(2, relay.accepted());
      assertNull(events.seen.poll(), "no resume of a banned account: " + events.seen);
    }
  }

  @Test
  void attemptsThatNeverConnectGiveUp() throws Exception {
    Events events = new Events();
    Set<Thread> threadsBefore = ricochetThreads();
    try (RicochetClient client = viaRelay(events).resumeAttempts(3).build()) {
      await(client.register("unlucky", "password-unlucky"));
      await(client.login("unlucky", "password-unlucky"));
      loseTheNetwork(events);
      CompletableFuture<List<MatchInfo>> meanwhile = client.listMatches();

      RicochetException gaveUp = events.next(RicochetException.class);
      assertEquals(RicochetException.Kind.DISCONNECTED, gaveUp.kind(), gaveUp.getMessage());
      assertTrue(gaveUp.getMessage().contains("3 attempt"), gaveUp.getMessage());
      assertEquals(RicochetException.Kind.DISCONNECTED, failure(meanwhile).kind());
      assertEquals(1 + 3, relay.accepted(), "the first connection and three attempts");
    }
    assertEquals("[]", startedSince(threadsBefore), "every thread the client started ended");
  }

  @Test
  void closingWhileResumingFailsTheWaitingCalls() throws Exception {
    Events events = new Events();
    Set<Thread> threadsBefore = ricochetThreads();
    RicochetClient client = viaRelay(events).build();
    await(client.register("closer", "password-closer"));
    await(client.login("closer", "password-closer"));
    loseTheNetwork(events);
    CompletableFuture<List<MatchInfo>> meanwhile = client.listMatches();
    client.close();
    assertEquals(RicochetException.Kind.CLOSED, failure(meanwhile).kind());
    int accepted = relay.accepted();
    relay.refuse(false);
    assertEquals("[]", startedSince(threadsBefore), "every thread the client started ended");
    assertEquals(accepted, relay.accepted(), "no attempt after close");
  }

  @Test
  void theGameConnectionPlaysOnAndTheResumedConnectionIsBackInItsMatch() throws Exception {
    Events events = new Events();
    AtomicInteger snapshots = new AtomicInteger();
    AtomicReference<DisconnectReason> gameEnded = new AtomicReference<>();
    GameListener counting = new GameListener() {
      @Override
      public void onSnapshot(GameSnapshot snapshot) {
        snapshots.incrementAndGet();
      }

      @Override
      public void onDisconnected(DisconnectReason reason) {
        gameEnded.set(reason);
      }
    };
    try (RicochetClient client = viaRelay(events).build()) {
      await(client.register("away_player", "password-away"));
      await(client.login("away_player", "password-away"));
      long matchId = await(client.listMatches()).get(0).matchId();
      GameConnection game = await(client.joinMatch(matchId, counting));
      assertTrue(eventually(() -> snapshots.get() >= 10), "snapshots before the loss");
      loseTheNetwork(events);
      int atLoss = snapshots.get();
      assertTrue(eventually(() -> snapshots.get() >= atLoss + 60), "a second of snapshots");
      assertTrue(game.isOpen());
      relay.refuse(false);
      // Back in the match (PROTOCOL.md, resume): the sign-in that joined plays its seat again.
      Session resumed = events.next(Session.class);
      assertEquals(matchId, resumed.matchId(), resumed.toString());
      assertEquals(ControlState.IN_MATCH, client.state());
      int atResume = snapshots.get();
      assertTrue(eventually(() -> snapshots.get() >= atResume + 30), "snapshots after the resume");
      MatchInfo match = await(client.listMatches()).get(0);
      assertEquals(matchId, match.matchId());
      assertEquals(1, match.players(), match.toString());
      // Chat goes out on the resumed connection (the server takes it only from the connection that
      // plays the account, while its game connection is up).
      await(client.chat("back on mobile"));
      // A fresh ticket for the same match moves nothing: the game connection is not kicked.
      JoinTicket ticket = await(client.joinMatch(matchId));
      assertEquals(matchId, ticket.matchId());
      int atTicket = snapshots.get();
      assertTrue(eventually(() -> snapshots.get() >= atTicket + 30), "snapshots after the ticket");
      assertNull(gameEnded.get(), "the game connection played on");
      assertTrue(game.isOpen());
      // Leaving works there and gives the seat up: the server ends the game connection, as left.
      await(client.leave());
      assertEquals(ControlState.AUTHENTICATED, client.state());
      assertTrue(eventually(() -> gameEnded.get() != null), "the game connection ended");
      assertEquals(DisconnectReason.LEFT, gameEnded.get());
      assertEquals(0, await(client.listMatches()).get(0).players());
      game.close();
      assertNull(events.seen.poll(), "nothing more: " + events.seen);
    }
  }

  @Test
  void theMatchResultsReachTheResumedConnection() throws Exception {
    String source = System.getProperty("ricochet.source_dir", ".");
    // A match that ends by itself a few seconds after its first player connects.
    try (ServerProcess shortMatch = new ServerProcess("count = 1\nmax_players = 4\nmaps = [\""
                 + source + "/server/maps/arena.toml\"]\nseed = 42\nwarmup_s = 0\n"
                 + "frag_limit = 0\nrecord = false\nmin_players = 1\ntime_limit_s = 6\n",
             "", ClientTesting.FAST_ACCOUNTS, ClientTesting.WAIT_MS);
         TcpRelay toShortMatch = new TcpRelay(shortMatch.controlPort())) {
      Events events = new Events();
      try (RicochetClient client = viaRelay(events, shortMatch, toShortMatch).build()) {
        await(client.register("results_player", "password-results"));
        await(client.login("results_player", "password-results"));
        long matchId = await(client.listMatches()).get(0).matchId();
        GameConnection game = await(client.joinMatch(matchId, new GameListener() {}));
        toShortMatch.cut(); // the network comes back at once: the next attempt gets through
        assertEquals(ControlCloseReason.CONNECTION_LOST, events.next(Disconnect.class).reason());
        assertEquals(matchId, events.next(Session.class).matchId());
        assertEquals(ControlState.IN_MATCH, client.state());
        // The time limit ends the match: its results come to the resumed connection.
        MatchResults results = events.next(MatchResults.class);
        assertEquals(matchId, results.getMatchId() & 0xffffffffL);
        assertEquals(1, results.getPlayersCount(), results.toString());
        assertEquals(ControlState.AUTHENTICATED, client.state());
        game.close();
      }
    }
  }
}
