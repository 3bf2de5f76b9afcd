package io.ricochet.bot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertNotEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.GameConnection;
import org.junit.jupiter.api.Test;

/** The Java bot's behaviour, sans-IO: scenes in, decisions out, fake time. */
class BrainTest {
  private static final float EPSILON = 1e-5f;

  /** Where a yaw looks, on the ground: (x, z) of PROTOCOL.md's convention (0 along -Z). */
  private static double[] forward(float yaw) {
    return new double[] {-Math.sin(yaw), -Math.cos(yaw)};
  }

  @Test
  void aimsAtTheNearestLivingOtherPlayerAndFires() {
    Brain brain = new Brain(1, 7); // skill 1: no aim error
    Scene scene = new Scene();
    scene.clear(1, true);
    scene.addPlayer(1, 0, 1, 0, true);
    scene.addPlayer(2, 3, 1, 0, false); // dead: not a target
    scene.addPlayer(3, 0, 1, 20, true); // farther
    scene.addPlayer(4, -8, 3, 0, true); // the nearest living one, 2 m higher
    Brain.Decision decision = new Brain.Decision();
    brain.decide(scene, 1000, decision);
    assertEquals(4, brain.target());
    assertTrue(decision.holds(GameConnection.BUTTON_FIRE));
    double[] looking = forward(decision.yawRad);
    assertEquals(-1, looking[0], 1e-5);
    assertEquals(0, looking[1], 1e-5);
    assertEquals(Math.atan2(2, 8), decision.pitchRad, 1e-5);
    assertEquals(1, decision.moveForward, EPSILON, "8 m away: it closes in");
    assertEquals(1, Math.abs(decision.moveRight), EPSILON, "and strafes");
  }

  @Test
  void aTargetNearerThanCloseRangeIsStrafedNotApproached() {
    Brain brain = new Brain(1, 7);
    Scene scene = new Scene();
    scene.clear(1, true);
    scene.addPlayer(1, 0, 1, 0, true);
    scene.addPlayer(2, 0, 1, -3, true);
    Brain.Decision decision = new Brain.Decision();
    brain.decide(scene, 0, decision);
    assertEquals(2, brain.target());
    assertEquals(0, decision.yawRad, 1e-5, "straight along -Z");
    assertEquals(0, decision.moveForward, EPSILON);
  }

  @Test
  void aimErrorShrinksWithSkill() {
    Scene scene = new Scene();
    scene.clear(1, true);
    scene.addPlayer(1, 0, 1, 0, true);
    scene.addPlayer(2, 0, 1, -10, true);
    double unskilled = meanAbsoluteYawError(new Brain(0, 3), scene);
    double skilled = meanAbsoluteYawError(new Brain(0.8, 3), scene);
    // Gaussian of sd 0.25 rad: the mean absolute error is 0.25 * sqrt(2/pi) = 0.2 rad.
    assertTrue(unskilled > 0.15 && unskilled < 0.25, "skill 0: " + unskilled);
    assertTrue(skilled < unskilled / 3, "skill 0.8: " + skilled + ", skill 0: " + unskilled);
    assertEquals(0, meanAbsoluteYawError(new Brain(1, 3), scene), 1e-6);
  }

  private static double meanAbsoluteYawError(Brain brain, Scene scene) {
    Brain.Decision decision = new Brain.Decision();
    double sum = 0;
    int draws = 400;
    for (int i = 0; i < draws; ++i) {
      brain.decide(scene, i * 1000L, decision); // a new error every 300 ms: one per decision
      sum += Math.abs(decision.yawRad);
    }
    return sum / draws;
  }

  @Test
  void aloneItWandersToRememberedPlacesAndPicksAnotherOnArrival() {
    Brain brain = new Brain(1, 11);
    Scene scene = new Scene();
    // Another player seen once, far away: a place worth going to, then it leaves.
    scene.clear(1, true);
    scene.addPlayer(1, 0, 1, 0, true);
    scene.addPlayer(2, 100, 1, 0, true);
    Brain.Decision decision = new Brain.Decision();
    brain.decide(scene, 0, decision);
    assertEquals(2, brain.places());
    scene.clear(1, true);
    scene.addPlayer(1, 0, 1, 0, true);
    brain.decide(scene, 10, decision);
    assertEquals(0, brain.target());
    assertFalse(decision.holds(GameConnection.BUTTON_FIRE));
    assertEquals(1, decision.moveForward, EPSILON);
    double[] looking = forward(decision.yawRad);
    assertEquals(1, looking[0], 1e-5, "towards x = 100, the only place away from here");
    // Arrived there: the next waypoint is elsewhere (the start, the only other place).
    scene.clear(1, true);
    scene.addPlayer(1, 99.5f, 1, 0, true);
    brain.decide(scene, 20, decision);
    looking = forward(decision.yawRad);
    assertEquals(-1, looking[0], 1e-3);
  }

  @Test
  void jumpsWhenItWalksWithoutMovingAndNowAndThen() {
    Brain brain = new Brain(1, 5);
    Scene scene = new Scene();
    scene.clear(1, true);
    scene.addPlayer(1, 0, 1, 0, true);
    Brain.Decision decision = new Brain.Decision();
    brain.decide(scene, 0, decision);
    assertFalse(decision.holds(GameConnection.BUTTON_JUMP));
    // Walking into a wall: a second later it has not moved, so it jumps.
    brain.decide(scene, Brain.STUCK_CHECK_MS, decision);
    assertTrue(decision.holds(GameConnection.BUTTON_JUMP), "stuck");
    brain.decide(scene, Brain.STUCK_CHECK_MS + 16, decision);
    assertFalse(decision.holds(GameConnection.BUTTON_JUMP), "one press, then released");
    // Moving freely it still jumps now and then: within 6 s, at least once, not every tick.
    int jumps = 0;
    float x = 0;
    for (long now = 3000; now < 15000; now += 16) {
      x += 0.12f;
      scene.clear(1, true);
      scene.addPlayer(1, x, 1, 0, true);
      brain.decide(scene, now, decision);
      if (decision.holds(GameConnection.BUTTON_JUMP)) ++jumps;
    }
    assertTrue(jumps >= 2 && jumps <= 6, "jumps in 12 s: " + jumps);
  }

  @Test
  void deadOrAbsentItStandsStill() {
    Brain brain = new Brain(1, 5);
    Scene scene = new Scene();
    scene.clear(1, false);
    scene.addPlayer(1, 0, 1, 0, false);
    scene.addPlayer(2, 0, 1, -5, true);
    Brain.Decision decision = new Brain.Decision();
    decision.buttons = GameConnection.BUTTON_FIRE;
    decision.moveForward = 1;
    brain.decide(scene, 0, decision);
    assertEquals(0, decision.buttons);
    assertEquals(0, decision.moveForward, EPSILON);
    assertEquals(0, brain.target());
    scene.clear(9, true); // its entity is not in the snapshot
    scene.addPlayer(2, 0, 1, -5, true);
    brain.decide(scene, 100, decision);
    assertEquals(0, brain.target());
  }

  @Test
  void theSameSeedDecidesTheSameAndAnotherDiffers() {
    float[] first = run(new Brain(0.3, 42));
    float[] again = run(new Brain(0.3, 42));
    float[] other = run(new Brain(0.3, 43));
    assertEquals(java.util.Arrays.toString(first), java.util.Arrays.toString(again));
    assertNotEquals(java.util.Arrays.toString(first), java.util.Arrays.toString(other));
  }

  private static float[] run(Brain brain) {
    Scene scene = new Scene();
    Brain.Decision decision = new Brain.Decision();
    float[] yaws = new float[50];
    for (int i = 0; i < yaws.length; ++i) {
      scene.clear(1, true);
      scene.addPlayer(1, i * 0.1f, 1, 0, true);
      scene.addPlayer(2, 5, 1, 5 - i * 0.2f, true);
      brain.decide(scene, i * 100L, decision);
      yaws[i] = decision.yawRad + decision.moveRight;
    }
    return yaws;
  }
}
