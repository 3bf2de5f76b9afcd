package io.ricochet.client;

import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.fail;

import io.ricochet.client.testing.ServerProcess;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.ExecutionException;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.TimeoutException;

/** What the RicochetClient tests share: clients of a test server, bounded waits on futures. */
final class ClientTesting {
  /** Every wait on the server is bounded by this (a loaded machine hashes slowly). */
  static final long WAIT_MS = 30_000;

  /** The main server's extra tables: cheap password hashes and room for many accounts. */
  static final String FAST_ACCOUNTS =
      "[db]\npassword_hashing = \"minimum\"\nregistrations_per_hour_per_address = 1000\n";

  private ClientTesting() {}

  /** A client of {@code server}, pinned to its certificate. */
  static RicochetClient.Builder pinned(ServerProcess server) {
    return RicochetClient.builder()
        .host("127.0.0.1")
        .controlPort(server.controlPort())
        .pinSha256(server.fingerprint());
  }

  /** The future's value, waiting at most {@link #WAIT_MS}. */
  static <T> T await(CompletableFuture<T> future) throws Exception {
    try {
      return future.get(WAIT_MS, TimeUnit.MILLISECONDS);
    } catch (ExecutionException e) {
      throw new AssertionError("the call failed: " + e.getCause(), e.getCause());
    }
  }

  /** How the future failed; fails the test when it succeeded or took over {@link #WAIT_MS}. */
  static RicochetException failure(CompletableFuture<?> future) throws Exception {
    try {
      Object value = future.get(WAIT_MS, TimeUnit.MILLISECONDS);
      fail("expected a failure, got " + value);
      return null;
    } catch (ExecutionException e) {
      assertInstanceOf(RicochetException.class, e.getCause());
      return (RicochetException) e.getCause();
    } catch (TimeoutException e) {
      throw new AssertionError("no answer within " + WAIT_MS + " ms", e);
    }
  }

  /** A new account signed in on a new client; the client is the caller's to close. */
  static RicochetClient signedIn(ServerProcess server, String username) throws Exception {
    RicochetClient client = pinned(server).build();
    await(client.register(username, "password-" + username));
    await(client.login(username, "password-" + username));
    return client;
  }

  /** Live threads whose name starts with "ricochet-". */
  static int ricochetThreads() {
    int count = 0;
    for (Thread thread : Thread.getAllStackTraces().keySet()) {
      if (thread.isAlive() && thread.getName().startsWith("ricochet-")) ++count;
    }
    return count;
  }
}
