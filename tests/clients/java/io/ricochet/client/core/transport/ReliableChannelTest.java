package io.ricochet.client.core.transport;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.util.ArrayList;
import java.util.Collections;
import java.util.List;
import java.util.Random;
import org.junit.jupiter.api.Test;

/** ReliableSender and ReliableReceiver: order, dedupe, the window, resends, acks, wrapping ids. */
class ReliableChannelTest {
  private static final long RESEND_US = 100_000;

  @Test
  void theReceiverReordersAndDedupes() {
    ReliableReceiver receiver = new ReliableReceiver();
    byte[] bytes = {10, 11, 12, 13};
    assertEquals(ReliableReceiver.Outcome.ACCEPTED, receiver.receive(2, bytes, 2, 1));
    assertNull(receiver.pop());
    assertEquals(ReliableReceiver.Outcome.ACCEPTED, receiver.receive(1, bytes, 1, 1));
    assertEquals(ReliableReceiver.Outcome.DUPLICATE, receiver.receive(2, bytes, 3, 1));
    assertEquals(ReliableReceiver.Outcome.ACCEPTED, receiver.receive(0, bytes, 0, 2));
    assertArrayEquals(new byte[] {10, 11}, receiver.pop());
    assertArrayEquals(new byte[] {11}, receiver.pop());
    assertArrayEquals(new byte[] {12}, receiver.pop()); // the first copy of 2 wins
    assertNull(receiver.pop());
    assertEquals(ReliableReceiver.Outcome.DUPLICATE, receiver.receive(0, bytes, 0, 1));
    assertEquals(
        ReliableReceiver.Outcome.DUPLICATE, receiver.receive(65_535 - 30_000, bytes, 0, 1));
    assertEquals(ReliableReceiver.Outcome.ACCEPTED, receiver.receive(3 + 255, bytes, 0, 1));
    assertEquals(ReliableReceiver.Outcome.OUT_OF_WINDOW, receiver.receive(3 + 256, bytes, 0, 1));
  }

  @Test
  void idsWrapAfter65535() {
    ReliableSender sender = new ReliableSender(256, 256);
    ReliableReceiver receiver = new ReliableReceiver();
    byte[] packet = new byte[Packets.MAX_DATAGRAM_BYTES];
    int[] ids = new int[255];
    long now = 0;
    for (int i = 0; i < 70_000; ++i) {
      byte[] message = {(byte) i, (byte) (i >> 8), (byte) (i >> 16)};
      assertTrue(sender.push(message, 0, 3));
      assertEquals(1, sender.takeDue(now, RESEND_US, 1000, packet, 0, ids));
      assertEquals(i & 0xFFFF, ids[0]);
      assertEquals(ReliableReceiver.Outcome.ACCEPTED,
          receiver.receive(Packets.getU16(packet, 0), packet, 4, Packets.getU16(packet, 2)));
      assertArrayEquals(message, receiver.pop());
      sender.acknowledge(ids[0]);
      assertEquals(0, sender.pending());
    }
  }

  @Test
  void theSenderResendsUntilAckedAndKeepsOrderWithinItsBudget() {
    ReliableSender sender = new ReliableSender(256, 256);
    byte[] packet = new byte[Packets.MAX_DATAGRAM_BYTES];
    int[] ids = new int[255];
    sender.push(new byte[100], 0, 100);
    sender.push(new byte[10], 0, 10);
    sender.push(new byte[10], 0, 10);
    // A budget for the first only: the small ones must not overtake it.
    assertEquals(0, sender.takeDue(0, RESEND_US, 103, packet, 0, ids));
    assertEquals(1, sender.takeDue(0, RESEND_US, 104 + 13, packet, 0, ids));
    assertEquals(104, sender.takenBytes());
    assertEquals(2, sender.takeDue(10, RESEND_US, 1000, packet, 0, ids));
    assertEquals(1, ids[0]);
    assertEquals(2, ids[1]);
    assertFalse(sender.hasDue(99_999, RESEND_US));
    assertTrue(sender.hasDue(100_000, RESEND_US));
    sender.acknowledge(1);
    assertEquals(3, sender.pending()); // 0 is not acked: 1 waits behind it
    assertEquals(1, sender.takeDue(100_000, RESEND_US, 1000, packet, 0, ids));
    assertEquals(0, ids[0]);
    assertEquals(1, sender.resends());
    sender.acknowledge(0);
    assertEquals(1, sender.pending());
    sender.acknowledge(0); // again: nothing
    sender.acknowledge(7); // never sent: nothing
    assertEquals(1, sender.pending());
    assertEquals(1, sender.takeDue(200_000, RESEND_US, 1000, packet, 0, ids));
    assertEquals(2, ids[0]);
  }

  @Test
  void atMostAWindowIsInFlightAndTheQueueIsCapped() {
    ReliableSender sender = new ReliableSender(4, 6);
    byte[] packet = new byte[Packets.MAX_DATAGRAM_BYTES];
    int[] ids = new int[255];
    for (int i = 0; i < 6; ++i) assertTrue(sender.push(new byte[] {1}, 0, 1));
    assertFalse(sender.push(new byte[] {1}, 0, 1));
    assertEquals(4, sender.takeDue(0, RESEND_US, 1000, packet, 0, ids));
    assertFalse(sender.hasDue(1, RESEND_US)); // 4 and 5 wait for room
    sender.acknowledge(0);
    assertEquals(1, sender.takeDue(2, RESEND_US, 1000, packet, 0, ids));
    assertEquals(4, ids[0]);
  }

  @Test
  void overALossyReorderingLinkEveryMessageArrivesOnceInOrder() {
    Random random = new Random(8);
    ReliableSender sender = new ReliableSender(256, 1024);
    ReliableReceiver receiver = new ReliableReceiver();
    byte[] packet = new byte[Packets.MAX_DATAGRAM_BYTES];
    int[] ids = new int[255];
    List<byte[]> inFlight = new ArrayList<>();
    List<Integer> delivered = new ArrayList<>();
    int pushed = 0;
    for (long now = 0; now < 20_000_000; now += 10_000) {
      for (int k = random.nextInt(5); k > 0 && pushed < 2000; --k) {
        byte[] message = {(byte) pushed, (byte) (pushed >> 8)};
        if (!sender.push(message, 0, 2)) break;
        ++pushed;
      }
      int count = sender.takeDue(now, RESEND_US, 600, packet, 0, ids);
      if (count > 0 && random.nextInt(10) >= 3) { // 30 % lost
        byte[] copy = java.util.Arrays.copyOf(packet, sender.takenBytes());
        inFlight.add(copy);
        if (random.nextInt(5) == 0) inFlight.add(copy); // duplicated
      }
      Collections.shuffle(inFlight, random);
      while (inFlight.size() > 3) {
        byte[] arriving = inFlight.remove(inFlight.size() - 1);
        for (int at = 0; at < arriving.length;) {
          int id = Packets.getU16(arriving, at);
          int length = Packets.getU16(arriving, at + 2);
          // The sender never has more in flight than the receiver's window.
          assertTrue(receiver.receive(id, arriving, at + 4, length)
              != ReliableReceiver.Outcome.OUT_OF_WINDOW);
          if (random.nextInt(10) >= 2) sender.acknowledge(id); // 20 % of acks lost
          at += 4 + length;
        }
        for (byte[] message = receiver.pop(); message != null; message = receiver.pop()) {
          delivered.add((message[0] & 0xFF) | (message[1] & 0xFF) << 8);
        }
      }
    }
    assertEquals(2000, pushed);
    assertEquals(2000, delivered.size());
    for (int i = 0; i < delivered.size(); ++i) assertEquals(i, (int) delivered.get(i));
  }
}
