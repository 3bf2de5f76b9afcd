package io.ricochet.client;

import static io.ricochet.client.ClientTesting.await;
import static io.ricochet.client.ClientTesting.failure;
import static io.ricochet.client.ClientTesting.pinned;
import static io.ricochet.client.ClientTesting.signedIn;
import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertNotEquals;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.core.control.ControlCloseReason;
import io.ricochet.client.core.control.ControlState;
import io.ricochet.client.testing.RealServer;
import io.ricochet.wire.ControlProto.ErrorCode;
import java.util.List;
import java.util.concurrent.ArrayBlockingQueue;
import java.util.concurrent.BlockingQueue;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.ExecutorService;
import java.util.concurrent.Executors;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.extension.RegisterExtension;

/**
 * The client against the real ricochet-server on 127.0.0.1: sign in, the directory,
 * reconnects.
 */
class RicochetClientTest {
  @RegisterExtension static final RealServer server = RealServer.arena(ClientTesting.FAST_ACCOUNTS);

  @Test
  void registerAndLoginWithTheRightPin() throws Exception {
    try (RicochetClient client = pinned(server.get()).build()) {
      assertEquals(ControlState.CLOSED, client.state(), "no connection before the first call");
      long accountId = await(client.register("Alice_1", "correct horse"));
      assertTrue(accountId > 0);
      Session session = await(client.login("alice_1", "correct horse"));
      assertEquals(accountId, session.accountId());
      // Names are unique ignoring case; a login in another case signs in the same account.
      assertTrue("Alice_1".equalsIgnoreCase(session.username()), session.username());
      assertTrue(session.sessionToken().matches("[0-9a-f]{64}"), session.sessionToken());
      assertTrue(session.expiresUnixMs() > System.currentTimeMillis());
      assertEquals(ControlState.AUTHENTICATED, client.state());
    }
  }

  @Test
  void thePinWorksWithoutColonsAndInLowerCase() throws Exception {
    String bare = server.get().fingerprint().replace(":", "").toLowerCase(java.util.Locale.ROOT);
    try (RicochetClient client = RicochetClient.builder()
                                     .host("127.0.0.1")
                                     .controlPort(server.get().controlPort())
                                     .pinSha256(bare)
                                     .build()) {
      assertTrue(await(client.register("bare_pin", "password-1")) > 0);
    }
  }

  @Test
  void theDirectoryGivesTypedResults() throws Exception {
    try (RicochetClient client = signedIn(server.get(), "directory")) {
      List<MatchInfo> matches = await(client.listMatches());
      assertEquals(1, matches.size(), matches.toString());
      MatchInfo arena = matches.get(0);
      assertTrue(arena.matchId() > 0);
      assertEquals("ffa", arena.mode());
      assertEquals(16, arena.maxPlayers());
      assertFalse(arena.map().isEmpty());

      MatchInfo created = await(client.createMatch("Friday night", 4, ""));
      assertEquals("Friday night", created.name());
      assertEquals(4, created.maxPlayers());
      assertEquals(0, created.players(), "the creator is not joined");
      assertNotEquals(arena.matchId(), created.matchId());
      assertEquals(2, await(client.listMatches()).size());

      JoinTicket ticket = await(client.joinMatch(arena.matchId()));
      assertEquals(ControlState.IN_MATCH, client.state());
      assertEquals(arena.matchId(), ticket.matchId());
      assertEquals("127.0.0.1", ticket.host());
      assertEquals(server.get().gamePort(), ticket.udpPort());
      assertEquals(32, ticket.clientToServerKey().length);
      assertEquals(32, ticket.serverToClientKey().length);
      assertFalse(java.util.Arrays.equals(ticket.clientToServerKey(), ticket.serverToClientKey()));
      assertTrue(ticket.connectToken().length > 0);
      assertTrue(ticket.tokenExpiresInMs() > 0 && ticket.tokenExpiresInMs() <= 30_000);
      assertEquals(60, ticket.tickRateHz());
      assertTrue(ticket.snapshotRateHz() >= 1 && ticket.snapshotRateHz() <= 60);
      assertTrue(ticket.timeoutMs() >= 1000);
      assertTrue(ticket.quantization().getTickS() > 0);
      assertTrue(ticket.hasCollisionWorld());
      assertTrue(ticket.collisionWorldBytes().length > 0);
      assertFalse(ticket.weapons().isEmpty(), "one WeaponSpec per weapon");
      // Joining the match again (how a client reconnects its game channel) within the token
      // reuse window gives the same unused token, its lifetime shorter.
      JoinTicket again = await(client.joinMatch(arena.matchId()));
      assertEquals(ControlState.IN_MATCH, client.state());
      assertEquals(32, again.clientToServerKey().length);
      if (again.receivedAtMs() - ticket.receivedAtMs() < 500) { // well inside the 1 s window
        assertArrayEquals(ticket.connectToken(), again.connectToken());
        assertArrayEquals(ticket.clientToServerKey(), again.clientToServerKey());
        assertTrue(again.tokenExpiresInMs() <= ticket.tokenExpiresInMs());
      }
      for (MatchInfo match : await(client.listMatches())) {
        if (match.matchId() == arena.matchId()) assertEquals(1, match.players(), "a reserved seat");
      }

      await(client.leave());
      assertEquals(ControlState.AUTHENTICATED, client.state());
      await(client.logout());
      assertEquals(ControlState.UNAUTHENTICATED, client.state());
    }
  }

  @Test
  void aDroppedSignedInConnectionResumesByItself() throws Exception {
    BlockingQueue<Object> events = new ArrayBlockingQueue<>(8);
    RicochetClient.Listener listener = new RicochetClient.Listener() {
      @Override
      public void onDisconnected(Disconnect disconnect) {
        events.add(disconnect);
      }

      @Override
      public void onResumed(Session session) {
        events.add(session);
      }
    };
    int threadsBefore = ClientTesting.ricochetThreads();
    try (RicochetClient client = pinned(server.get()).listener(listener).build()) {
      await(client.register("roamer", "password-roamer"));
      Session first = await(client.login("roamer", "password-roamer"));
      client.dropConnectionForTest();
      Object disconnect = events.poll(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS);
      assertNotNull(disconnect, "onDisconnected after the drop");
      assertEquals(ControlCloseReason.CONNECTION_LOST, ((Disconnect) disconnect).reason());

      // The client reconnects and resumes with the token by itself: a call made meanwhile waits.
      assertFalse(await(client.listMatches()).isEmpty());
      Object resumed = events.poll(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS);
      assertInstanceOf(Session.class, resumed, "onResumed after onDisconnected");
      assertEquals(first.accountId(), ((Session) resumed).accountId());
      assertEquals("roamer", ((Session) resumed).username());
      assertEquals(first.sessionToken(), ((Session) resumed).sessionToken());
      assertEquals(ControlState.AUTHENTICATED, client.state());
    }
    assertEquals(threadsBefore, ClientTesting.ricochetThreads(), "both connections' threads ended");
  }

  @Test
  void aDroppedConnectionAfterLogoutIsNotResumed() throws Exception {
    BlockingQueue<Object> events = new ArrayBlockingQueue<>(8);
    RicochetClient.Listener listener = new RicochetClient.Listener() {
      @Override
      public void onDisconnected(Disconnect disconnect) {
        events.add(disconnect);
      }

      @Override
      public void onResumed(Session session) {
        events.add(session);
      }
    };
    try (RicochetClient client = pinned(server.get()).listener(listener).build()) {
      await(client.register("leaver", "password-leaver"));
      Session session = await(client.login("leaver", "password-leaver"));
      await(client.logout());
      client.dropConnectionForTest();
      assertInstanceOf(Disconnect.class, events.poll(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS));
      // The next call connects unauthenticated; the revoked token is not tried.
      RicochetException refused = failure(client.listMatches());
      assertEquals(RicochetException.Kind.REFUSED_LOCALLY, refused.kind());
      assertEquals(ControlState.UNAUTHENTICATED, client.state());
      assertNull(events.poll(), "no resume after a logout");
      RicochetException revoked = failure(client.resume(session.sessionToken()));
      assertEquals(ErrorCode.UNKNOWN_SESSION, revoked.errorCode());
    }
  }

  @Test
  void requestsBeforeTheLoginReplyAreRefusedLocally() throws Exception {
    try (RicochetClient client = pinned(server.get()).build()) {
      RicochetException refused = failure(client.listMatches());
      assertEquals(RicochetException.Kind.REFUSED_LOCALLY, refused.kind());
      assertEquals(io.ricochet.client.core.control.RequestRefusal.WRONG_STATE, refused.refusal());
    }
  }

  @Test
  void futuresAndTheListenerRunOnTheListenerExecutorOnly() throws Exception {
    ExecutorService executor =
        Executors.newSingleThreadExecutor(runnable -> new Thread(runnable, "app-listener"));
    BlockingQueue<String> threads = new ArrayBlockingQueue<>(16);
    RicochetClient.Listener listener = new RicochetClient.Listener() {
      @Override
      public void onDisconnected(Disconnect disconnect) {
        threads.add("listener:" + Thread.currentThread().getName());
      }
    };
    try (RicochetClient client =
             pinned(server.get()).listenerExecutor(executor).listener(listener).build()) {
      CompletableFuture<Long> registered = client.register("threads", "password-threads");
      CompletableFuture<Void> seen =
          registered.thenAccept(id -> threads.add("future:" + Thread.currentThread().getName()));
      await(seen);
      RicochetException failed = failure(client.register("threads", "password-threads"));
      assertEquals(RicochetException.Kind.SERVER_ERROR, failed.kind());
      client.dropConnectionForTest();
      String first = threads.poll(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS);
      String second = threads.poll(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS);
      assertEquals("future:app-listener", first);
      assertEquals("listener:app-listener", second);
    } finally {
      executor.shutdown();
      assertTrue(executor.awaitTermination(10, TimeUnit.SECONDS));
    }
  }

  @Test
  void theDefaultListenerThreadIsNeitherTheCallersNorAnIoThread() throws Exception {
    try (RicochetClient client = pinned(server.get()).build()) {
      String thread = await(client.register("default_thread", "password-x")
                                .thenApply(id -> Thread.currentThread().getName()));
      assertEquals("ricochet-listener", thread);
      assertNotEquals(Thread.currentThread().getName(), thread);
    }
  }

  @Test
  void closeFromAListenerCallbackDoesNotWaitForItself() throws Exception {
    int before = ClientTesting.ricochetThreads();
    RicochetClient client = pinned(server.get()).build();
    CompletableFuture<Void> closedInside =
        client.register("self_closer", "password-self").thenAccept(id -> client.close());
    await(closedInside);
    long deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(10);
    while (ClientTesting.ricochetThreads() > before && System.nanoTime() < deadline) {
      Thread.sleep(10); // the listener thread ends once the callback returns
    }
    assertEquals(before, ClientTesting.ricochetThreads());
  }

  @Test
  void closeLeavesNoThreadBehindAndFailsWhatIsPending() throws Exception {
    int before = ClientTesting.ricochetThreads();
    RicochetClient client = signedIn(server.get(), "closer");
    await(client.listMatches());
    assertTrue(ClientTesting.ricochetThreads() >= before + 3, "read, write and listener threads");
    CompletableFuture<List<MatchInfo>> pending = client.listMatches();
    client.close();
    assertEquals(before, ClientTesting.ricochetThreads(), "every thread ended with close()");
    assertTrue(pending.isDone(), "a pending call is answered or failed by close()");
    RicochetException after = failure(client.listMatches());
    assertEquals(RicochetException.Kind.CLOSED, after.kind());
    client.close(); // twice is fine
  }
}
