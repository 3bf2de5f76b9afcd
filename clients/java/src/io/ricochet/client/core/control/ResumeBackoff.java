package io.ricochet.client.core.control;

import io.ricochet.wire.ControlProto.ErrorCode;
import java.util.function.DoubleSupplier;

/**
 * When to try again to resume a lost control connection with the session token, sans-IO: the
 * caller says what happened and when ({@code nowMs}, any monotonic milliseconds) and asks when the
 * next attempt is due. Attempt {@code n} (from 0) waits a delay drawn uniformly from {@code [0,
 * min(maxMs, baseMs * 2^n)]} after the loss or the failed attempt before it ("full jitter", so
 * phones that lost one cell tower do not come back in step); after {@code maxAttempts} failed
 * attempts, or one the server refused (the session is gone), it gives up. Which losses are worth
 * resuming and which refusals are worth retrying are {@link #worthResuming} and {@link
 * #worthRetrying}. States: {@link ResumeState}. Not thread-safe; no clock, no threads.
 */
public final class ResumeBackoff {
  /** The default first delay's bound (ms). */
  public static final long DEFAULT_BASE_MS = 500;
  /** The default bound on any delay (ms). */
  public static final long DEFAULT_MAX_MS = 30_000;
  /**
   * The default number of attempts before giving up: with the default bounds, at most 151.5 s of
   * waiting in all (500 ms doubling to 30 s), half that on average.
   */
  public static final int DEFAULT_MAX_ATTEMPTS = 10;

  private final long baseMs;
  private final long maxMs;
  private final int maxAttempts;
  private final DoubleSupplier jitter;
  private ResumeState state = ResumeState.IDLE;
  private int failedAttempts;
  private long nextAttemptAtMs;

  /**
   * A back-off drawing its delays with {@code jitter} (values in [0, 1]; {@code Math::random} in
   * the library, a fixed sequence in tests). {@code baseMs} ≥ 1, {@code maxMs} ≥ {@code baseMs},
   * {@code maxAttempts} ≥ 1; IllegalArgumentException otherwise.
   */
  public ResumeBackoff(long baseMs, long maxMs, int maxAttempts, DoubleSupplier jitter) {
    if (baseMs < 1 || maxMs < baseMs || maxAttempts < 1 || jitter == null) {
      throw new IllegalArgumentException("resume back-off needs 1 <= baseMs <= maxMs and"
          + " maxAttempts >= 1, got " + baseMs + ", " + maxMs + ", " + maxAttempts);
    }
    this.baseMs = baseMs;
    this.maxMs = maxMs;
    this.maxAttempts = maxAttempts;
    this.jitter = jitter;
  }

  /**
   * Whether a signed-in connection that closed for {@code reason} (with the server's closing
   * {@code serverError} for {@link ControlCloseReason#SERVER_ERROR}, else anything) should be
   * resumed: yes when the network or the server went away (lost, a request timed out, the server
   * stopping, a frame cut off mid-way); no when the client closed it, the server closed it as idle
   * (the client sends no keep-alives: it chose to be closed; the next call connects again), the
   * server banned the account or refused the client's bytes, or the client refused the server's
   * (retrying would repeat it).
   */
  public static boolean worthResuming(ControlCloseReason reason, ErrorCode serverError) {
    switch (reason) {
      case CONNECTION_LOST:
      case REQUEST_TIMEOUT:
        return true;
      case SERVER_ERROR:
        return serverError == ErrorCode.SHUTTING_DOWN || serverError == ErrorCode.FRAME_TIMEOUT;
      default:
        return false; // requested, or a protocol refusal either way
    }
  }

  /**
   * Whether a resume the server answered with {@code code} may succeed later: yes for a busy,
   * rate-limited, failing or stopping server; no for {@code UNKNOWN_SESSION} (revoked),
   * {@code EXPIRED_SESSION}, {@code ACCOUNT_BANNED} and anything else (the session is gone: sign
   * in again).
   */
  public static boolean worthRetrying(ErrorCode code) {
    return code == ErrorCode.SERVER_BUSY || code == ErrorCode.RATE_LIMITED
        || code == ErrorCode.INTERNAL || code == ErrorCode.SHUTTING_DOWN;
  }

  /** The state. */
  public ResumeState state() {
    return state;
  }

  /** When the next attempt is due (ms); meaningful in {@link ResumeState#WAITING}. */
  public long nextAttemptAtMs() {
    return nextAttemptAtMs;
  }

  /** Attempts failed since the loss (0 after {@link #resumed} or {@link #stop}). */
  public int failedAttempts() {
    return failedAttempts;
  }

  /**
   * The signed-in connection was lost at {@code nowMs} (for a reason {@link #worthResuming}):
   * waits for the first attempt. Ignored unless {@link ResumeState#IDLE}.
   */
  public void lost(long nowMs) {
    if (state != ResumeState.IDLE) return;
    failedAttempts = 0;
    waitFrom(nowMs);
  }

  /**
   * Whether an attempt starts now: true (and {@link ResumeState#ATTEMPTING}) when waiting and
   * {@code nowMs} has reached {@link #nextAttemptAtMs()}; false otherwise (a timer fired early).
   */
  public boolean startAttempt(long nowMs) {
    if (state != ResumeState.WAITING || nowMs < nextAttemptAtMs) return false;
    state = ResumeState.ATTEMPTING;
    return true;
  }

  /** The attempt signed in again: back to {@link ResumeState#IDLE}, the count cleared. */
  public void resumed() {
    state = ResumeState.IDLE;
    failedAttempts = 0;
  }

  /**
   * The attempt failed at {@code nowMs}; {@code retryable} is false when the server refused the
   * session ({@link #worthRetrying} false) or the certificate did not match the pin. True when
   * another attempt will be made ({@link ResumeState#WAITING}); false when it gave up ({@link
   * ResumeState#IDLE}: refused, or {@code maxAttempts} failed). Ignored (false) unless attempting.
   */
  public boolean attemptFailed(long nowMs, boolean retryable) {
    if (state != ResumeState.ATTEMPTING) return false;
    ++failedAttempts;
    if (!retryable || failedAttempts >= maxAttempts) {
      state = ResumeState.IDLE;
      return false;
    }
    waitFrom(nowMs);
    return true;
  }

  /**
   * Gives up whatever it was doing (the client closed, or signed out): {@link ResumeState#IDLE}.
   */
  public void stop() {
    state = ResumeState.IDLE;
    failedAttempts = 0;
  }

  /** The bound of attempt {@code attempt}'s delay: min(maxMs, baseMs * 2^attempt) (ms). */
  long delayBoundMs(int attempt) {
    if (attempt >= 62 || baseMs > (maxMs >> Math.min(attempt, 62))) return maxMs;
    return Math.min(maxMs, baseMs << attempt);
  }

  private void waitFrom(long nowMs) {
    double draw = jitter.getAsDouble();
    if (!(draw >= 0)) draw = 0; // NaN or negative: an injected source out of its range
    if (draw > 1) draw = 1;
    nextAttemptAtMs = nowMs + Math.round(draw * delayBoundMs(failedAttempts));
    state = ResumeState.WAITING;
  }
}
