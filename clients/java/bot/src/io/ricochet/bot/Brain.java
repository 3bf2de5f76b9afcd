package io.ricochet.bot;

import io.ricochet.client.GameConnection;
import java.util.Random;

/**
 * One bot's behaviour, a decision per snapshot from what it sees ({@link Scene}): face the nearest
 * living other player within {@link #SIGHT_M}, aim at it with an error that shrinks with skill and
 * hold fire, strafing; with nobody in sight, wander between places players were seen at; jump now
 * and then, and when stuck. Sans-IO: time is a parameter and randomness comes from a seeded
 * generator, so a sequence of decisions is reproducible. Called on the bots' listener thread.
 */
final class Brain {
  /** Players farther than this are not chased, m. */
  static final double SIGHT_M = 60;
  /** Aim error at skill 0, rad (standard deviation per axis, as ricochet-bot's). */
  static final double MAX_AIM_ERROR_RAD = 0.25;
  /** A waypoint this near is reached, m (horizontally). */
  static final double REACHED_M = 1.5;
  /** Beyond this a target is walked towards, m; nearer, the bot only strafes. */
  static final double CLOSE_M = 6;
  /** Places remembered to wander between (the oldest forgotten first). */
  static final int PLACES = 32;
  /** Moving less than this in {@link #STUCK_CHECK_MS} while walking makes the bot jump, m. */
  static final double STUCK_M = 0.5;
  static final long STUCK_CHECK_MS = 1000;
  private static final long PLACE_SAMPLE_MS = 1000;
  private static final long WAYPOINT_MS = 6000;
  private static final long AIM_REDRAW_MS = 300;
  private static final double WANDER_RADIUS_M = 12;

  /** What to send: {@link GameConnection#setInput}'s arguments. */
  static final class Decision {
    float moveRight;
    float moveForward;
    float yawRad;
    float pitchRad;
    int buttons;

    /** Stand still, looking where it looked, no button. */
    void idle() {
      moveRight = 0;
      moveForward = 0;
      buttons = 0;
    }

    /** Whether {@code button} (a {@link GameConnection} BUTTON_ constant) is held. */
    boolean holds(int button) {
      return (buttons & button) != 0;
    }
  }

  private final double aimErrorRad;
  private final Random random;
  private final float[] places = new float[3 * PLACES];
  private int placeCount;
  private int nextPlace;
  private long nextPlaceSampleMs;
  private boolean hasWaypoint;
  private final float[] waypoint = new float[3];
  private long waypointUntilMs;
  private final float[] progressFrom = new float[3];
  private long progressCheckMs = -1;
  private long nextJumpMs = -1;
  private float yawError;
  private float pitchError;
  private long aimErrorUntilMs = -1;
  private float strafe = 1;
  private long strafeUntilMs;
  private long target;

  /** {@code skill} 0..1 (1 aims exactly); {@code seed}: the behaviour's random numbers. */
  Brain(double skill, long seed) {
    if (!(skill >= 0 && skill <= 1)) throw new IllegalArgumentException("skill 0..1: " + skill);
    aimErrorRad = MAX_AIM_ERROR_RAD * (1 - skill);
    random = new Random(seed);
  }

  /** The entity aimed at by the newest decision; 0 when none. */
  long target() {
    return target;
  }

  /** Places remembered so far (at most {@link #PLACES}). */
  int places() {
    return placeCount;
  }

  /** Decides into {@code out} what to do now ({@code nowMs}: the bot's clock, ms). */
  void decide(Scene scene, long nowMs, Decision out) {
    target = 0;
    rememberPlaces(scene, nowMs);
    int self = scene.indexOf(scene.ownId());
    if (!scene.ownAlive() || self < 0) {
      out.idle();
      hasWaypoint = false;
      progressCheckMs = -1;
      return;
    }
    float x = scene.positionM(self, 0);
    float y = scene.positionM(self, 1);
    float z = scene.positionM(self, 2);
    int enemy = nearestLivingOther(scene, self);
    out.buttons = 0;
    if (enemy >= 0) {
      target = scene.id(enemy);
      if (nowMs >= aimErrorUntilMs) {
        yawError = (float) (random.nextGaussian() * aimErrorRad);
        pitchError = (float) (random.nextGaussian() * aimErrorRad);
        aimErrorUntilMs = nowMs + AIM_REDRAW_MS;
      }
      float dx = scene.positionM(enemy, 0) - x;
      float dy = scene.positionM(enemy, 1) - y;
      float dz = scene.positionM(enemy, 2) - z;
      double horizontal = Math.sqrt(dx * dx + dz * dz);
      out.yawRad = wrap(yawTowards(dx, dz) + yawError);
      out.pitchRad = clampPitch((float) Math.atan2(dy, horizontal) + pitchError);
      out.buttons |= GameConnection.BUTTON_FIRE;
      if (nowMs >= strafeUntilMs) {
        strafe = random.nextBoolean() ? 1 : -1;
        strafeUntilMs = nowMs + 700 + random.nextInt(800);
      }
      out.moveRight = strafe;
      out.moveForward = horizontal > CLOSE_M ? 1 : 0;
    } else {
      if (!hasWaypoint || nowMs >= waypointUntilMs
          || horizontalDistance(x, z, waypoint[0], waypoint[2]) < REACHED_M) {
        pickWaypoint(x, y, z, nowMs);
      }
      out.yawRad = wrap(yawTowards(waypoint[0] - x, waypoint[2] - z));
      out.pitchRad = 0;
      out.moveRight = 0;
      out.moveForward = 1;
    }
    if (nextJumpMs < 0) nextJumpMs = nowMs + 2000 + random.nextInt(4000);
    boolean stuck = false;
    if (progressCheckMs < 0) {
      startProgressCheck(x, y, z, nowMs);
    } else if (nowMs >= progressCheckMs) {
      stuck = out.moveForward != 0
          && horizontalDistance(x, z, progressFrom[0], progressFrom[2]) < STUCK_M;
      startProgressCheck(x, y, z, nowMs);
    }
    if (stuck || nowMs >= nextJumpMs) {
      out.buttons |= GameConnection.BUTTON_JUMP;
      nextJumpMs = nowMs + 2000 + random.nextInt(4000);
      if (stuck) hasWaypoint = false; // and try another way
    }
  }

  private void startProgressCheck(float x, float y, float z, long nowMs) {
    progressFrom[0] = x;
    progressFrom[1] = y;
    progressFrom[2] = z;
    progressCheckMs = nowMs + STUCK_CHECK_MS;
  }

  /** Every second, where each living player stands: places worth wandering to (spawns, paths). */
  private void rememberPlaces(Scene scene, long nowMs) {
    if (nowMs < nextPlaceSampleMs) return;
    nextPlaceSampleMs = nowMs + PLACE_SAMPLE_MS;
    for (int i = 0; i < scene.count(); ++i) {
      if (!scene.living(i)) continue;
      for (int a = 0; a < 3; ++a) places[3 * nextPlace + a] = scene.positionM(i, a);
      nextPlace = (nextPlace + 1) % PLACES;
      if (placeCount < PLACES) ++placeCount;
    }
  }

  /** A remembered place away from here, or a point around here when none is. */
  private void pickWaypoint(float x, float y, float z, long nowMs) {
    hasWaypoint = true;
    waypointUntilMs = nowMs + WAYPOINT_MS;
    if (placeCount > 0) {
      int first = random.nextInt(placeCount);
      for (int k = 0; k < placeCount; ++k) {
        int i = (first + k) % placeCount;
        if (horizontalDistance(x, z, places[3 * i], places[3 * i + 2]) >= 2 * REACHED_M) {
          System.arraycopy(places, 3 * i, waypoint, 0, 3);
          return;
        }
      }
    }
    double angle = random.nextDouble() * 2 * Math.PI;
    waypoint[0] = x + (float) (WANDER_RADIUS_M * Math.sin(angle));
    waypoint[1] = y;
    waypoint[2] = z + (float) (WANDER_RADIUS_M * Math.cos(angle));
  }

  private static int nearestLivingOther(Scene scene, int self) {
    int best = -1;
    double bestM = SIGHT_M;
    for (int i = 0; i < scene.count(); ++i) {
      if (i == self || !scene.living(i)) continue;
      double d = 0;
      for (int a = 0; a < 3; ++a) {
        double delta = scene.positionM(i, a) - scene.positionM(self, a);
        d += delta * delta;
      }
      d = Math.sqrt(d);
      if (d < bestM) {
        bestM = d;
        best = i;
      }
    }
    return best;
  }

  /** The yaw that looks along (dx, dz): yaw 0 looks along -Z and positive turns left. */
  static float yawTowards(double dx, double dz) {
    return (float) Math.atan2(-dx, -dz);
  }

  private static float wrap(float yaw) {
    double wrapped = yaw;
    while (wrapped > Math.PI) wrapped -= 2 * Math.PI;
    while (wrapped < -Math.PI) wrapped += 2 * Math.PI;
    return (float) wrapped;
  }

  private static float clampPitch(float pitch) {
    float limit = (float) (Math.PI / 2) - 0.01f;
    return Math.max(-limit, Math.min(limit, pitch));
  }

  private static double horizontalDistance(float x0, float z0, float x1, float z1) {
    double dx = x1 - x0;
    double dz = z1 - z0;
    return Math.sqrt(dx * dx + dz * dz);
  }
}
