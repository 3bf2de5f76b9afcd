package io.ricochet.client.core.game;

/**
 * The inputs of one game connection (PROTOCOL.md ClientPayload and Input): each {@link #push}
 * numbers an input 1, 2, 3 ... and keeps the newest {@link #MAX_PER_PAYLOAD}, so that every
 * payload repeats the last few (one lost packet loses no input); {@code
 * ServerPayload.last_input_sequence} acknowledges them. Stored in primitive arrays: nothing is
 * allocated after construction. Single-threaded; a new connection takes a new history.
 */
public final class InputHistory {
  /** Inputs a payload may carry (the protocol's limit). */
  public static final int MAX_PER_PAYLOAD = 8;

  private final int[] sequence = new int[MAX_PER_PAYLOAD];
  private final int[] moveRight = new int[MAX_PER_PAYLOAD];
  private final int[] moveForward = new int[MAX_PER_PAYLOAD];
  private final float[] yaw = new float[MAX_PER_PAYLOAD];
  private final float[] pitch = new float[MAX_PER_PAYLOAD];
  private final int[] buttons = new int[MAX_PER_PAYLOAD];
  private final int[] weaponSlot = new int[MAX_PER_PAYLOAD];
  private final int[] viewTick = new int[MAX_PER_PAYLOAD];
  private final int[] viewFraction = new int[MAX_PER_PAYLOAD];
  private long nextSequence = 1;
  private long acknowledged;

  /**
   * Numbers and keeps one tick's input, already in the wire's ranges (checked by {@link
   * InputState}); {@code viewTick} unsigned 32-bit, {@code viewFraction} 0..255.
   */
  public void push(InputState input, long viewTick, int viewFraction) {
    int slot = (int) (nextSequence % MAX_PER_PAYLOAD);
    sequence[slot] = (int) nextSequence;
    moveRight[slot] = input.moveRight();
    moveForward[slot] = input.moveForward();
    yaw[slot] = input.yaw();
    pitch[slot] = input.pitch();
    buttons[slot] = input.buttons();
    weaponSlot[slot] = input.weaponSlot();
    this.viewTick[slot] = (int) viewTick;
    this.viewFraction[slot] = viewFraction;
    ++nextSequence;
  }

  /**
   * From an untrusted payload: the server applied every input up to {@code sequence}. False (and
   * ignored) when this connection never sent that sequence; a smaller one than before is kept.
   */
  public boolean acknowledge(long sequence) {
    if (sequence >= nextSequence) return false;
    if (sequence > acknowledged) acknowledged = sequence;
    return true;
  }

  /** The sequence of the newest input pushed; 0 before the first. */
  public long lastSequence() {
    return nextSequence - 1;
  }

  /** The newest sequence the server said it applied; 0 before any. */
  public long acknowledged() {
    return acknowledged;
  }

  /** How many of the newest inputs are held (at most {@link #MAX_PER_PAYLOAD}). */
  public int held() {
    return (int) Math.min(nextSequence - 1, MAX_PER_PAYLOAD);
  }

  /**
   * Writes the newest {@code count} inputs (at most {@link #held}), oldest first, as the {@code
   * inputs} fields of a ClientPayload into {@code out} from {@code offset}; returns the new offset.
   */
  int writeNewest(int count, byte[] out, int offset) {
    int at = offset;
    for (long s = nextSequence - count; s < nextSequence; ++s) {
      int slot = (int) (s % MAX_PER_PAYLOAD);
      int length = inputBytes(slot);
      at = Wire.putTag(out, at, 1, Wire.LENGTH_DELIMITED);
      at = Wire.putVarint(out, at, length);
      at = writeInput(slot, out, at);
    }
    return at;
  }

  private int inputBytes(int slot) {
    int bytes = 0;
    if (sequence[slot] != 0) bytes += 1 + Wire.varintBytes(sequence[slot] & 0xFFFFFFFFL);
    if (moveRight[slot] != 0) bytes += 1 + Wire.varintBytes(Wire.zigZag(moveRight[slot]));
    if (moveForward[slot] != 0) bytes += 1 + Wire.varintBytes(Wire.zigZag(moveForward[slot]));
    if (Float.floatToRawIntBits(yaw[slot]) != 0) bytes += 5;
    if (Float.floatToRawIntBits(pitch[slot]) != 0) bytes += 5;
    if (buttons[slot] != 0) bytes += 1 + Wire.varintBytes(buttons[slot] & 0xFFFFFFFFL);
    if (weaponSlot[slot] != 0) bytes += 1 + Wire.varintBytes(weaponSlot[slot] & 0xFFFFFFFFL);
    if (viewTick[slot] != 0) bytes += 1 + Wire.varintBytes(viewTick[slot] & 0xFFFFFFFFL);
    if (viewFraction[slot] != 0) bytes += 1 + Wire.varintBytes(viewFraction[slot] & 0xFFFFFFFFL);
    return bytes;
  }

  private int writeInput(int slot, byte[] out, int offset) {
    int at = offset;
    at = Wire.putUnsignedField(out, at, 1, sequence[slot]);
    if (moveRight[slot] != 0) {
      at = Wire.putTag(out, at, 2, Wire.VARINT);
      at = Wire.putVarint(out, at, Wire.zigZag(moveRight[slot]));
    }
    if (moveForward[slot] != 0) {
      at = Wire.putTag(out, at, 3, Wire.VARINT);
      at = Wire.putVarint(out, at, Wire.zigZag(moveForward[slot]));
    }
    at = Wire.putFloatField(out, at, 4, yaw[slot]);
    at = Wire.putFloatField(out, at, 5, pitch[slot]);
    at = Wire.putUnsignedField(out, at, 6, buttons[slot]);
    at = Wire.putUnsignedField(out, at, 7, weaponSlot[slot]);
    at = Wire.putUnsignedField(out, at, 8, viewTick[slot]);
    at = Wire.putUnsignedField(out, at, 9, viewFraction[slot]);
    return at;
  }
}
