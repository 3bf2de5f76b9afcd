package io.ricochet.client.core.snapshot;

/**
 * The game's bits of a snapshot entity's 8-bit flags (PROTOCOL.md, "Entities in snapshots";
 * proto/entity_flags.h). The snapshot codec carries them opaquely; an app reads them from {@link
 * SnapshotView#flags} with these names.
 */
public final class EntityFlags {
  /** A player standing on something (it can jump). */
  public static final int GROUNDED = 1;
  /** Its player is away, within the reconnect grace. */
  public static final int DISCONNECTED = 1 << 1;
  /** A player waiting to respawn (not hittable, not moving). */
  public static final int DEAD = 1 << 4;
  /** A player under spawn protection. */
  public static final int PROTECTED = 1 << 5;

  /** Kind (bits 2..3): a player. */
  public static final int KIND_PLAYER = 0;
  /** Kind (bits 2..3): a rocket. */
  public static final int KIND_ROCKET = 1;
  /** Kind (bits 2..3): a grenade. */
  public static final int KIND_GRENADE = 2;
  /** Kind (bits 2..3): the unassigned value; an entity of another build's kind. */
  public static final int KIND_UNKNOWN = 3;

  private static final int KIND_SHIFT = 2;

  private EntityFlags() {}

  /** The kind bits 2..3 of {@code flags}: one of the {@code KIND_} constants. */
  public static int kind(int flags) {
    return (flags >>> KIND_SHIFT) & 3;
  }

  /** True when every bit of {@code flag} is set in {@code flags}. */
  public static boolean has(int flags, int flag) {
    return (flags & flag) == flag;
  }
}
