package io.ricochet.client.core.control;

/**
 * Why {@link Assignment#of} refused the server's {@code Assignment} (PROTOCOL.md, Placement): what
 * a client needs to follow it is missing or out of range.
 */
public enum AssignmentRefusal {
  /** {@code connection} is not {@code host:port} (IPv6 in brackets) with a port 1..65535. */
  CONNECTION("connection"),
  /** {@code game_port} is not 1..65535. */
  GAME_PORT("game_port"),
  /** {@code certificate_sha256} is not 64 hex digits. */
  CERTIFICATE("certificate"),
  /** {@code ticket} is not {@link Assignment#TICKET_BYTES} bytes. */
  TICKET("ticket"),
  /** {@code mode} is empty: the assignment says nothing of what will be played. */
  MODE("mode");

  private final String counterName;

  AssignmentRefusal(String counterName) {
    this.counterName = counterName;
  }

  /** The reason's name in logs. */
  public String counterName() {
    return counterName;
  }
}
