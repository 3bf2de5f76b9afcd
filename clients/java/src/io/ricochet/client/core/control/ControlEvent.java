package io.ricochet.client.core.control;

import io.ricochet.wire.ControlProto.MatchResults;
import io.ricochet.wire.ControlProto.ServerMessage;

/**
 * What {@link ControlSession#pollEvent()} yields: a {@link Reply} to a request, {@link
 * MatchResultsArrived} sent by the server unasked, or {@link Closed}, the last event.
 */
public abstract class ControlEvent {
  private ControlEvent() {}

  /**
   * The answer to a request: its reply body, or an Error (the request was not done; the
   * connection stays open unless a {@link Closed} follows).
   */
  public static final class Reply extends ControlEvent {
    private final long requestId;
    private final RequestKind kind;
    private final ServerMessage message;

    Reply(long requestId, RequestKind kind, ServerMessage message) {
      this.requestId = requestId;
      this.kind = kind;
      this.message = message;
    }

    /** The request's id, 1 .. 2^32-1. */
    public long requestId() {
      return requestId;
    }

    /** The request's kind. */
    public RequestKind kind() {
      return kind;
    }

    /** The server's message; its body answers {@link #kind()} or is an Error. */
    public ServerMessage message() {
      return message;
    }

    /** True when the server refused the request with an Error. */
    public boolean isError() {
      return message.getBodyCase() == ServerMessage.BodyCase.ERROR;
    }
  }

  /** A match this account played ended (request_id 0). */
  public static final class MatchResultsArrived extends ControlEvent {
    private final MatchResults results;

    MatchResultsArrived(MatchResults results) {
      this.results = results;
    }

    /** The match's results as the server sent them. */
    public MatchResults results() {
      return results;
    }
  }

  /** The session is closed; requests still pending get no reply. */
  public static final class Closed extends ControlEvent {
    private final ControlCloseReason reason;
    private final String detail;
    private final io.ricochet.wire.ControlProto.Error serverError;

    Closed(ControlCloseReason reason, String detail, io.ricochet.wire.ControlProto.Error error) {
      this.reason = reason;
      this.detail = detail;
      this.serverError = error;
    }

    /** Why it closed. */
    public ControlCloseReason reason() {
      return reason;
    }

    /** For people: what came and what was expected. */
    public String detail() {
      return detail;
    }

    /** {@link ControlCloseReason#SERVER_ERROR}: what the server said; null otherwise. */
    public io.ricochet.wire.ControlProto.Error serverError() {
      return serverError;
    }
  }
}
