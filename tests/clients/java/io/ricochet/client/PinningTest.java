package io.ricochet.client;

import static io.ricochet.client.ClientTesting.await;
import static io.ricochet.client.ClientTesting.failure;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.testing.RealServer;
import java.util.HashMap;
import java.util.Map;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.extension.RegisterExtension;

/** Certificate pinning and trust on first use against the real server.get()'s self-signed pair. */
class PinningTest {
  private static final String WRONG_PIN =
      "00:11:22:33:44:55:66:77:88:99:AA:BB:CC:DD:EE:FF:00:11:22:33:44:55:66:77:88:99:AA:BB:CC:DD:EE:FF";

  @RegisterExtension static final RealServer server = RealServer.arena(ClientTesting.FAST_ACCOUNTS);

  /** A store in memory that counts its calls. */
  private static final class MemoryPins implements PinStore {
    final Map<String, String> pins = new HashMap<>();
    int saves;

    @Override
    public synchronized String load(String hostPort) {
      return pins.get(hostPort);
    }

    @Override
    public synchronized void save(String hostPort, String pinSha256) {
      ++saves;
      pins.put(hostPort, pinSha256);
    }
  }

  private static RicochetClient.Builder client() {
    return RicochetClient.builder().host("127.0.0.1").controlPort(server.get().controlPort());
  }

  @Test
  void aWrongPinIsRefusedBeforeAnyCredentialIsSent() throws Exception {
    try (RicochetClient client = client().pinSha256(WRONG_PIN).build()) {
      RicochetException refused = failure(client.register("never_sent", "password-never"));
      assertEquals(RicochetException.Kind.PIN_MISMATCH, refused.kind());
      assertTrue(refused.getMessage().contains(server.get().fingerprint()), refused.getMessage());
      assertTrue(refused.getMessage().contains(WRONG_PIN), refused.getMessage());
      RicochetException login = failure(client.login("never_sent", "password-never"));
      assertEquals(RicochetException.Kind.PIN_MISMATCH, login.kind());
    }
    // The register never reached the server.get(): the name is still free.
    try (RicochetClient client = ClientTesting.pinned(server.get()).build()) {
      assertTrue(await(client.register("never_sent", "password-never")) > 0);
    }
  }

  @Test
  void withoutAPinTheSelfSignedChainIsRefused() throws Exception {
    try (RicochetClient client = client().build()) {
      RicochetException refused = failure(client.register("no_pin", "password-no-pin"));
      assertEquals(RicochetException.Kind.CONNECT_FAILED, refused.kind());
    }
  }

  @Test
  void trustOnFirstUseStoresThePinThenEnforcesIt() throws Exception {
    MemoryPins store = new MemoryPins();
    String hostPort = "127.0.0.1:" + server.get().controlPort();
    try (RicochetClient client = client().pinStore(store).build()) {
      assertTrue(await(client.register("tofu", "password-tofu")) > 0);
    }
    assertEquals(server.get().fingerprint(), store.pins.get(hostPort), "saved on first use");
    assertEquals(1, store.saves);
    try (RicochetClient client = client().pinStore(store).build()) {
      await(client.login("tofu", "password-tofu"));
    }
    assertEquals(1, store.saves, "a known server.get() is checked, not saved again");
    store.pins.put(
        hostPort, WRONG_PIN.replace(":", "")); // the server.get() "changed" its certificate
    try (RicochetClient client = client().pinStore(store).build()) {
      RicochetException refused = failure(client.login("tofu", "password-tofu"));
      assertEquals(RicochetException.Kind.PIN_MISMATCH, refused.kind());
    }
    assertEquals(1, store.saves);
  }

  @Test
  void aMalformedPinIsRefusedByTheBuilder() {
    assertThrows(IllegalArgumentException.class, () -> client().pinSha256("AB:CD").build());
    assertThrows(IllegalArgumentException.class,
        () -> client().pinSha256(WRONG_PIN.replace('0', 'G')).build());
  }
}
