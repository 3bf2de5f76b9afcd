package io.ricochet.client.core.transport;

import java.util.Arrays;
import org.bouncycastle.crypto.macs.Poly1305;
import org.bouncycastle.crypto.params.KeyParameter;

/**
 * ChaCha20-Poly1305 IETF (RFC 8439, libsodium's {@code crypto_aead_chacha20poly1305_ietf}) for the
 * game packets of one key (PROTOCOL.md Game channel transport §5.2): nonce = 4 zero bytes || u64
 * sequence, additional data = version || u64 protocol_id || u8 type. Built from Bouncy Castle's
 * lightweight ChaCha7539Engine ({@link PacketChaCha}) and Poly1305 rather than its ChaCha20Poly1305
 * mode, which allocates a key block and parameters per message: this one reuses its buffers, so
 * sealing and opening allocate nothing once warm (PacketAeadTest checks both the bytes, against
 * that mode, and the allocation). One per key and direction; not thread-safe.
 */
final class PacketAead {
  private static final int AD_BYTES = 16 + 8 + 1;
  private static final byte[] ZERO_PAD = new byte[16];

  private final PacketChaCha chacha;
  private final Poly1305 poly = new Poly1305();
  private final KeyParameter macKey = new KeyParameter(new byte[32]);
  private final byte[] ad = new byte[AD_BYTES];
  private final byte[] keyBlock = new byte[64];
  private final byte[] lengths = new byte[16];
  private final byte[] tag = new byte[Packets.MAC_BYTES];

  /** {@code key}: 32 bytes, copied. */
  PacketAead(byte[] key, long protocolId) {
    if (key.length != Packets.KEY_BYTES) {
      throw new IllegalArgumentException("a key is 32 bytes, got " + key.length);
    }
    chacha = new PacketChaCha(key);
    System.arraycopy(Packets.VERSION, 0, ad, 0, 16);
    Packets.putU64(ad, 16, protocolId);
  }

  /**
   * Encrypts {@code packet[HEADER_BYTES, length)} in place under the type and sequence of its
   * header and writes the tag after it; returns the sealed length ({@code length + MAC_BYTES}).
   */
  int seal(byte[] packet, int length) {
    int bodyBytes = length - Packets.HEADER_BYTES;
    start(packet[0], Packets.getU64(packet, 1));
    chacha.processBytes(packet, Packets.HEADER_BYTES, bodyBytes, packet, Packets.HEADER_BYTES);
    mac(packet, Packets.HEADER_BYTES, bodyBytes);
    poly.doFinal(packet, length);
    return length + Packets.MAC_BYTES;
  }

  /**
   * Authenticates {@code datagram[0, length)} (header, ciphertext, tag) and decrypts its body into
   * {@code body} (at least {@code length} bytes); returns the body's length, or -1 when the tag
   * does not verify (then {@code body} is untouched).
   */
  int open(byte[] datagram, int length, byte[] body) {
    int bodyBytes = length - Packets.HEADER_BYTES - Packets.MAC_BYTES;
    if (bodyBytes < 0) return -1;
    start(datagram[0], Packets.getU64(datagram, 1));
    mac(datagram, Packets.HEADER_BYTES, bodyBytes);
    poly.doFinal(tag, 0);
    int difference = 0;
    for (int i = 0; i < Packets.MAC_BYTES; ++i) {
      difference |= tag[i] ^ datagram[Packets.HEADER_BYTES + bodyBytes + i];
    }
    if (difference != 0) return -1;
    chacha.processBytes(datagram, Packets.HEADER_BYTES, bodyBytes, body, 0);
    return bodyBytes;
  }

  /** Keys ChaCha20 with the packet's nonce, takes the Poly1305 key from block 0 (RFC 8439). */
  private void start(byte type, long sequence) {
    ad[AD_BYTES - 1] = type;
    chacha.start(sequence);
    Arrays.fill(keyBlock, (byte) 0);
    chacha.processBytes(keyBlock, 0, 64, keyBlock, 0); // the counter is at block 1 after this
    // KeyParameter hands out its own array: the block's first 32 bytes become the Poly1305 key
    // without a new parameters object per packet.
    System.arraycopy(keyBlock, 0, macKey.getKey(), 0, 32);
    poly.init(macKey);
  }

  /** Poly1305 over ad || pad || ciphertext || pad || u64 ad length || u64 ciphertext length. */
  private void mac(byte[] ciphertext, int offset, int length) {
    poly.update(ad, 0, AD_BYTES);
    poly.update(ZERO_PAD, 0, (16 - AD_BYTES % 16) % 16);
    poly.update(ciphertext, offset, length);
    poly.update(ZERO_PAD, 0, (16 - length % 16) % 16);
    Packets.putU64(lengths, 0, AD_BYTES);
    Packets.putU64(lengths, 8, length);
    poly.update(lengths, 0, 16);
  }
}
