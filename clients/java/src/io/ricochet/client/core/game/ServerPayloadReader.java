package io.ricochet.client.core.game;

/**
 * Reads a serialised {@code ServerPayload} (game.proto; PROTOCOL.md Game payloads) in place,
 * without allocating: its scalar fields into primitives, its snapshot's entity stream as a slice
 * of the caller's bytes (handed to the snapshot decoder as is). Follows protobuf's proto3 rules
 * as the generated parser does: fields in any order, a repeated scalar field or message merged
 * (the last scalar wins, {@code ammo} appends, packed or not), unknown fields (groups included)
 * skipped, a zero field number, a reserved wire type, a varint over 10 bytes or a length past the
 * end refused. Untrusted input: {@link #read} returns false and never throws for bad bytes.
 * Single-threaded; the values are those of the last {@code read}, valid until the next.
 */
public final class ServerPayloadReader {
  private static final int VARINT = 0;
  private static final int FIXED64 = 1;
  private static final int LENGTH_DELIMITED = 2;
  private static final int START_GROUP = 3;
  private static final int END_GROUP = 4;
  private static final int FIXED32 = 5;
  private static final int MAX_GROUP_DEPTH = 100;
  private static final long U32 = 0xFFFFFFFFL;

  private byte[] bytes = new byte[0];
  private int position;
  private boolean malformed;

  private boolean hasSnapshot;
  private long snapshotTick;
  private long baselineAge;
  private int entitiesOffset;
  private int entitiesLength;
  private long lastInputSequence;
  private long serverTick;
  private long yourEntityId;
  private final PlayerStatus status = new PlayerStatus();

  /**
   * Reads {@code bytes[offset, offset + length)}; true when it is a well-formed ServerPayload (the
   * accessors then show it), false when not (the accessors show an empty payload). The entity
   * stream is not copied: {@link #entitiesOffset} indexes {@code bytes}. Throws only when the
   * range is outside the array (a caller's bug).
   */
  public boolean read(byte[] bytes, int offset, int length) {
    if (offset < 0 || length < 0 || offset > bytes.length - length) {
      throw new IndexOutOfBoundsException(
          "read(" + offset + ", " + length + ") of " + bytes.length);
    }
    clear();
    this.bytes = bytes;
    position = offset;
    malformed = false;
    readPayload(offset + length);
    if (malformed) clear();
    return !malformed;
  }

  /** Whether field 1 ({@code snapshot}) was present. */
  public boolean hasSnapshot() {
    return hasSnapshot;
  }

  /** {@code snapshot.tick}, unsigned 32-bit. */
  public long snapshotTick() {
    return snapshotTick;
  }

  /** {@code snapshot.baseline_age}, unsigned 32-bit. */
  public long baselineAge() {
    return baselineAge;
  }

  /** Where {@code snapshot.entities} starts in the array given to {@link #read}. */
  public int entitiesOffset() {
    return entitiesOffset;
  }

  /** {@code snapshot.entities}' length, bytes. */
  public int entitiesLength() {
    return entitiesLength;
  }

  /** {@code last_input_sequence}: the last input the server applied (0: none), unsigned. */
  public long lastInputSequence() {
    return lastInputSequence;
  }

  /** {@code server_tick}, unsigned 32-bit. */
  public long serverTick() {
    return serverTick;
  }

  /** {@code your_entity_id}: the entity this client controls, unsigned 32-bit. */
  public long yourEntityId() {
    return yourEntityId;
  }

  /** The own player's status (field 5; {@link PlayerStatus#present()} says whether it came). */
  public PlayerStatus status() {
    return status;
  }

  private void clear() {
    hasSnapshot = false;
    snapshotTick = 0;
    baselineAge = 0;
    entitiesOffset = 0;
    entitiesLength = 0;
    lastInputSequence = 0;
    serverTick = 0;
    yourEntityId = 0;
    status.clear();
  }

  private void readPayload(int end) {
    while (position < end && !malformed) {
      int key = tag(end);
      if (malformed) return;
      int field = key >>> 3;
      int wire = key & 7;
      if (field == 1 && wire == LENGTH_DELIMITED) {
        int stop = lengthEnd(end);
        if (malformed) return;
        hasSnapshot = true;
        readSnapshot(stop);
      } else if (field == 2 && wire == VARINT) {
        lastInputSequence = varint(end) & U32;
      } else if (field == 3 && wire == VARINT) {
        serverTick = varint(end) & U32;
      } else if (field == 4 && wire == VARINT) {
        yourEntityId = varint(end) & U32;
      } else if (field == 5 && wire == LENGTH_DELIMITED) {
        int stop = lengthEnd(end);
        if (malformed) return;
        status.setPresent();
        readStatus(stop);
      } else {
        skip(key, end, 0);
      }
    }
  }

  private void readSnapshot(int end) {
    while (position < end && !malformed) {
      int key = tag(end);
      if (malformed) return;
      int field = key >>> 3;
      int wire = key & 7;
      if (field == 1 && wire == VARINT) {
        snapshotTick = varint(end) & U32;
      } else if (field == 2 && wire == VARINT) {
        baselineAge = varint(end) & U32;
      } else if (field == 3 && wire == LENGTH_DELIMITED) {
        int stop = lengthEnd(end);
        if (malformed) return;
        entitiesOffset = position;
        entitiesLength = stop - position;
        position = stop;
      } else {
        skip(key, end, 0);
      }
    }
  }

  private void readStatus(int end) {
    while (position < end && !malformed) {
      int key = tag(end);
      if (malformed) return;
      int field = key >>> 3;
      int wire = key & 7;
      if (field == 1 && wire == VARINT) {
        status.setHealth((int) varint(end));
      } else if (field == 2 && wire == VARINT) {
        status.setArmor((int) varint(end));
      } else if (field == 3 && wire == VARINT) {
        status.setWeapon((int) varint(end));
      } else if (field == 4 && wire == VARINT) {
        status.addAmmo((int) varint(end));
      } else if (field == 4 && wire == LENGTH_DELIMITED) {
        int stop = lengthEnd(end);
        while (!malformed && position < stop) status.addAmmo((int) varint(stop));
      } else if (field == 5 && wire == VARINT) {
        status.setAlive(varint(end) != 0);
      } else if (field == 6 && wire == VARINT) {
        status.setRespawnTick(varint(end) & U32);
      } else if (field == 7 && wire == VARINT) {
        status.setProtectedUntilTick(varint(end) & U32);
      } else if (field == 8 && wire == VARINT) {
        status.setTeam((int) varint(end));
      } else {
        skip(key, end, 0);
      }
    }
  }

  /**
   * A field's key: a varint whose low 32 bits are kept (as protobuf's readTag does), field number
   * >= 1, a wire type protobuf defines.
   */
  private int tag(int end) {
    int key = (int) varint(end);
    if (malformed) return 0;
    if ((key >>> 3) == 0 || (key & 7) > FIXED32) {
      malformed = true;
      return 0;
    }
    return key;
  }

  /** Reads a length and returns where the delimited bytes end; malformed when past {@code end}. */
  private int lengthEnd(int end) {
    long length = varint(end);
    if (malformed) return position;
    if (length < 0 || length > end - position) {
      malformed = true;
      return position;
    }
    return position + (int) length;
  }

  private long varint(int end) {
    long value = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (position >= end) {
        malformed = true;
        return 0;
      }
      int b = bytes[position++];
      value |= (long) (b & 0x7F) << shift;
      if (b >= 0) return value;
    }
    malformed = true; // more than 10 bytes
    return 0;
  }

  /** Skips the value of an unknown field whose key was just read. */
  private void skip(int key, int end, int depth) {
    switch (key & 7) {
      case VARINT:
        varint(end);
        return;
      case FIXED64:
        advance(8, end);
        return;
      case LENGTH_DELIMITED:
        position = lengthEnd(end);
        return;
      case FIXED32:
        advance(4, end);
        return;
      case START_GROUP:
        if (depth >= MAX_GROUP_DEPTH) {
          malformed = true;
          return;
        }
        while (!malformed) {
          if (position >= end) {
            malformed = true;
            return;
          }
          int inner = tag(end);
          if (malformed) return;
          if ((inner & 7) == END_GROUP) {
            if ((inner >>> 3) != (key >>> 3)) malformed = true;
            return;
          }
          skip(inner, end, depth + 1);
        }
        return;
      default: // an END_GROUP with no group open
        malformed = true;
    }
  }

  private void advance(int count, int end) {
    if (end - position < count) {
      malformed = true;
      return;
    }
    position += count;
  }
}
