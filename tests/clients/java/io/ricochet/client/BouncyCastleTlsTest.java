package io.ricochet.client;

import static io.ricochet.client.ClientTesting.await;
import static io.ricochet.client.ClientTesting.failure;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.core.control.ControlState;
import io.ricochet.client.testing.RealServer;
import java.security.NoSuchAlgorithmException;
import java.security.Provider;
import java.security.Security;
import javax.net.ssl.SSLContext;
import org.bouncycastle.jce.provider.BouncyCastleProvider;
import org.bouncycastle.jsse.provider.BouncyCastleJsseProvider;
import org.junit.jupiter.api.AfterAll;
import org.junit.jupiter.api.BeforeAll;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.extension.RegisterExtension;

/**
 * The client on a platform without TLS 1.3 of its own (Android before 10): the JDK's JSSE
 * provider is removed from this JVM (each test class runs in a JVM of its own), so Bouncy Castle's
 * JSSE carries the whole connection: passed to the builder as an instance, or picked by the client
 * itself when none is passed.
 */
class BouncyCastleTlsTest {
  @RegisterExtension static final RealServer server = RealServer.arena(ClientTesting.FAST_ACCOUNTS);

  private static Provider removed;
  private static int removedAt;

  /**
   * Bouncy Castle's JSSE over Bouncy Castle's JCA, as instances: it needs nothing of the JDK's, so
   * it carries the connection in the suite's JVM without the JDK's ciphers too.
   */
  private static Provider bouncyCastle() {
    return new BouncyCastleJsseProvider(new BouncyCastleProvider());
  }

  @BeforeAll
  static void removeTheJdkTls() throws Exception {
    Provider[] providers = Security.getProviders();
    for (int i = 0; i < providers.length; ++i) {
      if (providers[i].getName().equals("SunJSSE")) {
        removed = providers[i];
        removedAt = i + 1;
      }
    }
    Security.removeProvider("SunJSSE");
  }

  @AfterAll
  static void restoreTheJdkTls() {
    if (removed != null) Security.insertProviderAt(removed, removedAt);
  }

  @Test
  void thePlatformHasNoTlsLeft() {
    assertNull(Security.getProvider("SunJSSE"));
    assertThrows(NoSuchAlgorithmException.class, () -> SSLContext.getInstance("TLSv1.3"));
  }

  @Test
  void bouncyCastleCarriesTheConnectionWithThePin() throws Exception {
    try (RicochetClient client =
             ClientTesting.pinned(server.get()).tlsProvider(bouncyCastle()).build()) {
      long id = await(client.register("bouncy", "password-bouncy"));
      Session session = await(client.login("bouncy", "password-bouncy"));
      assertEquals(id, session.accountId());
      assertEquals(ControlState.AUTHENTICATED, client.state());
      assertTrue(await(client.listMatches()).size() >= 1);
      JoinTicket ticket = await(client.joinMatch(await(client.listMatches()).get(0).matchId()));
      assertEquals(32, ticket.clientToServerKey().length);
    }
  }

  @Test
  void bouncyCastleRefusesAWrongPin() throws Exception {
    String wrong = "00000000000000000000000000000000"
        + "00000000000000000000000000000000";
    try (RicochetClient client = RicochetClient.builder()
                                     .host("127.0.0.1")
                                     .controlPort(server.get().controlPort())
                                     .pinSha256(wrong)
                                     .tlsProvider(bouncyCastle())
                                     .build()) {
      RicochetException refused = failure(client.register("x_y_z", "pw-12345678"));
      assertEquals(RicochetException.Kind.PIN_MISMATCH, refused.kind(), refused.getMessage());
    }
  }

  @Test
  void withoutAProviderTheClientPicksBouncyCastleByItself() throws Exception {
    try (RicochetClient client = ClientTesting.pinned(server.get()).build()) {
      long id = await(client.register("no_tls", "password-no-tls"));
      assertEquals(id, await(client.login("no_tls", "password-no-tls")).accountId());
      assertEquals(ControlState.AUTHENTICATED, client.state());
    }
    assertNull(Security.getProvider("BCJSSE"), "the client registered a provider by name");
    assertNull(Security.getProvider("BC"), "the client registered a provider by name");
  }
}
