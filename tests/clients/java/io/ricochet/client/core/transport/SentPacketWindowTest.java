package io.ricochet.client.core.transport;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import org.junit.jupiter.api.Test;

/** Acks recover full sequences from 16 bits, acknowledge carried reliable messages, time RTT. */
class SentPacketWindowTest {
  private static final int[] NONE = new int[0];

  @Test
  void anAckOf16BitsNamesTheNewestSentSequenceWithThoseBitsAcrossTheWrap() {
    SentPacketWindow window = new SentPacketWindow();
    ReliableSender sender = new ReliableSender(256, 256);
    for (long sequence = 65_530; sequence < 65_540; ++sequence) {
      window.onSent(sequence, sequence, NONE, 0);
    }
    // 65_538 is 0x10002: ack 2, and bit 3 names 65_538 - 1 - 3 = 65_534 (0xFFFE).
    window.onAck(2, 1 << 3, 65_540, 70_000, sender);
    assertTrue(window.acked(65_538));
    assertTrue(window.acked(65_534));
    assertFalse(window.acked(65_537));
    assertFalse(window.acked(2)); // never sent
    // An ack of a sequence never sent (above the newest sent) is ignored.
    window.onAck(100, ~0, 65_540, 70_000, sender);
    assertFalse(window.acked(65_535));
  }

  @Test
  void anAckBeforeAnythingWasSentOrOfAnUnsentSequenceIsIgnored() {
    SentPacketWindow window = new SentPacketWindow();
    ReliableSender sender = new ReliableSender(256, 256);
    window.onAck(0, ~0, 0, 1, sender);
    window.onSent(0, 0, NONE, 0);
    window.onAck(5, ~0, 1, 1, sender);
    assertFalse(window.acked(0));
    assertEquals(0, window.rttUs());
  }

  @Test
  void acknowledgesTheReliableMessagesAPacketCarriedOnceAndSmoothsTheRoundTrip() {
    SentPacketWindow window = new SentPacketWindow();
    ReliableSender sender = new ReliableSender(256, 256);
    byte[] packet = new byte[Packets.MAX_DATAGRAM_BYTES];
    int[] ids = new int[255];
    for (int i = 0; i < 3; ++i) sender.push(new byte[] {1}, 0, 1);
    int carried = sender.takeDue(0, 100_000, 1000, packet, 0, ids);
    window.onSent(0, 0, ids, carried);
    window.onSent(1, 10_000, NONE, 0);
    window.onAck(1, 1, 2, 80_000, sender); // acks 1 (70 ms) and 0 (80 ms)
    assertEquals(0, sender.pending());
    assertEquals(70_000 + (80_000 - 70_000) / 8, window.rttUs());
    window.onAck(1, 1, 2, 500_000, sender); // again: no new sample
    assertEquals(71_250, window.rttUs());
  }

  @Test
  void aPacketOutOfTheWindowCanNoLongerBeAcked() {
    SentPacketWindow window = new SentPacketWindow();
    ReliableSender sender = new ReliableSender(256, 256);
    for (long sequence = 0; sequence <= 256; ++sequence) window.onSent(sequence, 0, NONE, 0);
    window.onAck(256, ~0, 257, 1, sender);
    assertTrue(window.acked(256));
    assertTrue(window.acked(224));
    assertFalse(window.acked(0)); // its slot holds 256 now
  }
}
