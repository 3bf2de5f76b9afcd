package io.ricochet.client.core.control;

/**
 * Why a {@link ControlSession} closed. From {@link #FRAME_OVERSIZE} on, the server sent something
 * the protocol does not allow and the client refused it ({@link #refusesServer()}).
 */
public enum ControlCloseReason {
  /** {@link ControlSession#close()} by the caller. */
  REQUESTED("requested"),
  /** The caller saw the stream end or fail ({@link ControlSession#connectionLost}). */
  CONNECTION_LOST("connection_lost"),
  /** The server's Error with request_id 0, its last word before it closes. */
  SERVER_ERROR("server_error"),
  /** A request had no reply within the request timeout. */
  REQUEST_TIMEOUT("request_timeout"),
  /** A frame header declared over 65536 bytes. */
  FRAME_OVERSIZE("frame_oversize"),
  /** A frame header declared 0 bytes. */
  FRAME_EMPTY("frame_empty"),
  /** A payload that is not a ServerMessage. */
  MALFORMED("malformed"),
  /** A ServerMessage with no body (or only an unknown one). */
  MISSING_BODY("missing_body"),
  /** A reply to a request id that is not pending. */
  UNKNOWN_REQUEST("unknown_request"),
  /** A reply whose body does not answer its request's kind. */
  WRONG_REPLY("wrong_reply"),
  /** request_id 0 with a body other than MatchResults or Error. */
  UNEXPECTED_MESSAGE("unexpected_message");

  private final String counterName;

  ControlCloseReason(String counterName) {
    this.counterName = counterName;
  }

  /** The reason's name in counters and logs, the same as the C++ end's. */
  public String counterName() {
    return counterName;
  }

  /** True for the reasons that refuse the server's input. */
  public boolean refusesServer() {
    return ordinal() >= FRAME_OVERSIZE.ordinal();
  }
}
