package io.ricochet.client.core.control;

import io.ricochet.wire.ControlProto.ClientMessage;
import io.ricochet.wire.ControlProto.ServerMessage;

/**
 * The client requests, in the order of {@code ClientMessage}'s oneof, with the one table of
 * which state allows which (PROTOCOL.md, Control channel, Connection states) and which reply body
 * answers each. {@link ControlSession} consults it before it sends anything.
 */
public enum RequestKind {
  /** {@code register_account}. */
  REGISTER("register", ServerMessage.BodyCase.REGISTER_ACCOUNT, true, false, false),
  /** {@code login}. */
  LOGIN("login", ServerMessage.BodyCase.SESSION, true, false, false),
  /** {@code resume}. */
  RESUME("resume", ServerMessage.BodyCase.SESSION, true, false, false),
  /** {@code list_matches}. */
  LIST_MATCHES("list_matches", ServerMessage.BodyCase.LIST_MATCHES, false, true, true),
  /** {@code create_match}. */
  CREATE_MATCH("create_match", ServerMessage.BodyCase.CREATE_MATCH, false, true, true),
  /** {@code join_match}; in a match, only the same match (a fresh token). */
  JOIN_MATCH("join_match", ServerMessage.BodyCase.JOIN_MATCH, false, true, true),
  /** {@code leave_match}. */
  LEAVE_MATCH("leave_match", ServerMessage.BodyCase.LEAVE_MATCH, false, false, true),
  /** {@code chat}. */
  CHAT("chat", ServerMessage.BodyCase.CHAT, false, false, true),
  /** {@code ping}: allowed in every open state. */
  PING("ping", ServerMessage.BodyCase.PONG, true, true, true),
  /** {@code logout}. */
  LOGOUT("logout", ServerMessage.BodyCase.LOGOUT, false, true, true),
  /** {@code find_match}: an Assignment, possibly on another server (PROTOCOL.md, Placement). */
  FIND_MATCH("find_match", ServerMessage.BodyCase.FIND_MATCH, false, true, true);

  private final String counterName;
  private final ServerMessage.BodyCase reply;
  private final boolean unauthenticated;
  private final boolean authenticated;
  private final boolean inMatch;

  RequestKind(String counterName, ServerMessage.BodyCase reply, boolean unauthenticated,
      boolean authenticated, boolean inMatch) {
    this.counterName = counterName;
    this.reply = reply;
    this.unauthenticated = unauthenticated;
    this.authenticated = authenticated;
    this.inMatch = inMatch;
  }

  /** The kind's name in logs, the same as the C++ end's ({@code control_states.h}). */
  public String counterName() {
    return counterName;
  }

  /** Whether a connection in {@code state} may send a request of this kind. */
  public boolean allowedIn(ControlState state) {
    switch (state) {
      case UNAUTHENTICATED:
        return unauthenticated;
      case AUTHENTICATED:
        return authenticated;
      case IN_MATCH:
        return inMatch;
      case CLOSED:
      default:
        return false;
    }
  }

  /** Whether a reply with {@code body} answers this kind of request (an Error answers any). */
  public boolean answeredBy(ServerMessage.BodyCase body) {
    return body == ServerMessage.BodyCase.ERROR || body == reply;
  }

  /** The kind of {@code message}'s body, or null when it has none. */
  public static RequestKind of(ClientMessage message) {
    switch (message.getBodyCase()) {
      case REGISTER_ACCOUNT:
        return REGISTER;
      case LOGIN:
        return LOGIN;
      case RESUME:
        return RESUME;
      case LIST_MATCHES:
        return LIST_MATCHES;
      case CREATE_MATCH:
        return CREATE_MATCH;
      case JOIN_MATCH:
        return JOIN_MATCH;
      case LEAVE_MATCH:
        return LEAVE_MATCH;
      case CHAT:
        return CHAT;
      case PING:
        return PING;
      case LOGOUT:
        return LOGOUT;
      case FIND_MATCH:
        return FIND_MATCH;
      case BODY_NOT_SET:
      default:
        return null;
    }
  }
}
