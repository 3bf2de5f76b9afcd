package io.ricochet.client.testing;

/** Lowercase hex, as the vector files write bytes. */
public final class Hex {
  private Hex() {}

  public static byte[] decode(String hex) {
    if (hex.length() % 2 != 0) throw new IllegalArgumentException("odd hex length");
    byte[] out = new byte[hex.length() / 2];
    for (int i = 0; i < out.length; ++i) {
      out[i] = (byte) Integer.parseInt(hex.substring(2 * i, 2 * i + 2), 16);
    }
    return out;
  }

  public static String encode(byte[] bytes) {
    StringBuilder out = new StringBuilder(bytes.length * 2);
    for (byte b : bytes) out.append(String.format("%02x", b & 0xFF));
    return out.toString();
  }
}
