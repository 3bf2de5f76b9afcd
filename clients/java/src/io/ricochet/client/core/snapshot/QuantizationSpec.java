package io.ricochet.client.core.snapshot;

import io.ricochet.wire.SnapshotProto.Quantization;

/**
 * How a match quantises entity states for its snapshots (PROTOCOL.md, Snapshots §2;
 * proto/quantize.h): the map's bounds, the steps of position, velocity and orientation, and the
 * tick length that position prediction uses. The game layer reads it from {@code
 * JoinMatchReply.quantization} ({@link #fromWire}, untrusted) and hands it to a {@link
 * SnapshotDecoder}; {@link SnapshotView} turns the decoded integers back into metres with it.
 * Immutable.
 *
 * <p>Every check and derived integer is computed as the C++ end computes it: in IEEE double from
 * the float fields, the ranges compared on the floats.
 */
public final class QuantizationSpec {
  private static final double MAX_POSITION_STEPS = 2147483647.0;
  private static final double MAX_VELOCITY_STEPS = 1073741823.0;
  private static final long MAX_PREDICTION_SCALE = 1L << 23;
  private static final double SQRT2 = 1.4142135623730951;
  private static final String[] AXIS = {"x", "y", "z"};

  private final float[] boundsMinM;
  private final float[] boundsMaxM;
  private final float positionStepM;
  private final float velocityStepMps;
  private final float maxSpeedMps;
  private final int orientationBits;
  private final float tickS;

  // Derived once (PROTOCOL.md §2): steps and bits per axis, limits, the prediction scale.
  private final int[] positionSteps = new int[3];
  private final int[] positionBits = new int[3];
  private final int velocityLimit;
  private final int velocityBits;
  private final int orientationLimit;
  private final long predictionScale;
  private final double orientationScale;

  private QuantizationSpec(float[] boundsMinM, float[] boundsMaxM, float positionStepM,
      float velocityStepMps, float maxSpeedMps, int orientationBits, float tickS) {
    this.boundsMinM = boundsMinM.clone();
    this.boundsMaxM = boundsMaxM.clone();
    this.positionStepM = positionStepM;
    this.velocityStepMps = velocityStepMps;
    this.maxSpeedMps = maxSpeedMps;
    this.orientationBits = orientationBits;
    this.tickS = tickS;
    for (int a = 0; a < 3; ++a) {
      positionSteps[a] = (int) axisSpanSteps(a) + 1;
      positionBits[a] = bitsForCount(positionSteps[a]);
    }
    velocityLimit = (int) Math.floor((double) maxSpeedMps / velocityStepMps + 0.5);
    velocityBits = bitsForCount(2L * velocityLimit + 1);
    orientationLimit = (1 << (orientationBits - 1)) - 1;
    predictionScale =
        Math.round(65536.0 * (double) velocityStepMps * (double) tickS / (double) positionStepM);
    orientationScale = 1.0 / (SQRT2 * orientationLimit);
  }

  /**
   * The server's defaults: bounds (-64,-16,-64)..(64,48,64) m, 1 mm, 0.01 m/s, 64 m/s, 9, 60 Hz.
   */
  public static QuantizationSpec defaults() {
    return of(new float[] {-64f, -16f, -64f}, new float[] {64f, 48f, 64f}, 0.001f, 0.01f, 64f, 9,
        1.0f / 60);
  }

  /**
   * A spec from its fields (units in the names; bounds as x, y, z). For a spec the app builds
   * itself; throws IllegalArgumentException naming the first field out of range.
   */
  public static QuantizationSpec of(float[] boundsMinM, float[] boundsMaxM, float positionStepM,
      float velocityStepMps, float maxSpeedMps, int orientationBits, float tickS) {
    if (boundsMinM.length != 3 || boundsMaxM.length != 3) {
      throw new IllegalArgumentException("bounds must have 3 values each");
    }
    String problem = problem(boundsMinM, boundsMaxM, positionStepM, velocityStepMps, maxSpeedMps,
        orientationBits, tickS);
    if (!problem.isEmpty()) throw new IllegalArgumentException(problem);
    return new QuantizationSpec(boundsMinM, boundsMaxM, positionStepM, velocityStepMps, maxSpeedMps,
        orientationBits, tickS);
  }

  /**
   * The spec a JoinMatchReply carries (untrusted): null when it is unusable, for which {@link
   * #problemWith} says why. Called by the game layer once per join.
   */
  public static QuantizationSpec fromWire(Quantization in) {
    if (!problemWith(in).isEmpty()) return null;
    return new QuantizationSpec(minOf(in), maxOf(in), in.getPositionStepM(),
        in.getVelocityStepMps(), in.getMaxSpeedMps(), in.getOrientationBits(), in.getTickS());
  }

  /** Empty when {@link #fromWire} accepts {@code in}; otherwise the wrong field and its value. */
  public static String problemWith(Quantization in) {
    if (in.getBoundsMinMCount() != 3 || in.getBoundsMaxMCount() != 3) {
      return "quantization bounds must have 3 values each, got " + in.getBoundsMinMCount() + " and "
          + in.getBoundsMaxMCount();
    }
    long bits = in.getOrientationBits() & 0xFFFFFFFFL;
    if (bits > 16) return "quantization orientation_bits must be 4..16, got " + bits;
    return problem(minOf(in), maxOf(in), in.getPositionStepM(), in.getVelocityStepMps(),
        in.getMaxSpeedMps(), (int) bits, in.getTickS());
  }

  /** The spec as a JoinMatchReply carries it. */
  public Quantization toWire() {
    Quantization.Builder out = Quantization.newBuilder();
    for (int a = 0; a < 3; ++a) {
      out.addBoundsMinM(boundsMinM[a]);
      out.addBoundsMaxM(boundsMaxM[a]);
    }
    return out.setPositionStepM(positionStepM)
        .setVelocityStepMps(velocityStepMps)
        .setMaxSpeedMps(maxSpeedMps)
        .setOrientationBits(orientationBits)
        .setTickS(tickS)
        .build();
  }

  /** Number of position steps along {@code axis} (0 x, 1 y, 2 z): positions are 0..steps-1. */
  public int positionSteps(int axis) {
    return positionSteps[axis];
  }

  /** Largest velocity magnitude in steps: velocities lie in [-limit, limit]. */
  public int velocityLimit() {
    return velocityLimit;
  }

  /** Largest smallest-three component magnitude in steps: components lie in [-limit, limit]. */
  public int orientationLimit() {
    return orientationLimit;
  }

  /** Bits per smallest-three component, 4..16. */
  public int orientationBits() {
    return orientationBits;
  }

  /** m per position step. */
  public float positionStepM() {
    return positionStepM;
  }

  /** m/s per velocity step. */
  public float velocityStepMps() {
    return velocityStepMps;
  }

  /** s per server tick. */
  public float tickS() {
    return tickS;
  }

  /** The bounds' minimum along {@code axis}, m. */
  public float boundsMinM(int axis) {
    return boundsMinM[axis];
  }

  /** The bounds' maximum along {@code axis}, m. */
  public float boundsMaxM(int axis) {
    return boundsMaxM[axis];
  }

  /** Position {@code steps} (unsigned) along {@code axis} in m: min + steps * step. */
  public float positionM(int steps, int axis) {
    return (float) (boundsMinM[axis] + (double) (steps & 0xFFFFFFFFL) * positionStepM);
  }

  /** Velocity {@code steps} in m/s. */
  public float velocityMps(int steps) {
    return (float) ((double) steps * velocityStepMps);
  }

  /**
   * Rebuilds the unit quaternion of a smallest-three orientation into {@code xyzw} (4 floats,
   * x y z w) as proto::dequantize does, bit for bit; allocates nothing.
   */
  public void orientation(int largest, int c0, int c1, int c2, float[] xyzw) {
    int left = largest & 3;
    double q0 = 0, q1 = 0, q2 = 0, q3 = 0;
    double sumSquared = 0;
    int k = 0;
    for (int i = 0; i < 4; ++i) {
      if (i == left) continue;
      double q = (k == 0 ? c0 : k == 1 ? c1 : c2) * orientationScale;
      ++k;
      sumSquared += q * q;
      if (i == 0)
        q0 = q;
      else if (i == 1)
        q1 = q;
      else if (i == 2)
        q2 = q;
      else
        q3 = q;
    }
    double big = Math.sqrt(Math.max(0.0, 1.0 - sumSquared));
    if (left == 0)
      q0 = big;
    else if (left == 1)
      q1 = big;
    else if (left == 2)
      q2 = big;
    else
      q3 = big;
    double norm = 0;
    norm += q0 * q0;
    norm += q1 * q1;
    norm += q2 * q2;
    norm += q3 * q3;
    norm = Math.sqrt(norm);
    xyzw[0] = (float) (q0 / norm);
    xyzw[1] = (float) (q1 / norm);
    xyzw[2] = (float) (q2 / norm);
    xyzw[3] = (float) (q3 / norm);
  }

  int positionBits(int axis) {
    return positionBits[axis];
  }

  int velocityBits() {
    return velocityBits;
  }

  /** Position steps one velocity step covers in one tick, in 1/65536ths. */
  long predictionScale() {
    return predictionScale;
  }

  /** Bits needed to write any value in [0, count - 1]; 0 when count <= 1. */
  static int bitsForCount(long count) {
    int bits = 0;
    while (count > 1 && (1L << bits) < count) ++bits;
    return bits;
  }

  private double axisSpanSteps(int axis) {
    return axisSpanSteps(boundsMinM[axis], boundsMaxM[axis], positionStepM);
  }

  private static double axisSpanSteps(float minM, float maxM, float stepM) {
    double span = (double) maxM - minM;
    return Math.floor(span / stepM + 0.5);
  }

  private static float[] minOf(Quantization in) {
    return new float[] {in.getBoundsMinM(0), in.getBoundsMinM(1), in.getBoundsMinM(2)};
  }

  private static float[] maxOf(Quantization in) {
    return new float[] {in.getBoundsMaxM(0), in.getBoundsMaxM(1), in.getBoundsMaxM(2)};
  }

  /** proto::QuantizationSpec::validate(): empty, or the first wrong field. */
  private static String problem(float[] min, float[] max, float positionStepM,
      float velocityStepMps, float maxSpeedMps, int orientationBits, float tickS) {
    for (int a = 0; a < 3; ++a) {
      if (!Float.isFinite(min[a]) || !Float.isFinite(max[a]) || !(min[a] < max[a])) {
        return "bounds." + AXIS[a] + " must be finite with min_m < max_m, got " + min[a] + " .. "
            + max[a];
      }
    }
    if (!(positionStepM > 0 && positionStepM <= 0.001f)) {
      return "position_step_m must be in (0, 0.001] m, got " + positionStepM;
    }
    for (int a = 0; a < 3; ++a) {
      double steps = axisSpanSteps(min[a], max[a], positionStepM) + 1;
      if (steps > MAX_POSITION_STEPS) {
        return "bounds." + AXIS[a] + " span / position_step_m must be < 2^31 steps, got " + steps;
      }
    }
    if (!(velocityStepMps > 0) || !Float.isFinite(velocityStepMps)) {
      return "velocity_step_mps must be finite and > 0, got " + velocityStepMps;
    }
    if (!(maxSpeedMps >= velocityStepMps) || !Float.isFinite(maxSpeedMps)
        || (double) maxSpeedMps / velocityStepMps > MAX_VELOCITY_STEPS) {
      return "max_speed_mps must be finite, >= velocity_step_mps and < 2^30 steps, got "
          + maxSpeedMps;
    }
    if (orientationBits < 4 || orientationBits > 16) {
      return "orientation_bits must be 4..16, got " + orientationBits;
    }
    if (!(tickS > 0 && tickS <= 1)) return "tick_s must be in (0, 1] s, got " + tickS;
    long scale =
        Math.round(65536.0 * (double) velocityStepMps * (double) tickS / (double) positionStepM);
    if (scale > MAX_PREDICTION_SCALE) {
      return "velocity_step_mps * tick_s / position_step_m must be <= 128, got " + scale / 65536.0;
    }
    return "";
  }
}
