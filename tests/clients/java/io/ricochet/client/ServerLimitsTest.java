package io.ricochet.client;

import static io.ricochet.client.ClientTesting.await;
import static io.ricochet.client.ClientTesting.failure;
import static io.ricochet.client.ClientTesting.pinned;
import static io.ricochet.client.ClientTesting.signedIn;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.core.control.ControlCloseReason;
import io.ricochet.client.testing.ServerProcess;
import io.ricochet.wire.ControlProto.ErrorCode;
import java.util.List;
import java.util.concurrent.ArrayBlockingQueue;
import java.util.concurrent.BlockingQueue;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;

/**
 * The error codes that need a server configured for them (each test starts its own): the
 * registration and seat limits, the login and idle timeouts, the shutdown; and that the client's
 * keep-alive pings hold a connection the server would otherwise close as idle.
 */
class ServerLimitsTest {
  /** A listener that queues every disconnect. */
  private static final class Disconnects implements RicochetClient.Listener {
    final BlockingQueue<Disconnect> queue = new ArrayBlockingQueue<>(8);

    @Override
    public void onDisconnected(Disconnect disconnect) {
      queue.add(disconnect);
    }

    Disconnect next() throws InterruptedException {
      Disconnect disconnect = queue.poll(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS);
      assertNotNull(disconnect, "no disconnect within " + ClientTesting.WAIT_MS + " ms");
      return disconnect;
    }
  }

  private static void assertServerError(ErrorCode code, RicochetException failed) {
    assertEquals(RicochetException.Kind.SERVER_ERROR, failed.kind(), failed.getMessage());
    assertEquals(code, failed.errorCode(), failed.getMessage());
  }

  @Test
  void registrationsPerAddressAreLimited() throws Exception {
    try (ServerProcess server = ServerProcess.arena(
             "[db]\npassword_hashing = \"minimum\"\nregistrations_per_hour_per_address = 2\n");
         RicochetClient client = pinned(server).build()) {
      await(client.register("first", "password-first"));
      await(client.register("second", "password-second"));
      assertServerError(
          ErrorCode.REGISTRATION_RATE_LIMITED, failure(client.register("third", "password-3")));
    }
  }

  @Test
  void seatsPerAddressAreLimited() throws Exception {
    try (ServerProcess server =
             ServerProcess.arena("seats_per_address = 1\n", "", ClientTesting.FAST_ACCOUNTS);
         RicochetClient first = signedIn(server, "seat_one");
         RicochetClient second = signedIn(server, "seat_two")) {
      List<MatchInfo> matches = await(first.listMatches());
      await(first.joinMatch(matches.get(0).matchId()));
      assertServerError(
          ErrorCode.ADDRESS_SEAT_LIMIT, failure(second.joinMatch(matches.get(0).matchId())));
    }
  }

  @Test
  void creationsPerAccountAreRateLimited() throws Exception {
    try (ServerProcess server =
             ServerProcess.arena("max_created_per_account = 4\n", "", ClientTesting.FAST_ACCOUNTS);
         RicochetClient client = signedIn(server, "builder")) {
      await(client.createMatch("first", 2, ""));
      // Two a minute, one at a time: the second at once is refused.
      assertServerError(
          ErrorCode.CREATE_RATE_LIMITED, failure(client.createMatch("second", 2, "")));
    }
  }

  @Test
  void timeoutsKeepAlivesAndTheShutdown() throws Exception {
    try (ServerProcess server = ServerProcess.arena("",
             "login_timeout_ms = 3000\nidle_timeout_ms = 1500\n", ClientTesting.FAST_ACCOUNTS)) {
      Disconnects idleEvents = new Disconnects();
      Disconnects pingingEvents = new Disconnects();
      Disconnects anonymousEvents = new Disconnects();
      try (RicochetClient idle = pinned(server).keepAliveMs(0).listener(idleEvents).build();
           RicochetClient pinging = pinned(server).keepAliveMs(200).listener(pingingEvents).build();
           RicochetClient anonymous =
               pinned(server).keepAliveMs(200).listener(anonymousEvents).build()) {
        await(idle.register("idle", "password-idle"));
        await(idle.login("idle", "password-idle"));
        await(pinging.register("pinging", "password-pinging"));
        await(pinging.login("pinging", "password-pinging"));
        await(anonymous.register("anonymous", "password-anonymous")); // never signs in

        // Quiet for 1.5 s: the server closes it with its reason.
        Disconnect idleEnd = idleEvents.next();
        assertEquals(ControlCloseReason.SERVER_ERROR, idleEnd.reason());
        assertEquals(ErrorCode.IDLE_TIMEOUT, idleEnd.errorCode(), idleEnd.toString());
        // Pings do not extend the login deadline.
        Disconnect loginEnd = anonymousEvents.next();
        assertEquals(ErrorCode.LOGIN_TIMEOUT, loginEnd.errorCode(), loginEnd.toString());
        // The pinging client outlived both, on its first connection.
        assertNull(pingingEvents.queue.poll(), "keep-alive pings hold the connection");
        assertTrue(await(pinging.listMatches()).size() >= 1);
        assertNull(pingingEvents.queue.poll());

        server.terminate();
        Disconnect shutdown = pingingEvents.next();
        assertEquals(ControlCloseReason.SERVER_ERROR, shutdown.reason());
        assertEquals(ErrorCode.SHUTTING_DOWN, shutdown.errorCode(), shutdown.toString());
      }
    }
  }
}
