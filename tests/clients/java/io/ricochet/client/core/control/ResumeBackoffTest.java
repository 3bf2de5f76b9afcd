package io.ricochet.client.core.control;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.wire.ControlProto.ErrorCode;
import java.util.Random;
import java.util.function.DoubleSupplier;
import org.junit.jupiter.api.Test;

/** The resume back-off with fake time and injected jitter: schedule, bounds, giving up. */
class ResumeBackoffTest {
  private static DoubleSupplier always(double value) {
    return () -> value;
  }

  /** Fails attempt after attempt at the moment each is due; the delays between them. */
  private static long[] delaysUntilGivingUp(ResumeBackoff backoff, long lostAtMs) {
    long[] delays = new long[64];
    int count = 0;
    long now = lostAtMs;
    backoff.lost(now);
    while (backoff.state() == ResumeState.WAITING) {
      delays[count++] = backoff.nextAttemptAtMs() - now;
      now = backoff.nextAttemptAtMs();
      assertTrue(backoff.startAttempt(now));
      backoff.attemptFailed(now, true);
    }
    return java.util.Arrays.copyOf(delays, count);
  }

  @Test
  void theBoundDoublesFromTheBaseUpToTheMaximum() {
    ResumeBackoff backoff = new ResumeBackoff(500, 30_000, 10, always(1.0));
    long[] delays = delaysUntilGivingUp(backoff, 1_000);
    assertEquals(10, delays.length, "one wait before each of the 10 attempts");
    long[] expected = {500, 1000, 2000, 4000, 8000, 16000, 30000, 30000, 30000, 30000};
    assertEquals(java.util.Arrays.toString(expected), java.util.Arrays.toString(delays));
    assertEquals(ResumeState.IDLE, backoff.state(), "gave up after the last attempt");
    assertEquals(10, backoff.failedAttempts());
  }

  @Test
  void fullJitterScalesTheBoundByTheDraw() {
    double[] draws = {0.0, 0.5, 0.25, 0.999};
    int[] next = {0};
    ResumeBackoff backoff = new ResumeBackoff(1000, 60_000, 4, () -> draws[next[0]++]);
    long[] delays = delaysUntilGivingUp(backoff, 0);
    // Bounds 1000, 2000, 4000, 8000 ms.
    assertEquals("[0, 1000, 1000, 7992]", java.util.Arrays.toString(delays));
  }

  @Test
  void randomDelaysStayWithinTheirBoundsAndSpread() {
    Random random = new Random(7);
    long[] smallest = new long[6];
    long[] largest = new long[6];
    java.util.Arrays.fill(smallest, Long.MAX_VALUE);
    for (int run = 0; run < 2000; ++run) {
      ResumeBackoff backoff = new ResumeBackoff(100, 1000, 6, random::nextDouble);
      long[] delays = delaysUntilGivingUp(backoff, 5_000);
      for (int i = 0; i < delays.length; ++i) {
        long bound = Math.min(1000, 100L << i);
        assertTrue(delays[i] >= 0 && delays[i] <= bound, "attempt " + i + ": " + delays[i]);
        smallest[i] = Math.min(smallest[i], delays[i]);
        largest[i] = Math.max(largest[i], delays[i]);
      }
    }
    for (int i = 0; i < 6; ++i) {
      long bound = Math.min(1000, 100L << i);
      // Full jitter: the draws cover the whole range, not a band around the bound.
      assertTrue(smallest[i] <= bound / 20, "attempt " + i + " never short: " + smallest[i]);
      assertTrue(largest[i] >= bound - bound / 20, "attempt " + i + " never long: " + largest[i]);
    }
  }

  @Test
  void aDrawOutOfRangeIsClamped() {
    ResumeBackoff high = new ResumeBackoff(100, 1000, 3, always(7.0));
    high.lost(0);
    assertEquals(100, high.nextAttemptAtMs());
    ResumeBackoff nan = new ResumeBackoff(100, 1000, 3, always(Double.NaN));
    nan.lost(0);
    assertEquals(0, nan.nextAttemptAtMs());
  }

  @Test
  void noAttemptStartsBeforeItIsDue() {
    ResumeBackoff backoff = new ResumeBackoff(1000, 1000, 3, always(0.5));
    assertFalse(backoff.startAttempt(0), "nothing lost");
    backoff.lost(10_000);
    assertEquals(10_500, backoff.nextAttemptAtMs());
    assertFalse(backoff.startAttempt(10_499));
    assertEquals(ResumeState.WAITING, backoff.state());
    assertTrue(backoff.startAttempt(10_500));
    assertEquals(ResumeState.ATTEMPTING, backoff.state());
    assertFalse(backoff.startAttempt(10_500), "one attempt at a time");
  }

  @Test
  void aResumeClearsTheCountSoTheNextLossStartsFromTheBase() {
    ResumeBackoff backoff = new ResumeBackoff(100, 10_000, 5, always(1.0));
    backoff.lost(0);
    backoff.startAttempt(100);
    assertTrue(backoff.attemptFailed(100, true));
    assertEquals(300, backoff.nextAttemptAtMs(), "the second attempt's bound is 200 ms");
    backoff.startAttempt(300);
    backoff.resumed();
    assertEquals(ResumeState.IDLE, backoff.state());
    assertEquals(0, backoff.failedAttempts());
    backoff.lost(1_000);
    assertEquals(1_100, backoff.nextAttemptAtMs());
  }

  @Test
  void aRefusalGivesUpAtOnce() {
    ResumeBackoff backoff = new ResumeBackoff(100, 10_000, 5, always(1.0));
    backoff.lost(0);
    backoff.startAttempt(100);
    assertFalse(backoff.attemptFailed(100, false));
    assertEquals(ResumeState.IDLE, backoff.state());
    assertEquals(1, backoff.failedAttempts());
  }

  @Test
  void stopEndsWaitingAndLateAnswersAreIgnored() {
    ResumeBackoff backoff = new ResumeBackoff(100, 10_000, 5, always(1.0));
    backoff.lost(0);
    backoff.stop();
    assertEquals(ResumeState.IDLE, backoff.state());
    assertFalse(backoff.startAttempt(1_000));
    assertFalse(backoff.attemptFailed(1_000, true), "no attempt was running");
    assertEquals(ResumeState.IDLE, backoff.state());
  }

  @Test
  void aLossWhileResumingDoesNotRestartTheSchedule() {
    ResumeBackoff backoff = new ResumeBackoff(100, 10_000, 5, always(1.0));
    backoff.lost(0);
    backoff.startAttempt(100);
    backoff.attemptFailed(100, true);
    backoff.lost(150);
    assertEquals(300, backoff.nextAttemptAtMs());
    assertEquals(1, backoff.failedAttempts());
  }

  @Test
  void hugeBoundsDoNotOverflow() {
    ResumeBackoff backoff = new ResumeBackoff(1L << 40, Long.MAX_VALUE / 4, 100, always(1.0));
    assertEquals(1L << 40, backoff.delayBoundMs(0));
    assertEquals(Long.MAX_VALUE / 4, backoff.delayBoundMs(30));
    assertEquals(Long.MAX_VALUE / 4, backoff.delayBoundMs(99));
    assertEquals(1L << 60, backoff.delayBoundMs(20));
    assertEquals(Long.MAX_VALUE / 4, backoff.delayBoundMs(21));
  }

  @Test
  void badSettingsAreRefused() {
    assertThrows(IllegalArgumentException.class, () -> new ResumeBackoff(0, 10, 1, always(0)));
    assertThrows(IllegalArgumentException.class, () -> new ResumeBackoff(10, 5, 1, always(0)));
    assertThrows(IllegalArgumentException.class, () -> new ResumeBackoff(10, 10, 0, always(0)));
    assertThrows(IllegalArgumentException.class, () -> new ResumeBackoff(10, 10, 1, null));
  }

  @Test
  void lostNetworksAndStoppingServersAreResumedRefusalsAndRequestsAreNot() {
    ErrorCode none = ErrorCode.ERROR_CODE_UNSPECIFIED;
    assertTrue(ResumeBackoff.worthResuming(ControlCloseReason.CONNECTION_LOST, none));
    assertTrue(ResumeBackoff.worthResuming(ControlCloseReason.REQUEST_TIMEOUT, none));
    assertTrue(
        ResumeBackoff.worthResuming(ControlCloseReason.SERVER_ERROR, ErrorCode.SHUTTING_DOWN));
    assertTrue(
        ResumeBackoff.worthResuming(ControlCloseReason.SERVER_ERROR, ErrorCode.FRAME_TIMEOUT));
    assertFalse(
        ResumeBackoff.worthResuming(ControlCloseReason.SERVER_ERROR, ErrorCode.IDLE_TIMEOUT));
    assertFalse(ResumeBackoff.worthResuming(ControlCloseReason.REQUESTED, none));
    assertFalse(
        ResumeBackoff.worthResuming(ControlCloseReason.SERVER_ERROR, ErrorCode.ACCOUNT_BANNED));
    assertFalse(ResumeBackoff.worthResuming(ControlCloseReason.SERVER_ERROR, ErrorCode.MALFORMED));
    for (ControlCloseReason reason : ControlCloseReason.values()) {
      if (reason.refusesServer())
        assertFalse(ResumeBackoff.worthResuming(reason, none), "" + reason);
    }
  }

  @Test
  void aGoneSessionIsNotRetriedABusyServerIs() {
    assertFalse(ResumeBackoff.worthRetrying(ErrorCode.UNKNOWN_SESSION));
    assertFalse(ResumeBackoff.worthRetrying(ErrorCode.EXPIRED_SESSION));
    assertFalse(ResumeBackoff.worthRetrying(ErrorCode.ACCOUNT_BANNED));
    assertFalse(ResumeBackoff.worthRetrying(ErrorCode.WRONG_STATE));
    assertTrue(ResumeBackoff.worthRetrying(ErrorCode.SERVER_BUSY));
    assertTrue(ResumeBackoff.worthRetrying(ErrorCode.RATE_LIMITED));
    assertTrue(ResumeBackoff.worthRetrying(ErrorCode.INTERNAL));
    assertTrue(ResumeBackoff.worthRetrying(ErrorCode.SHUTTING_DOWN));
  }
}
