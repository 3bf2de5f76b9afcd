package io.ricochet.client;

import io.ricochet.client.core.transport.DisconnectReason;
import io.ricochet.wire.GameProto.GameEvent;

/**
 * What a {@link GameConnection} reports. Every method is called on the client's listener executor
 * (never the I/O thread, never the caller's), in order, and has a no-op default.
 */
public interface GameListener {
  /** The game channel's handshake completed; inputs go out from now on. Again after a reconnect. */
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

  /**
   * The connection was lost ({@code why}: {@link DisconnectReason#TIMED_OUT} when the server went
   * silent) or the app asked for a reconnect ({@code why} null): it is connecting again from a new
   * socket with a fresh token; {@link #onConnected} follows when it is back, or {@link
   * #onDisconnected} when it gives up. Snapshots stop meanwhile.
   */
  default void onReconnecting(DisconnectReason why) {}

  /** About once a second: round trip, snapshot rate and loss, bandwidth. */
  default void onStats(GameStats stats) {}

  /**
   * The game connection ended, once, with the transport's reason ({@link
   * DisconnectReason#REQUESTED} after {@link GameConnection#close}); its thread has ended or is
   * ending.
   */
  default void onDisconnected(DisconnectReason reason) {}
}
