package io.ricochet.client.core.transport;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.util.Random;
import org.junit.jupiter.api.Test;

/** The replay window: duplicates and too-old sequences are refused; acks name what arrived. */
class ReplayWindowTest {
  private static boolean offer(ReplayWindow window, long sequence) {
    if (window.alreadyReceived(sequence)) return false;
    window.markReceived(sequence);
    return true;
  }

  @Test
  void refusesDuplicatesAndSequences256OrMoreBehindTheNewest() {
    ReplayWindow window = new ReplayWindow();
    assertTrue(offer(window, 1000));
    assertFalse(offer(window, 1000));
    assertTrue(offer(window, 745)); // 255 behind
    assertFalse(offer(window, 744)); // 256 behind
    assertFalse(offer(window, 0));
    assertFalse(offer(window, 745));
    assertTrue(offer(window, 999));
    assertTrue(offer(window, 5000)); // far ahead: everything before is forgotten
    assertFalse(offer(window, 1000));
    assertTrue(offer(window, 4745));
  }

  @Test
  void aSequenceWithBit63SetIsNeverBelowTheNewest() {
    ReplayWindow window = new ReplayWindow();
    assertTrue(offer(window, 10));
    assertFalse(window.alreadyReceived(Long.MIN_VALUE)); // unsigned: far ahead, not behind
  }

  @Test
  void theAckHeaderNamesTheNewestAndThe32BeforeIt() {
    ReplayWindow window = new ReplayWindow();
    assertEquals(0, window.ack());
    assertEquals(0, window.ackBits());
    for (long sequence : new long[] {65_534, 65_535, 65_537, 65_570}) offer(window, sequence);
    assertEquals(65_570 & 0xFFFF, window.ack());
    // 65_537 is 33 behind (bit 32: outside the ack bits); 65_535, 65_534 further.
    assertEquals(0, window.ackBits());
    offer(window, 65_569);
    offer(window, 65_538);
    assertEquals((1 << 0) | (1 << 31), window.ackBits());
  }

  @Test
  void everyAcceptedSequenceIsAcceptedOnceAgainstASimpleModel() {
    Random random = new Random(256);
    ReplayWindow window = new ReplayWindow();
    java.util.Set<Long> seen = new java.util.HashSet<>();
    long newest = -1;
    for (int i = 0; i < 100_000; ++i) {
      long sequence = Math.max(0, newest + random.nextInt(300) - 280);
      boolean expected = !seen.contains(sequence) && (newest < 0 || sequence > newest - 256);
      assertEquals(expected, offer(window, sequence), "sequence " + sequence + " newest " + newest);
      if (expected) {
        seen.add(sequence);
        newest = Math.max(newest, sequence);
      }
    }
    assertEquals(newest + 1 - seen.size(), window.missing());
  }
}
