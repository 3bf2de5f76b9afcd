package io.ricochet.client.core.game;

/**
 * The own player's status of a ServerPayload ({@code PlayerStatus} in game.proto), reusable: the
 * payload reader fills one per payload, and a {@link #copyFrom} keeps it past the payload without
 * allocating.
 */
public final class PlayerStatus {
  /** {@code ammo} counts kept at most (one per weapon: 3 today); more are skipped. */
  public static final int MAX_AMMO = 16;

  private boolean present;
  private int health;
  private int armor;
  private int weapon;
  private final int[] ammo = new int[MAX_AMMO];
  private int ammoCount;
  private boolean alive;
  private long respawnTick;
  private long protectedUntilTick;
  private int team;

  /** Whether the payload carried a status (field 5); the rest is 0 or false when not. */
  public boolean present() {
    return present;
  }

  /** {@code health}, 0..100 from a well-behaved server. */
  public int health() {
    return health;
  }

  /** {@code armor}, 0..100 from a well-behaved server. */
  public int armor() {
    return armor;
  }

  /** {@code weapon}: a {@code Weapon} number (1 rifle, 2 rocket launcher, 3 grenade launcher). */
  public int weapon() {
    return weapon;
  }

  /** How many {@code ammo} counts were kept (at most {@link #MAX_AMMO}). */
  public int ammoCount() {
    return ammoCount;
  }

  /** {@code ammo[index]}: the ammunition of weapon {@code index + 1}. */
  public int ammo(int index) {
    if (index < 0 || index >= ammoCount) {
      throw new IndexOutOfBoundsException("ammo " + index + " of " + ammoCount);
    }
    return ammo[index];
  }

  /** {@code alive}. */
  public boolean alive() {
    return alive;
  }

  /** {@code respawn_tick} (while dead), unsigned 32-bit. */
  public long respawnTick() {
    return respawnTick;
  }

  /** {@code protected_until_tick}: spawn protection lasts until this tick, unsigned 32-bit. */
  public long protectedUntilTick() {
    return protectedUntilTick;
  }

  /** {@code team}: a {@code Team} number (0 none, 1 red, 2 blue). */
  public int team() {
    return team;
  }

  /** Makes this a copy of {@code other}. */
  public void copyFrom(PlayerStatus other) {
    present = other.present;
    health = other.health;
    armor = other.armor;
    weapon = other.weapon;
    ammoCount = other.ammoCount;
    System.arraycopy(other.ammo, 0, ammo, 0, ammoCount);
    alive = other.alive;
    respawnTick = other.respawnTick;
    protectedUntilTick = other.protectedUntilTick;
    team = other.team;
  }

  void clear() {
    present = false;
    health = 0;
    armor = 0;
    weapon = 0;
    ammoCount = 0;
    alive = false;
    respawnTick = 0;
    protectedUntilTick = 0;
    team = 0;
  }

  void setPresent() {
    present = true;
  }

  void setHealth(int value) {
    health = value;
  }

  void setArmor(int value) {
    armor = value;
  }

  void setWeapon(int value) {
    weapon = value;
  }

  void addAmmo(int count) {
    if (ammoCount < MAX_AMMO) ammo[ammoCount++] = count;
  }

  void setAlive(boolean value) {
    alive = value;
  }

  void setRespawnTick(long value) {
    respawnTick = value;
  }

  void setProtectedUntilTick(long value) {
    protectedUntilTick = value;
  }

  void setTeam(int value) {
    team = value;
  }
}
