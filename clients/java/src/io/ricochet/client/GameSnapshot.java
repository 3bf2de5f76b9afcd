package io.ricochet.client;

import io.ricochet.client.core.game.ServerPayloadReader;
import io.ricochet.client.core.snapshot.QuantizationSpec;
import io.ricochet.client.core.snapshot.SnapshotView;
import java.util.Arrays;

/**
 * One decoded ServerPayload as {@link GameListener#onSnapshot} sees it: the entities of the
 * snapshot (ids ascending, quantised integers and their values in metres, m/s and unit
 * quaternions) and the rest of the payload (the server tick, the entity this client controls, the
 * last input the server applied, the own player's status). <b>Valid only during the callback</b>:
 * the object is pooled and refilled for a later snapshot once the callback returns; copy what you
 * keep. No accessor allocates.
 */
public final class GameSnapshot {
  private final QuantizationSpec spec;
  private int count;
  private long[] ids = new long[16];
  private int[] position = new int[48];
  private int[] velocity = new int[48];
  private int[] largest = new int[16];
  private int[] orientation = new int[48];
  private int[] flags = new int[16];
  private long tick;
  private long yourEntityId;
  private long lastInputSequence;
  private boolean hasStatus;
  private int health;
  private int armor;
  private int weapon;
  private final int[] ammo = new int[ServerPayloadReader.MAX_AMMO];
  private int ammoCount;
  private boolean alive;
  private long respawnTick;
  private long protectedUntilTick;
  private int team;

  GameSnapshot(QuantizationSpec spec) {
    this.spec = spec;
  }

  /** Copies the decoder's view and the payload's fields (the I/O thread, before the hand-off). */
  void fill(SnapshotView view, ServerPayloadReader payload) {
    count = view.count();
    if (ids.length < count) grow(count);
    for (int i = 0; i < count; ++i) {
      ids[i] = view.id(i);
      for (int a = 0; a < 3; ++a) {
        position[3 * i + a] = view.positionSteps(i, a);
        velocity[3 * i + a] = view.velocitySteps(i, a);
        orientation[3 * i + a] = view.orientationSteps(i, a);
      }
      largest[i] = view.orientationLargest(i);
      flags[i] = view.flags(i);
    }
    tick = view.tick();
    yourEntityId = payload.yourEntityId();
    lastInputSequence = payload.lastInputSequence();
    hasStatus = payload.hasStatus();
    health = payload.health();
    armor = payload.armor();
    weapon = payload.weapon();
    ammoCount = payload.ammoCount();
    for (int i = 0; i < ammoCount; ++i) ammo[i] = payload.ammo(i);
    alive = payload.alive();
    respawnTick = payload.respawnTick();
    protectedUntilTick = payload.protectedUntilTick();
    team = payload.team();
  }

  private void grow(int atLeast) {
    int size = Math.max(atLeast, ids.length * 2);
    ids = Arrays.copyOf(ids, size);
    position = Arrays.copyOf(position, 3 * size);
    velocity = Arrays.copyOf(velocity, 3 * size);
    largest = Arrays.copyOf(largest, size);
    orientation = Arrays.copyOf(orientation, 3 * size);
    flags = Arrays.copyOf(flags, size);
  }

  /** The server tick of the state shown (unsigned 32-bit). */
  public long tick() {
    return tick;
  }

  /** The entity this client controls (0 when the server named none). */
  public long yourEntityId() {
    return yourEntityId;
  }

  /** The last input sequence the server applied for this client (0: none yet). */
  public long lastInputSequence() {
    return lastInputSequence;
  }

  /** Entities held. */
  public int count() {
    return count;
  }

  /** The index of entity {@code id}, or -1 (binary search). */
  public int indexOf(long id) {
    int low = 0;
    int high = count - 1;
    while (low <= high) {
      int middle = (low + high) >>> 1;
      if (ids[middle] < id) {
        low = middle + 1;
      } else if (ids[middle] > id) {
        high = middle - 1;
      } else {
        return middle;
      }
    }
    return -1;
  }

  /** Entity {@code index}'s id. */
  public long id(int index) {
    return ids[checked(index)];
  }

  /** Position along {@code axis} (0 x, 1 y, 2 z, +Y up), m: the centre of its quantisation step. */
  public float positionM(int index, int axis) {
    return spec.positionM(positionSteps(index, axis), axis);
  }

  /** Position along {@code axis} in steps from the bounds' minimum, as the server sent it. */
  public int positionSteps(int index, int axis) {
    return position[3 * checked(index) + checkedAxis(axis)];
  }

  /** Velocity along {@code axis}, m/s. */
  public float velocityMps(int index, int axis) {
    return spec.velocityMps(velocity[3 * checked(index) + checkedAxis(axis)]);
  }

  /** The unit orientation quaternion into {@code xyzw} (x, y, z, w). */
  public void orientation(int index, float[] xyzw) {
    int base = 3 * checked(index);
    spec.orientation(
        largest[index], orientation[base], orientation[base + 1], orientation[base + 2], xyzw);
  }

  /** The entity's flag bits ({@link io.ricochet.client.core.snapshot.EntityFlags}). */
  public int flags(int index) {
    return flags[checked(index)];
  }

  /** Whether the payload carried the own player's status (the fields below). */
  public boolean hasStatus() {
    return hasStatus;
  }

  /** Own health, 0..100. */
  public int health() {
    return health;
  }

  /** Own armour, 0..100. */
  public int armor() {
    return armor;
  }

  /** The selected weapon (1 rifle, 2 rocket launcher, 3 grenade launcher). */
  public int weapon() {
    return weapon;
  }

  /** Ammunition counts carried, one per weapon. */
  public int ammoCount() {
    return ammoCount;
  }

  /** Ammunition of weapon {@code index + 1}. */
  public int ammo(int index) {
    if (index < 0 || index >= ammoCount) {
      throw new IndexOutOfBoundsException("ammo " + index + " of " + ammoCount);
    }
    return ammo[index];
  }

  /** Whether the own player is alive. */
  public boolean alive() {
    return alive;
  }

  /** While dead: the tick of the respawn. */
  public long respawnTick() {
    return respawnTick;
  }

  /** Spawn protection lasts until this tick. */
  public long protectedUntilTick() {
    return protectedUntilTick;
  }

  /** The own team (0 none, 1 red, 2 blue). */
  public int team() {
    return team;
  }

  private int checked(int index) {
    if (index < 0 || index >= count) {
      throw new IndexOutOfBoundsException("entity " + index + " of " + count);
    }
    return index;
  }

  private static int checkedAxis(int axis) {
    if (axis < 0 || axis > 2) throw new IndexOutOfBoundsException("axis " + axis);
    return axis;
  }
}
