package io.ricochet.client;

import static io.ricochet.client.ClientTesting.await;
import static io.ricochet.client.ClientTesting.failure;
import static io.ricochet.client.ClientTesting.pinned;
import static io.ricochet.client.ClientTesting.signedIn;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.core.control.Assignment;
import io.ricochet.client.core.control.ControlCloseReason;
import io.ricochet.client.core.control.ControlState;
import io.ricochet.client.core.control.RequestRefusal;
import io.ricochet.client.testing.RealServer;
import io.ricochet.wire.ControlProto.ErrorCode;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.ArrayBlockingQueue;
import java.util.concurrent.BlockingQueue;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.ExecutionException;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.extension.RegisterExtension;

/**
 * Every error code one client can drive the real server.get() to over the control channel arrives
 * as a
 * {@link RicochetException} of kind SERVER_ERROR with that code (or, for the server.get()'s closing
 * Error, as the {@link Disconnect}'s code). The server.get()'s limits that need their own
 * configuration are in {@link ServerLimitsTest}.
 */
class ServerErrorsTest {
  @RegisterExtension static final RealServer server = RealServer.arena(ClientTesting.FAST_ACCOUNTS);

  private static void assertServerError(ErrorCode code, CompletableFuture<?> call)
      throws Exception {
    RicochetException failed = failure(call);
    assertEquals(RicochetException.Kind.SERVER_ERROR, failed.kind(), failed.getMessage());
    assertEquals(code, failed.errorCode(), failed.getMessage());
    assertTrue(failed.getMessage().startsWith(code.name()), failed.getMessage());
  }

  private static long arenaId(RicochetClient client) throws Exception {
    for (MatchInfo match : await(client.listMatches())) {
      if (match.players() < match.maxPlayers() && match.maxPlayers() == 16) return match.matchId();
    }
    throw new AssertionError("no arena match");
  }

  @Test
  void registrationErrors() throws Exception {
    try (RicochetClient client = pinned(server.get()).build()) {
      assertServerError(ErrorCode.INVALID_USERNAME, client.register("ab", "password-ab"));
      assertServerError(ErrorCode.INVALID_USERNAME, client.register("spaces here", "password-1"));
      assertServerError(ErrorCode.INVALID_PASSWORD, client.register("short_pw", "1234567"));
      await(client.register("Taken", "password-taken"));
      assertServerError(ErrorCode.DUPLICATE_USERNAME, client.register("tAKEN", "password-other"));
      assertEquals(ControlState.UNAUTHENTICATED, client.state(), "errors keep it open");
    }
  }

  @Test
  void wrongCredentialsThenTheLoginRateLimit() throws Exception {
    try (RicochetClient client = pinned(server.get()).build()) {
      await(client.register("guessed", "password-guessed"));
      assertServerError(ErrorCode.WRONG_CREDENTIALS, client.login("nobody_here", "password-1"));
      for (int i = 0; i < 5; ++i) {
        assertServerError(ErrorCode.WRONG_CREDENTIALS, client.login("guessed", "wrong-" + i));
      }
      // Five failures a minute for one account from one address: the sixth is not even tried.
      assertServerError(ErrorCode.LOGIN_RATE_LIMITED, client.login("guessed", "password-guessed"));
    }
  }

  @Test
  void unknownSessions() throws Exception {
    try (RicochetClient client = pinned(server.get()).build()) {
      StringBuilder never = new StringBuilder();
      for (int i = 0; i < 64; ++i) never.append('0');
      assertServerError(ErrorCode.UNKNOWN_SESSION, client.resume(never.toString()));
      assertServerError(ErrorCode.UNKNOWN_SESSION, client.resume("not hex"));
      await(client.register("leaver", "password-leaver"));
      Session session = await(client.login("leaver", "password-leaver"));
      await(client.logout());
      assertServerError(ErrorCode.UNKNOWN_SESSION, client.resume(session.sessionToken()));
    }
  }

  @Test
  void directoryErrors() throws Exception {
    try (RicochetClient first = signedIn(server.get(), "creator");
         RicochetClient second = signedIn(server.get(), "latecomer")) {
      assertServerError(ErrorCode.MATCH_NOT_FOUND, first.joinMatch(987_654));
      assertServerError(ErrorCode.INVALID_REQUEST, first.createMatch("too many", 65, ""));
      assertServerError(ErrorCode.INVALID_REQUEST, first.createMatch("", 2, ""));
      MatchInfo solo = await(first.createMatch("solo", 1, ""));
      // One created match open per account (the counts are checked before the rates).
      assertServerError(ErrorCode.TOO_MANY_MATCHES, first.createMatch("another", 2, ""));
      assertServerError(ErrorCode.INVALID_REQUEST, second.createMatch("no map", 2, "atlantis"));
      await(first.joinMatch(solo.matchId()));
      assertServerError(ErrorCode.MATCH_FULL, second.joinMatch(solo.matchId()));
      assertServerError(ErrorCode.ALREADY_IN_MATCH, first.joinMatch(arenaId(second)));
      assertEquals(ControlState.IN_MATCH, first.state());
    }
  }

  /**
   * Placement on a server outside a fleet (SQLite: placement off): find_match has nowhere to
   * place, a ticket is unknown there; follow refuses locally what cannot work, sending nothing.
   */
  @Test
  void placementErrorsOutsideAFleet() throws Exception {
    try (RicochetClient client = signedIn(server.get(), "placer");
         RicochetClient unsigned = pinned(server.get()).build()) {
      assertServerError(ErrorCode.NO_SERVER_AVAILABLE, client.findMatch("ffa", ""));
      io.ricochet.wire.ControlProto.Assignment.Builder wire =
          io.ricochet.wire.ControlProto.Assignment.newBuilder()
              .setConnection("127.0.0.1:" + server.get().controlPort())
              .setGamePort(1)
              .setCertificateSha256(server.get().fingerprint().replace(":", ""))
              .setMode("ffa")
              .setTicket(com.google.protobuf.ByteString.copyFrom(new byte[32]))
              .setTicketExpiresInMs(30_000)
              .setOnThisServer(true);
      long nowMs = System.nanoTime() / 1_000_000;
      Assignment here = Assignment.of(wire.build(), nowMs).assignment();
      assertServerError(ErrorCode.UNKNOWN_TICKET, client.joinMatch(here));
      assertEquals(ControlState.AUTHENTICATED, client.state(), "a ticket's error keeps it open");
      assertTrue(client == await(client.follow(here)), "on this server: the same client");

      RicochetException notSignedIn = failure(unsigned.follow(here));
      assertEquals(RicochetException.Kind.REFUSED_LOCALLY, notSignedIn.kind());
      assertEquals(RequestRefusal.WRONG_STATE, notSignedIn.refusal());
      Assignment expired =
          Assignment.of(wire.setOnThisServer(false).setTicketExpiresInMs(1).build(), nowMs - 5)
              .assignment();
      RicochetException late = failure(client.follow(expired));
      assertEquals(RicochetException.Kind.REFUSED_LOCALLY, late.kind(), late.getMessage());
      assertEquals(ErrorCode.EXPIRED_TICKET, late.errorCode());
    }
  }

  /**
   * follow of an assignment elsewhere (here: this same server, named as another) connects pinned to
   * the assignment's fingerprint, not this client's pin, and resumes this session's token there.
   */
  @Test
  void followPinsTheAssignmentsFingerprintAndResumesTheSessionThere() throws Exception {
    try (RicochetClient client = signedIn(server.get(), "follower")) {
      io.ricochet.wire.ControlProto.Assignment.Builder wire =
          io.ricochet.wire.ControlProto.Assignment.newBuilder()
              .setConnection("127.0.0.1:" + server.get().controlPort())
              .setGamePort(1)
              .setCertificateSha256(server.get().fingerprint().replace(":", "").toLowerCase())
              .setMode("ffa")
              .setTicket(com.google.protobuf.ByteString.copyFrom(new byte[32]))
              .setTicketExpiresInMs(30_000);
      long nowMs = System.nanoTime() / 1_000_000;
      StringBuilder wrongPin = new StringBuilder();
      for (int i = 0; i < 64; ++i) wrongPin.append('a');
      Assignment forged =
          Assignment.of(wire.clone().setCertificateSha256(wrongPin.toString()).build(), nowMs)
              .assignment();
      RicochetException pinned = failure(client.follow(forged));
      assertEquals(RicochetException.Kind.PIN_MISMATCH, pinned.kind(), pinned.getMessage());

      Assignment elsewhere = Assignment.of(wire.build(), nowMs).assignment();
      try (RicochetClient there = await(client.follow(elsewhere))) {
        assertTrue(there != client, "a client of the server the assignment names");
        assertEquals(ControlState.AUTHENTICATED, there.state(), "resumed there");
        assertServerError(ErrorCode.UNKNOWN_TICKET, there.joinMatch(elsewhere));
      }
      assertEquals(ControlState.AUTHENTICATED, client.state(), "this one stays signed in");
    }
  }

  @Test
  void chatWithoutAGameConnectionIsNotInMatch() throws Exception {
    try (RicochetClient client = signedIn(server.get(), "talker")) {
      await(client.joinMatch(arenaId(client)));
      assertServerError(ErrorCode.NOT_IN_MATCH, client.chat("hello"));
      assertServerError(ErrorCode.INVALID_REQUEST, client.chat("bell\u0007"));
      await(client.leave());
    }
  }

  @Test
  void aChatCrossingTheLeaveGetsWrongState() throws Exception {
    try (RicochetClient client = signedIn(server.get(), "racer")) {
      await(client.joinMatch(arenaId(client)));
      // Both are allowed locally (the state is InMatch until the leave's reply); the server.get()
      // handles them in order, so the chat finds the connection Authenticated.
      List<CompletableFuture<Void>> calls = new ArrayList<>();
      client.pipelineForTest(() -> {
        calls.add(client.leave());
        calls.add(client.chat("bye"));
      });
      CompletableFuture<Void> leave = calls.get(0);
      CompletableFuture<Void> chat = calls.get(1);
      await(leave);
      assertServerError(ErrorCode.WRONG_STATE, chat);
      assertEquals(ControlState.AUTHENTICATED, client.state());
    }
  }

  @Test
  void overTheRequestRateRequestsAreDropped() throws Exception {
    try (RicochetClient client = signedIn(server.get(), "flooder")) {
      List<CompletableFuture<List<MatchInfo>>> calls = new ArrayList<>();
      for (int i = 0; i < 80; ++i) calls.add(client.listMatches());
      int limited = 0;
      int answered = 0;
      for (CompletableFuture<List<MatchInfo>> call : calls) {
        try {
          call.get(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS);
          ++answered;
        } catch (ExecutionException e) {
          RicochetException failed = (RicochetException) e.getCause();
          assertEquals(ErrorCode.RATE_LIMITED, failed.errorCode(), failed.getMessage());
          ++limited;
        }
      }
      assertTrue(limited > 0, "bursts of 40: " + answered + " answered");
      assertTrue(answered >= 30, answered + " answered: a burst of 40, less the sign-in's");
      assertEquals(ControlState.AUTHENTICATED, client.state(), "RATE_LIMITED keeps it open");
    }
  }

  @Test
  void aBanClosesTheConnectionThenRefusesTheLogin() throws Exception {
    BlockingQueue<Disconnect> disconnects = new ArrayBlockingQueue<>(4);
    RicochetClient.Listener listener = new RicochetClient.Listener() {
      @Override
      public void onDisconnected(Disconnect disconnect) {
        disconnects.add(disconnect);
      }
    };
    try (RicochetClient client = pinned(server.get()).listener(listener).build()) {
      await(client.register("mallory", "password-mallory"));
      Session session = await(client.login("mallory", "password-mallory"));
      assertEquals(200, server.get().ban("mallory"));
      Disconnect disconnect = disconnects.poll(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS);
      assertNotNull(disconnect);
      assertEquals(ControlCloseReason.SERVER_ERROR, disconnect.reason());
      assertEquals(ErrorCode.ACCOUNT_BANNED, disconnect.errorCode());
      assertServerError(ErrorCode.ACCOUNT_BANNED, client.login("mallory", "password-mallory"));
      assertServerError(ErrorCode.UNKNOWN_SESSION, client.resume(session.sessionToken()));
      assertFalse(client.state() == ControlState.AUTHENTICATED);
    }
  }
}
