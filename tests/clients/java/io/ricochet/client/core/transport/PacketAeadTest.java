package io.ricochet.client.core.transport;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;

import java.lang.management.ManagementFactory;
import java.util.Arrays;
import java.util.Random;
import org.bouncycastle.crypto.modes.ChaCha20Poly1305;
import org.bouncycastle.crypto.params.AEADParameters;
import org.bouncycastle.crypto.params.KeyParameter;
import org.junit.jupiter.api.Test;

/**
 * PacketAead against Bouncy Castle's own ChaCha20Poly1305 mode with AEADParameters (the nonce and
 * additional data of PROTOCOL.md §5.2), and its promise to allocate nothing once warm.
 */
class PacketAeadTest {
  private static byte[] referenceSeal(
      byte[] key, long protocolId, byte type, long sequence, byte[] body) throws Exception {
    byte[] nonce = new byte[12];
    Packets.putU64(nonce, 4, sequence);
    byte[] ad = new byte[25];
    System.arraycopy(Packets.VERSION, 0, ad, 0, 16);
    Packets.putU64(ad, 16, protocolId);
    ad[24] = type;
    ChaCha20Poly1305 reference = new ChaCha20Poly1305();
    reference.init(true, new AEADParameters(new KeyParameter(key), 128, nonce, ad));
    byte[] out = new byte[body.length + 16];
    int written = reference.processBytes(body, 0, body.length, out, 0);
    reference.doFinal(out, written);
    return out;
  }

  @Test
  void sealsAsBouncyCastlesChaCha20Poly1305ModeAndOpensWhatItSealed() throws Exception {
    Random random = new Random(1305);
    for (int round = 0; round < 300; ++round) {
      byte[] key = new byte[32];
      random.nextBytes(key);
      long protocolId = random.nextLong();
      long sequence = random.nextLong();
      byte type = (byte) (1 + random.nextInt(6));
      byte[] body = new byte[round < 20 ? round : random.nextInt(Packets.MAX_BODY_BYTES + 1)];
      random.nextBytes(body);
      PacketAead aead = new PacketAead(key, protocolId);
      byte[] packet = new byte[Packets.MAX_DATAGRAM_BYTES];
      packet[0] = type;
      Packets.putU64(packet, 1, sequence);
      System.arraycopy(body, 0, packet, 9, body.length);
      int length = aead.seal(packet, 9 + body.length);
      assertEquals(9 + body.length + 16, length);
      assertArrayEquals(referenceSeal(key, protocolId, type, sequence, body),
          Arrays.copyOfRange(packet, 9, length), "round " + round);
      byte[] opened = new byte[Packets.MAX_DATAGRAM_BYTES];
      assertEquals(body.length, aead.open(packet, length, opened));
      assertArrayEquals(body, Arrays.copyOf(opened, body.length));
      assertEquals(-1, aead.open(packet, 24, opened)); // shorter than header and tag
    }
  }

  @Test
  void sealingAndOpeningAllocateNothingOnceWarm() {
    com.sun.management.ThreadMXBean threads =
        (com.sun.management.ThreadMXBean) ManagementFactory.getThreadMXBean();
    long thread = Thread.currentThread().getId();
    PacketAead seal = new PacketAead(FakeServer.CLIENT_TO_SERVER, Packets.PROTOCOL_ID);
    PacketAead open = new PacketAead(FakeServer.CLIENT_TO_SERVER, Packets.PROTOCOL_ID);
    byte[] packet = new byte[Packets.MAX_DATAGRAM_BYTES];
    byte[] body = new byte[Packets.MAX_DATAGRAM_BYTES];
    long allocated = 0;
    for (int pass = 0; pass < 10 && (pass < 3 || allocated != 0); ++pass) { // warm up, compile
      long opened = 0;
      long before = threads.getThreadAllocatedBytes(thread);
      for (int i = 0; i < 20_000; ++i) {
        packet[0] = 5;
        Packets.putU64(packet, 1, i);
        int length = seal.seal(packet, 9 + 64 + i % 1000);
        opened += open.open(packet, length, body);
      }
      allocated = threads.getThreadAllocatedBytes(thread) - before;
      assertEquals(20_000L * 64 + 20L * (999 * 1000 / 2), opened); // every packet opened
    }
    System.out.println("PacketAead: " + allocated + " bytes allocated for 20000 seals and opens");
    assertEquals(0, allocated, "bytes allocated for 20 000 seals and opens once warm");
  }
}
