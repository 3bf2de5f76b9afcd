package io.ricochet.client.core.transport;

/**
 * Why the game client dropped a datagram (PROTOCOL.md Game channel transport, §12 and §13). The
 * names are the C++ end's ({@code proto::DropReason}); the client meets only the first ones and
 * {@link #RELIABLE_OUT_OF_WINDOW}. {@link GameClient} counts every drop by reason in {@link
 * TransportCounters}; a dropped datagram gets no reply.
 */
public enum DropReason {
  /** Zero bytes. */
  EMPTY("empty"),
  /** More than {@link Packets#MAX_DATAGRAM_BYTES}. */
  OVERSIZED("oversized"),
  /** Shorter than its packet type needs, or a length field that runs past the body. */
  TRUNCATED("truncated"),
  /** Unknown type, a body of the wrong length, a bad field, a handshake sequence without bit 63. */
  MALFORMED("malformed"),
  /** Connection request with another version string (server only). */
  WRONG_VERSION("wrong_version"),
  /** Connection request with another protocol id (server only). */
  WRONG_PROTOCOL("wrong_protocol"),
  /** A packet type the client's state does not accept (§11). */
  WRONG_STATE("wrong_state"),
  /** From another address than the server's (checked by the I/O layer's connected socket). */
  UNKNOWN_ADDRESS("unknown_address"),
  /** The authentication tag does not verify: wrong key, tampered or forged. */
  FORGED_MAC("forged_mac"),
  /** A sequence already accepted, or 256 or more below the newest accepted one. */
  REPLAYED("replayed"),
  /** Server only. */
  TOKEN_INVALID("token_invalid"),
  /** Server only. */
  TOKEN_EXPIRED("token_expired"),
  /** Server only. */
  TOKEN_REUSED("token_reused"),
  /** Server only. */
  CHALLENGE_INVALID("challenge_invalid"),
  /** Server only. */
  ADDRESS_RATE_LIMITED("address_rate_limited"),
  /** Server only. */
  CLIENT_RATE_LIMITED("client_rate_limited"),
  /** Server only. */
  ADDRESS_TABLE_FULL("address_table_full"),
  /** Server only. */
  HALF_OPEN_CAP("half_open_cap"),
  /** Server only. */
  SERVER_FULL("server_full"),
  /**
   * A reliable message 256 or more ids ahead of the next expected one; the rest of its packet is
   * still used (§8).
   */
  RELIABLE_OUT_OF_WINDOW("reliable_out_of_window"),
  /** Server only. */
  HANDSHAKE_IN_PROGRESS("handshake_in_progress"),
  /** Server only. */
  HOST_HALF_OPEN_CAP("host_half_open_cap"),
  /** Server only. */
  HOST_FULL("host_full"),
  /** Server only. */
  USED_TOKEN_TABLE_FULL("used_token_table_full");

  private final String counterName;

  DropReason(String counterName) {
    this.counterName = counterName;
  }

  /** The reason's name in counters and logs, the same as the C++ end's. */
  public String counterName() {
    return counterName;
  }
}
