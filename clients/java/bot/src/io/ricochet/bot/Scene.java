package io.ricochet.bot;

import io.ricochet.client.GameSnapshot;
import io.ricochet.client.core.snapshot.EntityFlags;
import java.util.Arrays;

/**
 * The players a bot sees at one snapshot, where the client shows them (the own player predicted,
 * the others interpolated 100 ms behind): what {@link Brain} decides from. Refilled for every
 * snapshot by {@link JavaBot} ({@link #fill}), or by hand in tests ({@link #clear}, {@link
 * #addPlayer}); nothing allocated once its arrays are large enough.
 */
final class Scene {
  private long ownId;
  private boolean ownAlive;
  private int count;
  private long[] ids = new long[16];
  private float[] positions = new float[48];
  private boolean[] living = new boolean[16];

  /** Empties it: the own player is entity {@code ownId}, alive or waiting to respawn. */
  void clear(long ownId, boolean ownAlive) {
    this.ownId = ownId;
    this.ownAlive = ownAlive;
    count = 0;
  }

  /** Adds a player (the own one too) at x, y, z m; {@code isLiving}: neither dead nor away. */
  void addPlayer(long id, float x, float y, float z, boolean isLiving) {
    if (count == ids.length) {
      ids = Arrays.copyOf(ids, 2 * count);
      positions = Arrays.copyOf(positions, 6 * count);
      living = Arrays.copyOf(living, 2 * count);
    }
    ids[count] = id;
    positions[3 * count] = x;
    positions[3 * count + 1] = y;
    positions[3 * count + 2] = z;
    living[count] = isLiving;
    ++count;
  }

  /**
   * The players of {@code snapshot} (valid during its callback only) where the client shows them.
   */
  void fill(GameSnapshot snapshot) {
    clear(snapshot.yourEntityId(), snapshot.status().alive());
    for (int i = 0; i < snapshot.count(); ++i) {
      int flags = snapshot.flags(i);
      if (EntityFlags.kind(flags) != EntityFlags.KIND_PLAYER) continue;
      boolean isLiving = !EntityFlags.has(flags, EntityFlags.DEAD)
          && !EntityFlags.has(flags, EntityFlags.DISCONNECTED);
      addPlayer(snapshot.id(i), snapshot.shownPositionM(i, 0), snapshot.shownPositionM(i, 1),
          snapshot.shownPositionM(i, 2), isLiving);
    }
  }

  /** The own player's entity id (0: not known yet). */
  long ownId() {
    return ownId;
  }

  /** Whether the own player is alive (its status says so and it is in the snapshot). */
  boolean ownAlive() {
    return ownAlive && indexOf(ownId) >= 0;
  }

  /** Players in it. */
  int count() {
    return count;
  }

  /** The index of entity {@code id}, or -1. */
  int indexOf(long id) {
    for (int i = 0; i < count; ++i) {
      if (ids[i] == id) return i;
    }
    return -1;
  }

  /** The id of player {@code index}. */
  long id(int index) {
    return ids[index];
  }

  /** Player {@code index}'s position on {@code axis} 0..2, m. */
  float positionM(int index, int axis) {
    return positions[3 * index + axis];
  }

  /** Whether player {@code index} is neither dead nor away. */
  boolean living(int index) {
    return living[index];
  }
}
