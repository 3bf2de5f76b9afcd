package io.ricochet.client.core.control;

import java.util.Locale;

/**
 * Where {@code find_match} sends a player (PROTOCOL.md, Placement; Open Match's name): the server
 * to connect to (its host, control and game ports, the SHA-256 of its certificate to pin), the
 * match there, and the one-time ticket to join with before {@link #expiresAtMs()}. Made from the
 * server's {@code FindMatchReply} by {@link #of}, which checks what a client needs to follow it.
 * Immutable; {@link #ticket()} is a copy. Time is the caller's monotonic milliseconds, as
 * everywhere in the core.
 */
public final class Assignment {
  /** Bytes of a ticket. */
  public static final int TICKET_BYTES = 32;

  /** What {@link #of} made of a wire Assignment: the assignment, or why it was refused. */
  public static final class Result {
    private final Assignment assignment;
    private final AssignmentRefusal refusal;
    private final String detail;

    private Result(Assignment assignment, AssignmentRefusal refusal, String detail) {
      this.assignment = assignment;
      this.refusal = refusal;
      this.detail = detail;
    }

    /** The assignment; null when refused. */
    public Assignment assignment() {
      return assignment;
    }

    /** Why it was refused; null when it was not. */
    public AssignmentRefusal refusal() {
      return refusal;
    }

    /** For people: what was expected and what came; null when it was not refused. */
    public String detail() {
      return detail;
    }
  }

  private final String host;
  private final int controlPort;
  private final int gamePort;
  private final String certificateSha256;
  private final long matchId;
  private final String mode;
  private final String map;
  private final byte[] ticket;
  private final long ticketExpiresInMs;
  private final long receivedAtMs;
  private final boolean onThisServer;

  private Assignment(String host, int controlPort, io.ricochet.wire.ControlProto.Assignment wire,
      long receivedAtMs) {
    this.host = host;
    this.controlPort = controlPort;
    this.gamePort = wire.getGamePort();
    this.certificateSha256 = wire.getCertificateSha256().toLowerCase(Locale.ROOT);
    this.matchId = wire.getMatchId() & 0xFFFFFFFFL;
    this.mode = wire.getMode();
    this.map = wire.getMap();
    this.ticket = wire.getTicket().toByteArray();
    this.ticketExpiresInMs = wire.getTicketExpiresInMs() & 0xFFFFFFFFL;
    this.receivedAtMs = receivedAtMs;
    this.onThisServer = wire.getOnThisServer();
  }

  /**
   * The assignment of {@code wire}, received at {@code receivedAtMs}, or why it cannot be followed
   * (the server's bytes are untrusted: a refusal, never an exception).
   */
  public static Result of(io.ricochet.wire.ControlProto.Assignment wire, long receivedAtMs) {
    String connection = wire.getConnection();
    int colon = connection.lastIndexOf(':');
    String host = colon > 0 ? connection.substring(0, colon) : "";
    if (host.startsWith("[") && host.endsWith("]")) {
      host = host.substring(1, host.length() - 1); // IPv6
      if (host.indexOf(':') < 0) host = "";
    } else if (host.indexOf(':') >= 0 || host.indexOf('[') >= 0 || host.indexOf(']') >= 0) {
      host = ""; // IPv6 must come in brackets
    }
    int controlPort = colon > 0 ? port(connection.substring(colon + 1)) : 0;
    if (host.isEmpty() || controlPort == 0) {
      return refused(AssignmentRefusal.CONNECTION,
          "connection must be host:port (IPv6 in brackets, port 1..65535), got '" + connection
              + "'");
    }
    if (wire.getGamePort() < 1 || wire.getGamePort() > 65535) {
      return refused(AssignmentRefusal.GAME_PORT,
          "game_port must be 1..65535, got " + (wire.getGamePort() & 0xFFFFFFFFL));
    }
    if (!wire.getCertificateSha256().matches("[0-9A-Fa-f]{64}")) {
      return refused(AssignmentRefusal.CERTIFICATE,
          "certificate_sha256 must be 64 hex digits, got '" + wire.getCertificateSha256() + "'");
    }
    if (wire.getTicket().size() != TICKET_BYTES) {
      return refused(AssignmentRefusal.TICKET,
          "ticket must be " + TICKET_BYTES + " bytes, got " + wire.getTicket().size());
    }
    if (wire.getMode().isEmpty()) return refused(AssignmentRefusal.MODE, "mode is empty");
    return new Result(new Assignment(host, controlPort, wire, receivedAtMs), null, null);
  }

  private static Result refused(AssignmentRefusal refusal, String detail) {
    return new Result(null, refusal, detail);
  }

  /** 1..65535 from decimal digits only; 0 for anything else. */
  private static int port(String digits) {
    if (digits.isEmpty() || digits.length() > 5) return 0;
    int value = 0;
    for (int i = 0; i < digits.length(); ++i) {
      char c = digits.charAt(i);
      if (c < '0' || c > '9') return 0;
      value = value * 10 + (c - '0');
    }
    return value <= 65535 ? value : 0;
  }

  /** The server's host name or address (an IPv6 address without its brackets). */
  public String host() {
    return host;
  }

  /** Its control channel's TCP port (TLS), 1..65535. */
  public int controlPort() {
    return controlPort;
  }

  /** Its game channel's UDP port on the same host, 1..65535. */
  public int gamePort() {
    return gamePort;
  }

  /**
   * The SHA-256 of the server's certificate, 64 lowercase hex digits: pin it when connecting there
   * (it came over the pinned control channel of the server that answered).
   */
  public String certificateSha256() {
    return certificateSha256;
  }

  /**
   * That server's match; 0: a new match of {@link #mode()} is made there when the ticket is used.
   */
  public long matchId() {
    return matchId;
  }

  /** The match's mode ("ffa", "tdm"). */
  public String mode() {
    return mode;
  }

  /** The match's map; empty: that server chooses. */
  public String map() {
    return map;
  }

  /** The 32-byte ticket to present in {@code join_match} there, once (a copy; a secret). */
  public byte[] ticket() {
    return ticket.clone();
  }

  /** How long after {@link #receivedAtMs()} the ticket holds the seat (ms). */
  public long ticketExpiresInMs() {
    return ticketExpiresInMs;
  }

  /** When the reply arrived (ms, the caller's monotonic clock). */
  public long receivedAtMs() {
    return receivedAtMs;
  }

  /** When the ticket stops holding the seat (ms, the clock of {@link #receivedAtMs()}). */
  public long expiresAtMs() {
    return receivedAtMs + ticketExpiresInMs;
  }

  /** Whether the ticket has expired at {@code nowMs}: joining with it would be refused. */
  public boolean expiredAt(long nowMs) {
    return nowMs >= expiresAtMs();
  }

  /** The server that answered is this one: join on the same connection. */
  public boolean onThisServer() {
    return onThisServer;
  }

  /** {@code host:port} as the server wrote it (IPv6 in brackets). */
  public String connection() {
    return (host.indexOf(':') >= 0 ? "[" + host + "]" : host) + ":" + controlPort;
  }

  @Override
  public String toString() {
    return "Assignment{" + mode + (map.isEmpty() ? "" : " " + map) + " match " + matchId + " on "
        + (onThisServer ? "this server" : connection()) + "}";
  }
}
