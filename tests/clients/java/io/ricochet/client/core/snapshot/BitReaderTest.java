package io.ricochet.client.core.snapshot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import org.junit.jupiter.api.Test;

/** The stream's bits and codes (PROTOCOL.md, Snapshots §3; proto/bit_stream.h). */
class BitReaderTest {
  private static BitReader reading(byte[] bytes) {
    BitReader reader = new BitReader();
    reader.reset(bytes, 0, bytes.length);
    return reader;
  }

  @Test
  void expGolombCodesOfTheProtocolsExamples() {
    // k = 0: 0 -> 1, 1 -> 010, 2 -> 011, 3 -> 00100; then order 3: 5 -> 1101.
    BitReader reader = reading(new StreamWriter().bits("1 010 011 00100 1101").bytes());
    assertEquals(0, reader.readExpGolomb(0));
    assertEquals(1, reader.readExpGolomb(0));
    assertEquals(2, reader.readExpGolomb(0));
    assertEquals(3, reader.readExpGolomb(0));
    assertEquals(5, reader.readExpGolomb(3));
    assertFalse(reader.failed());
    assertTrue(reader.onlyPaddingLeft());
  }

  @Test
  void rawFieldsAreReadMostSignificantBitFirstAcrossBytes() {
    BitReader reader = reading(new byte[] {(byte) 0xA5, (byte) 0x5A, 1, 2, 3, 4, 5, 6, 7, 8, 9});
    assertEquals(0x5, reader.readBits(3)); // 101
    assertEquals(0x55A0, reader.readBits(17)); // 00101, 0101 1010, 0000
    assertEquals(0x0102030405060708L, reader.readBits(60)); // 0001, then 02 .. 08
    assertEquals(9, reader.readBits(8));
    assertEquals(0, reader.bitsLeft());
    assertFalse(reader.failed());
  }

  @Test
  void aWholeWordAndWideCodesRead() {
    StreamWriter out = new StreamWriter().bits(0x0123456789ABCDEFL, 64);
    out.eg((1L << 42) - 2, 0); // the widest body accepted: 41 zeros, then 42 bits
    out.seg(-123456789L, 5);
    BitReader reader = reading(out.bytes());
    assertEquals(0x0123456789ABCDEFL, reader.readBits(64));
    assertEquals((1L << 42) - 2, reader.readExpGolomb(0));
    assertEquals(-123456789L, BitReader.unzigzag(reader.readExpGolomb(5)));
    assertFalse(reader.failed());
  }

  @Test
  void aCodeWiderThan42BitsIsMalformedAndTheEndIsTruncation() {
    BitReader wide = reading(new StreamWriter().eg((1L << 42) - 1, 0).bytes()); // a 43-bit body
    assertEquals(0, wide.readExpGolomb(0));
    assertTrue(wide.failed());
    assertTrue(wide.malformed());
    BitReader shortCode = reading(new byte[] {0x00, 0x01}); // 15 zeros, then the stream ends
    assertEquals(0, shortCode.readExpGolomb(0));
    assertTrue(shortCode.failed());
    assertFalse(shortCode.malformed());
    BitReader past = reading(new byte[] {(byte) 0xFF});
    assertEquals(0xFF, past.readBits(8));
    assertEquals(0, past.readBits(1));
    assertTrue(past.failed());
    assertEquals(0, past.bitsLeft());
    assertEquals(0, past.readBits(0), "failure is sticky");
    assertFalse(past.onlyPaddingLeft());
  }

  @Test
  void zigZagMapsBack() {
    assertEquals(0, BitReader.unzigzag(0));
    assertEquals(-1, BitReader.unzigzag(1));
    assertEquals(1, BitReader.unzigzag(2));
    assertEquals(-2, BitReader.unzigzag(3));
    assertEquals(Long.MIN_VALUE, BitReader.unzigzag(-1L));
  }

  @Test
  void paddingIsFewerThan8ZeroBits() {
    BitReader reader = reading(new byte[] {(byte) 0xE0});
    reader.readBits(3);
    assertTrue(reader.onlyPaddingLeft());
    BitReader dirty = reading(new byte[] {(byte) 0xE1});
    dirty.readBits(3);
    assertFalse(dirty.onlyPaddingLeft());
    BitReader whole = reading(new byte[] {(byte) 0xE0, 0});
    whole.readBits(3);
    assertFalse(whole.onlyPaddingLeft());
  }
}
