package io.ricochet.client.core.transport;

/**
 * Why a game connection ended (PROTOCOL.md Game channel transport §5.3): the byte carried in
 * disconnect and denied packets is the ordinal. Reported once by {@link
 * GameClientListener#onDisconnected}.
 */
public enum DisconnectReason {
  /** This end's application asked for it ({@link GameClient#disconnect}). */
  REQUESTED("requested"),
  /** The other end sent a disconnect packet (what the server records for a client's). */
  PEER_REQUESTED("peer_requested"),
  /** Nothing authenticated came from the server for the join reply's {@code timeout_s}. */
  TIMED_OUT("timed_out"),
  /** No challenge, or no keep-alive after the response, within {@code timeout_s}. */
  HANDSHAKE_TIMED_OUT("handshake_timed_out"),
  /** Denied: the server is full. */
  DENIED("denied"),
  /** The same account connected again (a new token, maybe from a new address). */
  REPLACED("replaced"),
  /** Must-arrive reliable messages passed their cap: the peer stopped acking. */
  RELIABLE_OVERFLOW("reliable_overflow"),
  /** The server is stopping. */
  SERVER_SHUTDOWN("server_shutdown"),
  /** The match is over, or the connection holds no seat. */
  KICKED("kicked"),
  /** Denied: too many clients from the client's host. */
  HOST_FULL("host_full"),
  /** The player left the match on the control channel. */
  LEFT("left"),
  /** An operator banned the account. */
  BANNED("banned");

  private static final DisconnectReason[] BY_WIRE = values();

  private final String counterName;

  DisconnectReason(String counterName) {
    this.counterName = counterName;
  }

  /** The reason's name in counters and logs, the same as the C++ end's. */
  public String counterName() {
    return counterName;
  }

  /** The byte that carries this reason in a packet. */
  public int wireValue() {
    return ordinal();
  }

  /** The reason a packet's byte (0..255) names, or null when it names none (malformed). */
  public static DisconnectReason fromWire(int value) {
    return value >= 0 && value < BY_WIRE.length ? BY_WIRE[value] : null;
  }
}
