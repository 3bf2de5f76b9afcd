package io.ricochet.client.core.transport;

/**
 * What a {@link GameClient} reports, called synchronously from inside {@link GameClient#receive},
 * {@link GameClient#update}, {@link GameClient#sendReliable} and {@link GameClient#disconnect} on
 * the thread that called them (the I/O layer's). Every method has a no-op default. A method must
 * not call back into the client.
 */
public interface GameClientListener {
  /** The handshake completed: the server's first keep-alive or payload arrived. Once. */
  default void onConnected() {}

  /**
   * The unreliable bytes of a payload packet (a {@code ServerPayload}), in {@code bytes[offset,
   * offset + length)}; valid only during the call (the buffer is reused). Never empty.
   */
  default void onUnreliable(byte[] bytes, int offset, int length) {}

  /** The next reliable message in order (a {@code GameEvent}), once each; the listener owns it. */
  default void onReliable(byte[] message) {}

  /** The connection ended, once; the client does nothing more. */
  default void onDisconnected(DisconnectReason reason) {}

  /** A datagram was dropped (already counted in {@link TransportCounters}); for logs. */
  default void onDrop(DropReason reason) {}

  /** The client moved from {@code from} to {@code to}; {@code why} is a short text for logs. */
  default void onTransition(ConnectionState from, ConnectionState to, String why) {}
}
