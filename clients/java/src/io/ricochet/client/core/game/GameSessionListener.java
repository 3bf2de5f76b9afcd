package io.ricochet.client.core.game;

import io.ricochet.client.core.snapshot.SnapshotView;
import io.ricochet.client.core.transport.DisconnectReason;
import io.ricochet.wire.GameProto.GameEvent;

/**
 * What a {@link GameSession} reports, synchronously from inside its {@code receive}, {@code
 * update} and {@code disconnect} on the caller's thread (the I/O layer's). No-op defaults. A method
 * must not call back into the session.
 */
public interface GameSessionListener {
  /** The handshake completed; inputs start going out. Once. */
  default void onConnected() {}

  /**
   * A snapshot was accepted: {@code view} shows its entities, {@code payload} the rest of its
   * ServerPayload (own entity, last applied input, status). Both are valid only during the call.
   */
  default void onSnapshot(SnapshotView view, ServerPayloadReader payload) {}

  /** A reliable game event, in order; the listener owns it. */
  default void onEvent(GameEvent event) {}

  /** The connection ended, once. */
  default void onDisconnected(DisconnectReason reason) {}
}
