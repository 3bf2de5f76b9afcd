package io.ricochet.client.core.transport;

/**
 * The game client's connection states (PROTOCOL.md Game channel transport §11): {@link
 * #SENDING_REQUEST} → {@link #SENDING_RESPONSE} → {@link #CONNECTED} → {@link #DISCONNECTED}, the
 * last one with a {@link DisconnectReason}. Each state accepts only some packet types; any other is
 * dropped as {@link DropReason#WRONG_STATE}.
 */
public enum ConnectionState {
  /** Sending the connection request every 100 ms; accepts denied and challenge. */
  SENDING_REQUEST("sending_request"),
  /**
   * Sending the response every 100 ms; accepts denied, challenge (ignored), keep-alive, payload
   * and disconnect.
   */
  SENDING_RESPONSE("sending_response"),
  /** Accepts keep-alive, payload and disconnect. */
  CONNECTED("connected"),
  /** Accepts nothing; the connection ended with a reason. */
  DISCONNECTED("disconnected");

  private final String logName;

  ConnectionState(String logName) {
    this.logName = logName;
  }

  /** The state's name in logs, the same as the C++ end's. */
  public String logName() {
    return logName;
  }

  /** Whether a packet of {@code type} may arrive in this state (the client's table of §11). */
  boolean accepts(PacketType type) {
    switch (this) {
      case SENDING_REQUEST:
        return type == PacketType.CONNECTION_DENIED || type == PacketType.CHALLENGE;
      case SENDING_RESPONSE:
        return type != PacketType.CONNECTION_REQUEST && type != PacketType.RESPONSE;
      case CONNECTED:
        return type == PacketType.KEEP_ALIVE || type == PacketType.PAYLOAD
            || type == PacketType.DISCONNECT;
      default:
        return false;
    }
  }
}
