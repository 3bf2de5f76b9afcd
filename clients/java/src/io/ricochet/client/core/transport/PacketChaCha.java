package io.ricochet.client.core.transport;

import org.bouncycastle.crypto.engines.ChaCha7539Engine;
import org.bouncycastle.crypto.params.KeyParameter;
import org.bouncycastle.crypto.params.ParametersWithIV;

/**
 * Bouncy Castle's ChaCha20 (RFC 8439: 32-bit block counter, 96-bit nonce) keyed once, whose nonce
 * then moves to each packet's sequence without a new {@code init}: init builds parameter and
 * constraint objects every call, this writes the nonce words of the engine's state (protected, for
 * subclasses) and restarts at block 0. Used by {@link PacketAead} only.
 */
final class PacketChaCha extends ChaCha7539Engine {
  /** Keyed with {@code key} (32 bytes); the nonce is set per packet with {@link #start}. */
  PacketChaCha(byte[] key) {
    init(true, new ParametersWithIV(new KeyParameter(key), new byte[12]));
  }

  /** Nonce = 4 zero bytes || u64 sequence (little endian); the keystream restarts at block 0. */
  void start(long sequence) {
    engineState[13] = 0;
    engineState[14] = (int) sequence;
    engineState[15] = (int) (sequence >>> 32);
    reset();
  }
}
