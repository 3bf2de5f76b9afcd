package io.ricochet.client.core.control;

/** What {@link ControlSession#request} did: the request's id, or why it was refused locally. */
public final class RequestResult {
  private final long requestId;
  private final RequestRefusal refusal;

  RequestResult(long requestId, RequestRefusal refusal) {
    this.requestId = requestId;
    this.refusal = refusal;
  }

  /** True when the request was queued to be sent. */
  public boolean queued() {
    return refusal == null;
  }

  /** The request's id, 1 .. 2^32-1, when queued; 0 when refused. */
  public long requestId() {
    return requestId;
  }

  /** Why it was refused, or null when it was queued. */
  public RequestRefusal refusal() {
    return refusal;
  }

  @Override
  public String toString() {
    return queued() ? "request " + requestId : "refused: " + refusal.counterName();
  }
}
