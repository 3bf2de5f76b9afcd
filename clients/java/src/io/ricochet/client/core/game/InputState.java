package io.ricochet.client.core.game;

/**
 * One tick's controls in the wire's ranges (PROTOCOL.md Input): the move stick quantised to
 * -127..127 per axis, yaw in [-π, π], pitch in [-π/2, π/2], button bits 0..2, weapon slot 0..9.
 * {@link #set} checks and converts what an app gives. Mutable, not thread-safe: the game
 * connection guards the one the app writes and copies it for its I/O thread.
 */
public final class InputState {
  /** Button bit: jump. */
  public static final int BUTTON_JUMP = 1;
  /** Button bit: fire. */
  public static final int BUTTON_FIRE = 1 << 1;
  /** Button bit: alternative fire. */
  public static final int BUTTON_ALT_FIRE = 1 << 2;
  /** Every button bit the protocol defines. */
  public static final int BUTTONS = BUTTON_JUMP | BUTTON_FIRE | BUTTON_ALT_FIRE;
  /** Steps of a full move along one axis. */
  public static final int MOVE_STEPS = 127;
  /** Highest weapon slot (0 keeps the weapon, 1 rifle, 2 rockets, 3 grenades). */
  public static final int MAX_WEAPON_SLOT = 9;

  private static final double TWO_PI = 2 * Math.PI;
  private static final float HALF_PI = (float) (Math.PI / 2);

  private int moveRight;
  private int moveForward;
  private float yaw;
  private float pitch;
  private int buttons;
  private int weaponSlot;

  /**
   * Sets the controls: {@code moveRight} and {@code moveForward} -1..1 (full stick; larger values
   * are clamped), {@code yawRad} any finite angle (wrapped into [-π, π]; 0 looks along -Z, positive
   * turns left), {@code pitchRad} finite (clamped to ±π/2; positive looks up), {@code buttons}
   * {@link #BUTTON_JUMP} | {@link #BUTTON_FIRE} | {@link #BUTTON_ALT_FIRE}, {@code weaponSlot}
   * 0..9. Throws IllegalArgumentException for a non-finite number, another button bit or slot.
   */
  public void set(float moveRight, float moveForward, float yawRad, float pitchRad, int buttons,
      int weaponSlot) {
    if (!finite(moveRight) || !finite(moveForward) || !finite(yawRad) || !finite(pitchRad)) {
      throw new IllegalArgumentException("input values must be finite");
    }
    if ((buttons & ~BUTTONS) != 0) {
      throw new IllegalArgumentException("unknown button bits " + Integer.toHexString(buttons));
    }
    if (weaponSlot < 0 || weaponSlot > MAX_WEAPON_SLOT) {
      throw new IllegalArgumentException("weapon slot must be 0..9, got " + weaponSlot);
    }
    this.moveRight = steps(moveRight);
    this.moveForward = steps(moveForward);
    this.yaw = wrap(yawRad);
    this.pitch = Math.max(-HALF_PI, Math.min(HALF_PI, pitchRad));
    this.buttons = buttons;
    this.weaponSlot = weaponSlot;
  }

  /** Makes this a copy of {@code other}. */
  public void copyFrom(InputState other) {
    moveRight = other.moveRight;
    moveForward = other.moveForward;
    yaw = other.yaw;
    pitch = other.pitch;
    buttons = other.buttons;
    weaponSlot = other.weaponSlot;
  }

  /** Strafe, -127..127; positive is right. */
  public int moveRight() {
    return moveRight;
  }

  /** Forward, -127..127; positive is forward. */
  public int moveForward() {
    return moveForward;
  }

  /** View yaw, rad, in [-π, π]. */
  public float yaw() {
    return yaw;
  }

  /** View pitch, rad, in [-π/2, π/2]. */
  public float pitch() {
    return pitch;
  }

  /** Held button bits. */
  public int buttons() {
    return buttons;
  }

  /** Weapon slot, 0..9. */
  public int weaponSlot() {
    return weaponSlot;
  }

  private static boolean finite(float value) {
    return !Float.isNaN(value) && !Float.isInfinite(value);
  }

  private static int steps(float move) {
    float clamped = Math.max(-1f, Math.min(1f, move));
    return Math.round(clamped * MOVE_STEPS);
  }

  private static float wrap(float yawRad) {
    if (yawRad >= -Math.PI && yawRad <= Math.PI) return yawRad;
    double wrapped = Math.IEEEremainder(yawRad, TWO_PI); // in [-π, π]
    return (float) Math.max(-Math.PI, Math.min(Math.PI, wrapped));
  }
}
