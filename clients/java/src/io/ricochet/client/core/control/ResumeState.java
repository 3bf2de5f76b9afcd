package io.ricochet.client.core.control;

/**
 * Where a {@link ResumeBackoff} is between a lost control connection and its resumed successor.
 *
 * <pre>
 *   IDLE ──lost──▶ WAITING ──startAttempt at nextAttemptAtMs──▶ ATTEMPTING ──resumed──▶ IDLE
 *                     ▲                                            │
 *                     └──attemptFailed, retryable, attempts left───┤
 *   IDLE ◀──attemptFailed, refused or no attempts left─────────────┘   any state ──stop──▶ IDLE
 * </pre>
 */
public enum ResumeState {
  /** Nothing to resume: connected, never signed in, given up or stopped. */
  IDLE,
  /** Lost; the next attempt is due at {@link ResumeBackoff#nextAttemptAtMs()}. */
  WAITING,
  /** An attempt (connect, then resume with the session token) is under way. */
  ATTEMPTING
}
