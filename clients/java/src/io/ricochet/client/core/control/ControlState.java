package io.ricochet.client.core.control;

/**
 * The control connection's states as the client follows them from the server's replies
 * (PROTOCOL.md, Control channel, Connection states). {@link ControlSession} moves between them;
 * {@link #CLOSED} is final.
 *
 * <pre>
 *   UNAUTHENTICATED ──SessionReply──▶ AUTHENTICATED ──JoinMatchReply──▶ IN_MATCH
 *        ▲                              ▲ ◀──LeaveMatchReply / NOT_IN_MATCH / MatchResults──┘
 *        └────────── LogoutReply ◀──────┴────────────────────────────────────────────┘
 *   any state ──close, connection lost, the server's closing Error, a refused frame──▶ CLOSED
 * </pre>
 */
public enum ControlState {
  /** TLS is up; only register, login, resume and ping are allowed. */
  UNAUTHENTICATED("unauthenticated"),
  /** Signed in (login or resume), not seated in a match. */
  AUTHENTICATED("authenticated"),
  /** Seated in a match (join_match succeeded). */
  IN_MATCH("in_match"),
  /** The connection is over; nothing more is sent or received. */
  CLOSED("closed");

  private final String counterName;

  ControlState(String counterName) {
    this.counterName = counterName;
  }

  /** The state's name in logs, the same as the C++ end's ({@code control_states.h}). */
  public String counterName() {
    return counterName;
  }
}
