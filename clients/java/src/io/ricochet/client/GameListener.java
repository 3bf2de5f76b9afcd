package io.ricochet.client;

import io.ricochet.client.core.transport.DisconnectReason;
import io.ricochet.wire.GameProto.GameEvent;

/**
 * What a {@link GameConnection} reports. Every method is called on the client's listener executor
 * (never the I/O thread, never the caller's), in order, and has a no-op default.
 */
public interface GameListener {
  /** The game channel's handshake completed; inputs go out from now on. Once. */
  default void onConnected() {}

  /**
   * A snapshot was decoded. {@code snapshot} is valid only during this call (it is pooled and
   * refilled later): copy what you keep. While every pooled snapshot is still being handed over
   * (the callbacks fall behind the snapshot rate), a newer one is not delivered ({@link
   * GameStats#snapshotsSkipped} counts them) rather than queued without bound.
   */
  default void onSnapshot(GameSnapshot snapshot) {}

  /** A reliable game event (joins, leaves, chat, kills, hits, the match's state), in order. */
  default void onEvent(GameEvent event) {}

  /** About once a second: round trip, snapshot rate and loss, bandwidth. */
  default void onStats(GameStats stats) {}

  /**
   * The game connection ended, once, with the transport's reason ({@link
   * DisconnectReason#REQUESTED} after {@link GameConnection#close}); its thread has ended or is
   * ending.
   */
  default void onDisconnected(DisconnectReason reason) {}
}
