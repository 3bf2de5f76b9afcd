package io.ricochet.client.core.predict;

/**
 * The movement rules of PROTOCOL.md (the physics core's character_motion.cpp and the server's
 * conversion of an Input, proto's stick_of), in single precision with the C++ operations in the
 * same order (Eigen's x + (y + z) for dot products and norms), so a prediction matches the
 * server's bits. Stateless; vectors are float[3] (x, y, z) written in place; nothing is
 * allocated.
 */
public final class CharacterMotion {
  /** Steps of a full move along one axis of an Input. */
  public static final int MOVE_STEPS = 127;

  private static final float PI = (float) Math.PI;

  private CharacterMotion() {}

  /**
   * The wish of one Input into {@code wish} = (direction x, y, z, speed fraction 0..1): the stick
   * (move_right, move_forward) / 127, shortened to length 1, seen from {@code yawRad}.
   */
  public static void wish(int moveRight, int moveForward, float yawRad, float[] wish) {
    float right = (float) moveRight / MOVE_STEPS;
    float forward = (float) moveForward / MOVE_STEPS;
    float lengthSq = right * right + forward * forward;
    if (lengthSq > 1) {
      float length = (float) Math.sqrt(lengthSq);
      right /= length;
      forward /= length;
    }
    float sinYaw = (float) Math.sin(yawRad);
    float cosYaw = (float) Math.cos(yawRad);
    // ahead (-sin, 0, -cos) * forward + side (cos, 0, -sin) * right
    float x = -sinYaw * forward + cosYaw * right;
    float y = 0f * forward + 0f * right;
    float z = -cosYaw * forward + -sinYaw * right;
    float length = (float) Math.sqrt(x * x + (y * y + z * z));
    if (length > 1e-6f) {
      wish[0] = x / length;
      wish[1] = y / length;
      wish[2] = z / length;
    } else {
      wish[0] = 0;
      wish[1] = 0;
      wish[2] = 0;
    }
    wish[3] = Math.min(1.0f, hypot(right, forward));
  }

  /**
   * The velocity for the next step ({@code velocity} in and out, m/s) from the wish of {@link
   * #wish} and whether the sphere is grounded; {@code jump} held. {@code dtS} the tick, s.
   */
  public static void velocity(MovementRules rules, float[] wish, boolean jump, boolean grounded,
      float dtS, float[] velocity) {
    float wishSpeed = rules.maxSpeedMps * wish[3];
    if (grounded) {
      applyFriction(rules, dtS, velocity);
      accelerate(velocity, wish, wishSpeed, rules.groundAcceleration, dtS);
      if (jump && velocity[1] < rules.jumpSpeedMps) velocity[1] = rules.jumpSpeedMps;
    } else {
      accelerate(velocity, wish, wishSpeed, rules.airAcceleration, dtS);
    }
  }

  /** The least normal y of a surface that counts as ground: cos(max slope). */
  public static float minGroundNormalY(MovementRules rules) {
    return (float) Math.cos(rules.groundMaxSlopeDeg * PI / 180);
  }

  private static void accelerate(
      float[] v, float[] direction, float wishSpeed, float acceleration, float dtS) {
    float along = v[0] * direction[0] + (v[1] * direction[1] + v[2] * direction[2]);
    float missing = wishSpeed - along;
    if (missing <= 0) return;
    float gain = Math.min(acceleration * wishSpeed * dtS, missing);
    v[0] = v[0] + gain * direction[0];
    v[1] = v[1] + gain * direction[1];
    v[2] = v[2] + gain * direction[2];
  }

  private static void applyFriction(MovementRules rules, float dtS, float[] v) {
    float speed = hypot(v[0], v[2]);
    if (speed <= 0) return;
    float drop = Math.max(speed, rules.stopSpeedMps) * rules.friction * dtS;
    float scale = Math.max(speed - drop, 0f) / speed;
    v[0] = v[0] * scale;
    v[2] = v[2] * scale;
  }

  /** glibc's hypotf: the double square root of the double sum, rounded once. */
  static float hypot(float a, float b) {
    return (float) Math.sqrt((double) a * a + (double) b * b);
  }
}
