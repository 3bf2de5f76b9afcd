package io.ricochet.client.core.predict;

import static org.junit.jupiter.api.Assertions.assertEquals;

import org.junit.jupiter.api.Test;

/** The movement rules of PROTOCOL.md with hand-computed numbers (the sample server's rules). */
class CharacterMotionTest {
  private static final MovementRules RULES = MovementRules.defaults();
  private static final float DT = 1f / 60;
  private static final float[] NO_WISH = {0, 0, 0, 0};

  @Test
  void frictionTakesSpeedTimesSixTimesDtOffTheHorizontalSpeed() {
    float[] v = {4, -1, 0};
    CharacterMotion.velocity(RULES, NO_WISH, false, true, 0.1f, v);
    // drop = max(4, 2) * 6 * 0.1 = 2.4: 4 -> 1.6; vertical untouched
    assertEquals(1.6f, v[0], 1e-6f);
    assertEquals(-1f, v[1], 0f);
  }

  @Test
  void belowTheStopSpeedFrictionActsAsAtTheStopSpeed() {
    float[] v = {0, 0, 1};
    CharacterMotion.velocity(RULES, NO_WISH, false, true, DT, v);
    assertEquals(1 - 2 * 6 * DT, v[2], 1e-6f); // 0.8
    float[] slow = {0, 0, 0.1f};
    CharacterMotion.velocity(RULES, NO_WISH, false, true, DT, slow);
    assertEquals(0f, slow[2], 0f); // stops, never reverses
  }

  @Test
  void groundAccelerationIsTenTimesTheWishedSpeedPerSecondTowardsTheWish() {
    float[] wish = new float[4];
    CharacterMotion.wish(0, 127, 0, wish); // full forward at yaw 0: along -Z
    assertEquals(0f, wish[0], 1e-7f);
    assertEquals(-1f, wish[2], 1e-7f);
    assertEquals(1f, wish[3], 0f);
    float[] v = {0, 0, 0};
    CharacterMotion.velocity(RULES, wish, false, true, DT, v);
    assertEquals(-10 * 7 * DT, v[2], 1e-6f); // 1.1667 m/s
    for (int i = 0; i < 600; ++i) CharacterMotion.velocity(RULES, wish, false, true, DT, v);
    // friction leaves 0.9 s, and 7 - 0.9 s <= 70 dt from s = 6.1 on: the wished 7 m/s is held
    assertEquals(0f, v[0], 1e-6f);
    assertEquals(-7f, v[2], 1e-5f);
  }

  @Test
  void strafingRightAtYawNinetyDegreesMovesAlongMinusZ() {
    float[] wish = new float[4];
    // yaw +90° (turned left): ahead is -X, right is -Z
    CharacterMotion.wish(127, 0, (float) (Math.PI / 2), wish);
    assertEquals(0f, wish[0], 1e-6f);
    assertEquals(-1f, wish[2], 1e-6f);
  }

  @Test
  void aFullDiagonalIsShortenedToFullSpeedAndHalfAStickIsHalfSpeed() {
    float[] wish = new float[4];
    CharacterMotion.wish(127, 127, 0, wish);
    assertEquals(1f, wish[3], 1e-6f);
    assertEquals(1f, (float) Math.sqrt(wish[0] * wish[0] + wish[2] * wish[2]), 1e-6f);
    CharacterMotion.wish(0, 64, 0, wish);
    assertEquals(64f / 127, wish[3], 1e-6f);
  }

  @Test
  void airControlIsOneTimesTheWishedSpeedPerSecondAndNoFriction() {
    float[] wish = new float[4];
    CharacterMotion.wish(0, 127, 0, wish);
    float[] v = {3, 0, 0};
    CharacterMotion.velocity(RULES, wish, false, false, DT, v);
    assertEquals(3f, v[0], 0f); // no friction in the air
    assertEquals(-7 * DT, v[2], 1e-6f);
  }

  @Test
  void aJumpSetsFiveMetresPerSecondOnlyOnTheGround() {
    float[] v = {0, -0.2f, 0};
    CharacterMotion.velocity(RULES, NO_WISH, true, true, DT, v);
    assertEquals(5f, v[1], 0f);
    float[] air = {0, -0.2f, 0};
    CharacterMotion.velocity(RULES, NO_WISH, true, false, DT, air);
    assertEquals(-0.2f, air[1], 0f);
    float[] rising = {0, 6, 0};
    CharacterMotion.velocity(RULES, NO_WISH, true, true, DT, rising);
    assertEquals(6f, rising[1], 0f); // never slows a faster rise
  }
}
