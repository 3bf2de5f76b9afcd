package io.ricochet.client;

import java.security.MessageDigest;
import java.security.NoSuchAlgorithmException;
import java.util.Locale;

/**
 * The pin of a server certificate (PROTOCOL.md, The server certificate and pinning): the SHA-256
 * of the leaf certificate's DER, written as 32 uppercase hex pairs separated by colons, as {@code
 * openssl x509 -noout -fingerprint -sha256} prints it. Used by the builder and the TLS connector.
 */
final class CertificatePin {
  private static final char[] HEX = "0123456789ABCDEF".toCharArray();

  private CertificatePin() {}

  /**
   * {@code pin} in the canonical form; it may come with or without colons, in either case. Throws
   * IllegalArgumentException when it is not 32 hex pairs.
   */
  static String normalize(String pin) {
    String bare = pin.replace(":", "").trim().toUpperCase(Locale.ROOT);
    if (bare.length() != 64) {
      throw new IllegalArgumentException(
          "a SHA-256 pin is 32 hex pairs (with or without colons), got " + pin.length()
          + " characters: " + pin);
    }
    StringBuilder out = new StringBuilder(95);
    for (int i = 0; i < 64; ++i) {
      char c = bare.charAt(i);
      if (Character.digit(c, 16) < 0) {
        throw new IllegalArgumentException("a SHA-256 pin is hex, got '" + c + "' in " + pin);
      }
      if (i > 0 && i % 2 == 0) out.append(':');
      out.append(c);
    }
    return out.toString();
  }

  /** The pin of a certificate whose DER encoding is {@code der}. */
  static String of(byte[] der) {
    byte[] digest;
    try {
      digest = MessageDigest.getInstance("SHA-256").digest(der);
    } catch (NoSuchAlgorithmException e) {
      throw new IllegalStateException("every Java platform has SHA-256", e);
    }
    StringBuilder out = new StringBuilder(95);
    for (int i = 0; i < digest.length; ++i) {
      if (i > 0) out.append(':');
      out.append(HEX[(digest[i] >> 4) & 0xF]).append(HEX[digest[i] & 0xF]);
    }
    return out.toString();
  }
}
