package io.ricochet.client;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.security.NoSuchAlgorithmException;
import java.security.Security;
import javax.crypto.Cipher;
import javax.net.ssl.SSLContext;
import org.junit.jupiter.api.Test;

/**
 * Which JVM the suite runs in. ctest runs every class twice: alone in a plain JDK, and all in one
 * JVM whose security providers leave out the JDK's TLS and ciphers ({@code no-jdk-crypto.security},
 * system property {@code ricochet.jdk_crypto=removed}), so that everything that connects there
 * went through the Bouncy Castle the client picked by itself. This proves the second JVM really
 * lacks them, and the first really has them (else the two runs would test the same thing).
 */
class JdkCryptoProvidersTest {
  private static boolean removed() {
    return "removed".equals(System.getProperty("ricochet.jdk_crypto"));
  }

  @Test
  void theJdksChaCha20Poly1305IsThereOnlyWhenNotRemoved() throws Exception {
    if (removed()) {
      assertNull(Security.getProvider("SunJCE"));
      assertThrows(NoSuchAlgorithmException.class, () -> Cipher.getInstance("ChaCha20-Poly1305"));
    } else {
      assertEquals("SunJCE", Cipher.getInstance("ChaCha20-Poly1305").getProvider().getName());
    }
  }

  @Test
  void theJdksTls13IsThereOnlyWhenNotRemoved() throws Exception {
    if (removed()) {
      assertNull(Security.getProvider("SunJSSE"));
      assertThrows(NoSuchAlgorithmException.class, () -> SSLContext.getInstance("TLSv1.3"));
      assertThrows(NoSuchAlgorithmException.class, () -> SSLContext.getInstance("TLS"));
    } else {
      assertEquals("SunJSSE", SSLContext.getInstance("TLSv1.3").getProvider().getName());
    }
  }

  @Test
  void noBouncyCastleProviderIsRegisteredByName() {
    // The client passes Bouncy Castle as instances; a registered "BC" would hand the JDK's
    // lookups (Cipher.getInstance above) a cipher and hide a missing one.
    assertNull(Security.getProvider("BC"));
    assertNull(Security.getProvider("BCJSSE"));
    assertTrue(Security.getProviders().length > 0);
  }
}
