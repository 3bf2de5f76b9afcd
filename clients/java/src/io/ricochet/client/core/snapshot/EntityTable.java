package io.ricochet.client.core.snapshot;

import java.util.Arrays;

/**
 * A set of quantised entity states in primitive arrays (one entity per index, three ints per
 * vector), which the decoder fills in place and grows only when a snapshot holds more entities
 * than any before: once warm, nothing is allocated. Fields as proto::QuantizedEntity.
 */
final class EntityTable {
  int count;
  int[] id; // unsigned
  int[] position; // 3 per entity, unsigned steps from the bounds' minimum
  int[] velocity; // 3 per entity, signed steps
  byte[] largest; // the smallest-three component left out, 0..3
  int[] orientation; // 3 per entity, signed steps
  byte[] flags;

  EntityTable(int capacity) {
    allocate(Math.max(1, capacity));
  }

  /** Room for {@code entities} entities, keeping the first {@code count}. */
  void ensureCapacity(int entities) {
    if (entities <= id.length) return;
    int capacity = id.length;
    while (capacity < entities) capacity = capacity > (1 << 29) ? entities : 2 * capacity;
    id = Arrays.copyOf(id, capacity);
    position = Arrays.copyOf(position, 3 * capacity);
    velocity = Arrays.copyOf(velocity, 3 * capacity);
    largest = Arrays.copyOf(largest, capacity);
    orientation = Arrays.copyOf(orientation, 3 * capacity);
    flags = Arrays.copyOf(flags, capacity);
  }

  /** Becomes a copy of {@code other}. */
  void copyOf(EntityTable other) {
    ensureCapacity(other.count);
    int n = other.count;
    System.arraycopy(other.id, 0, id, 0, n);
    System.arraycopy(other.position, 0, position, 0, 3 * n);
    System.arraycopy(other.velocity, 0, velocity, 0, 3 * n);
    System.arraycopy(other.largest, 0, largest, 0, n);
    System.arraycopy(other.orientation, 0, orientation, 0, 3 * n);
    System.arraycopy(other.flags, 0, flags, 0, n);
    count = n;
  }

  /** Appends entity {@code index} of {@code other} (room must have been made). */
  void append(EntityTable other, int index) {
    int to = count++;
    id[to] = other.id[index];
    largest[to] = other.largest[index];
    flags[to] = other.flags[index];
    for (int k = 0; k < 3; ++k) {
      position[3 * to + k] = other.position[3 * index + k];
      velocity[3 * to + k] = other.velocity[3 * index + k];
      orientation[3 * to + k] = other.orientation[3 * index + k];
    }
  }

  private void allocate(int capacity) {
    id = new int[capacity];
    position = new int[3 * capacity];
    velocity = new int[3 * capacity];
    largest = new byte[capacity];
    orientation = new int[3 * capacity];
    flags = new byte[capacity];
  }
}
