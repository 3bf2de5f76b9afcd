package io.ricochet.client.core.predict;

import io.ricochet.wire.WorldProto;

/**
 * A match's movement rules (PROTOCOL.md Movement rules; the physics core's
 * CharacterMotionConfig), checked against the server's ranges. Immutable.
 */
public final class MovementRules {
  /** Wished speed at full input, m/s. */
  public final float maxSpeedMps;
  /** Ground acceleration, 1/s. */
  public final float groundAcceleration;
  /** Air acceleration (air control), 1/s. */
  public final float airAcceleration;
  /** Ground friction, 1/s. */
  public final float friction;
  /** Below this speed friction acts as if at it, m/s. */
  public final float stopSpeedMps;
  /** Vertical speed a jump sets, m/s. */
  public final float jumpSpeedMps;
  /** Steeper surfaces are walls, degrees. */
  public final float groundMaxSlopeDeg;
  /** How far below the sphere ground still counts, m. */
  public final float groundProbeM;

  /** The rules with these values (unchecked: see {@link #from}). */
  public MovementRules(float maxSpeedMps, float groundAcceleration, float airAcceleration,
      float friction, float stopSpeedMps, float jumpSpeedMps, float groundMaxSlopeDeg,
      float groundProbeM) {
    this.maxSpeedMps = maxSpeedMps;
    this.groundAcceleration = groundAcceleration;
    this.airAcceleration = airAcceleration;
    this.friction = friction;
    this.stopSpeedMps = stopSpeedMps;
    this.jumpSpeedMps = jumpSpeedMps;
    this.groundMaxSlopeDeg = groundMaxSlopeDeg;
    this.groundProbeM = groundProbeM;
  }

  /** The sample server's defaults (7 m/s, 10, 1, 6, 2 m/s, 5 m/s, 50°, 0.05 m). */
  public static MovementRules defaults() {
    return new MovementRules(7, 10, 1, 6, 2, 5, 50, 0.05f);
  }

  /** The wire's rules when every field is in the server's range; otherwise null. */
  public static MovementRules from(WorldProto.MovementRules in) {
    MovementRules rules = new MovementRules(in.getMaxSpeedMps(), in.getGroundAcceleration(),
        in.getAirAcceleration(), in.getFriction(), in.getStopSpeedMps(), in.getJumpSpeedMps(),
        in.getGroundMaxSlopeDeg(), in.getGroundProbeM());
    return rules.valid() ? rules : null;
  }

  /** Whether every field is within the server's range. */
  public boolean valid() {
    return within(maxSpeedMps, 0.1f, 100) && within(groundAcceleration, 0, 1000)
        && within(airAcceleration, 0, 1000) && within(friction, 0, 1000)
        && within(stopSpeedMps, 0, 100) && within(jumpSpeedMps, 0, 100)
        && within(groundMaxSlopeDeg, 0, 89) && within(groundProbeM, 0.001f, 1);
  }

  static boolean within(float value, float low, float high) {
    return !Float.isNaN(value) && !Float.isInfinite(value) && value >= low && value <= high;
  }
}
