package io.ricochet.client.core.control;

/**
 * Why {@link ControlSession#request} refused a request locally; a refused request is never sent.
 */
public enum RequestRefusal {
  /** The state table ({@link RequestKind#allowedIn}) does not allow its kind in this state. */
  WRONG_STATE("wrong_state"),
  /** The session is closed. */
  CLOSED("closed"),
  /** The message has no body set. */
  NO_BODY("no_body"),
  /** It serialises to more than 65536 bytes. */
  TOO_LARGE("too_large");

  private final String counterName;

  RequestRefusal(String counterName) {
    this.counterName = counterName;
  }

  /** The reason's name in counters and logs, the same as the C++ end's. */
  public String counterName() {
    return counterName;
  }
}
