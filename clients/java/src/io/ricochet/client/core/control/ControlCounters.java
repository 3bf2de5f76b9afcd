package io.ricochet.client.core.control;

/**
 * What a {@link ControlSession} counted: frames and bytes each way, its own keep-alive pings,
 * requests refused locally by {@link RequestRefusal} and closes by {@link ControlCloseReason} (at
 * most one). Read by the caller (logs, stats); the session updates it.
 */
public final class ControlCounters {
  long framesIn;
  long framesOut;
  long bytesIn;
  long bytesOut;
  long keepAlives;
  final long[] refusedRequests = new long[RequestRefusal.values().length];
  final long[] closes = new long[ControlCloseReason.values().length];

  ControlCounters() {}

  /** Whole frames received from the server. */
  public long framesIn() {
    return framesIn;
  }

  /** Frames queued to the server, keep-alive pings included. */
  public long framesOut() {
    return framesOut;
  }

  /** Bytes received from the server (TLS plaintext). */
  public long bytesIn() {
    return bytesIn;
  }

  /** Bytes queued to the server (TLS plaintext). */
  public long bytesOut() {
    return bytesOut;
  }

  /** Pings the session sent on its own to keep the connection open. */
  public long keepAlives() {
    return keepAlives;
  }

  /** Requests refused locally for {@code refusal}. */
  public long refusedRequests(RequestRefusal refusal) {
    return refusedRequests[refusal.ordinal()];
  }

  /** Closes for {@code reason}: 0 or 1. */
  public long closes(ControlCloseReason reason) {
    return closes[reason.ordinal()];
  }
}
