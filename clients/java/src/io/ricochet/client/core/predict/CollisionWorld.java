package io.ricochet.client.core.predict;

import com.google.protobuf.InvalidProtocolBufferException;
import io.ricochet.wire.WorldProto;

/**
 * A join reply's collision world (PROTOCOL.md The collision world, world.proto), parsed from its
 * untrusted bytes and checked as the protocol's table says; the shapes are kept as the physics
 * core keeps them (plane normals normalised, box rotations as matrices, triangles as corners), in
 * single precision. A world that breaks any rule is refused whole ({@link #refusal}), and a
 * client then does not predict. Immutable; built once per join.
 */
public final class CollisionWorld {
  static final int MAX_PLANES = 16;
  static final int MAX_BOXES = 1024;
  static final int MAX_MESHES = 64;
  static final int MAX_VERTICES = 65536;
  static final int MAX_TRIANGLES = 65536;
  static final float MAX_COORDINATE_M = 100000;
  static final float MAX_GRAVITY_MPS2 = 100;

  private final WorldRefusal refusal;
  /** Per plane: normal x, y, z (unit), offset. */
  final float[] planes;
  final int planeCount;
  /** Per box: centre (3), rotation matrix row-major (9), half extents (3). */
  final float[] boxes;
  final int boxCount;
  /** Per triangle: corners a, b, c (9 floats). */
  final float[] triangles;
  /** Per triangle: the index of its mesh. */
  final int[] triangleMesh;
  /** Per triangle: its index within its mesh. */
  final int[] triangleIndex;
  final int triangleCount;
  final int meshCount;
  final float radiusM;
  final float massKg;
  final float[] gravityMps2;
  final MovementRules movement;

  private CollisionWorld(WorldRefusal refusal) {
    this.refusal = refusal;
    planes = new float[0];
    planeCount = 0;
    boxes = new float[0];
    boxCount = 0;
    triangles = new float[0];
    triangleMesh = new int[0];
    triangleIndex = new int[0];
    triangleCount = 0;
    meshCount = 0;
    radiusM = 0;
    massKg = 0;
    gravityMps2 = new float[3];
    movement = null;
  }

  private CollisionWorld(WorldProto.CollisionWorld in, MovementRules movement, int triangleCount) {
    this.refusal = null;
    this.movement = movement;
    planeCount = in.getPlanesCount();
    planes = new float[4 * planeCount];
    for (int i = 0; i < planeCount; ++i) {
      WorldProto.CollisionPlane plane = in.getPlanes(i);
      float x = plane.getNormal(0), y = plane.getNormal(1), z = plane.getNormal(2);
      float norm = (float) Math.sqrt(x * x + (y * y + z * z));
      planes[4 * i] = x / norm;
      planes[4 * i + 1] = y / norm;
      planes[4 * i + 2] = z / norm;
      planes[4 * i + 3] = plane.getOffsetM();
    }
    boxCount = in.getBoxesCount();
    boxes = new float[15 * boxCount];
    for (int i = 0; i < boxCount; ++i) {
      WorldProto.CollisionBox box = in.getBoxes(i);
      float[] q = {box.getOrientation(0), box.getOrientation(1), box.getOrientation(2),
          box.getOrientation(3)};
      normalize(q); // the bot's build_prediction_world
      normalize(q); // World::add_box
      int at = 15 * i;
      for (int k = 0; k < 3; ++k) {
        boxes[at + k] = box.getCenterM(k);
        boxes[at + 12 + k] = box.getHalfExtentsM(k);
      }
      rotationMatrix(q, boxes, at + 3);
    }
    meshCount = in.getMeshesCount();
    this.triangleCount = triangleCount;
    triangles = new float[9 * triangleCount];
    triangleMesh = new int[triangleCount];
    triangleIndex = new int[triangleCount];
    int t = 0;
    for (int m = 0; m < meshCount; ++m) {
      WorldProto.CollisionMesh mesh = in.getMeshes(m);
      for (int k = 0; k < mesh.getIndicesCount() / 3; ++k, ++t) {
        triangleMesh[t] = m;
        triangleIndex[t] = k;
        for (int corner = 0; corner < 3; ++corner) {
          int vertex = mesh.getIndices(3 * k + corner);
          for (int axis = 0; axis < 3; ++axis) {
            triangles[9 * t + 3 * corner + axis] = mesh.getVerticesM(3 * vertex + axis);
          }
        }
      }
    }
    radiusM = in.getPlayerRadiusM();
    massKg = in.getPlayerMassKg();
    gravityMps2 = new float[] {in.getGravityMps2(0), in.getGravityMps2(1), in.getGravityMps2(2)};
  }

  /**
   * Parses and checks the join reply's {@code world} bytes (untrusted; null or empty: no world).
   * Never throws: a broken world comes back with {@link #refusal} set.
   */
  public static CollisionWorld parse(byte[] bytes) {
    if (bytes == null) return new CollisionWorld(WorldRefusal.MALFORMED);
    WorldProto.CollisionWorld in;
    try {
      in = WorldProto.CollisionWorld.parseFrom(bytes);
    } catch (InvalidProtocolBufferException e) {
      return new CollisionWorld(WorldRefusal.MALFORMED);
    }
    return check(in);
  }

  /** Checks a parsed CollisionWorld message as {@link #parse} does. */
  public static CollisionWorld check(WorldProto.CollisionWorld in) {
    if (!in.hasMovement()) return new CollisionWorld(WorldRefusal.BAD_MOVEMENT);
    MovementRules movement = MovementRules.from(in.getMovement());
    if (movement == null) return new CollisionWorld(WorldRefusal.BAD_MOVEMENT);
    if (!MovementRules.within(in.getPlayerRadiusM(), 0.05f, 5)
        || !MovementRules.within(in.getPlayerMassKg(), 1, 10000)) {
      return new CollisionWorld(WorldRefusal.BAD_BODY);
    }
    if (in.getGravityMps2Count() != 3 || !finiteWithin(in.getGravityMps2List(), MAX_GRAVITY_MPS2)
        || length(in.getGravityMps2(0), in.getGravityMps2(1), in.getGravityMps2(2))
            > MAX_GRAVITY_MPS2) {
      return new CollisionWorld(WorldRefusal.BAD_GRAVITY);
    }
    if (in.getPlanesCount() > MAX_PLANES || in.getBoxesCount() > MAX_BOXES
        || in.getMeshesCount() > MAX_MESHES) {
      return new CollisionWorld(WorldRefusal.TOO_MANY_SHAPES);
    }
    for (WorldProto.CollisionPlane plane : in.getPlanesList()) {
      if (plane.getNormalCount() != 3 || !finiteWithin(plane.getNormalList(), 1e6f)
          || length(plane.getNormal(0), plane.getNormal(1), plane.getNormal(2)) < 1e-3f
          || !MovementRules.within(plane.getOffsetM(), -MAX_COORDINATE_M, MAX_COORDINATE_M)) {
        return new CollisionWorld(WorldRefusal.BAD_PLANE);
      }
    }
    for (WorldProto.CollisionBox box : in.getBoxesList()) {
      if (!boxValid(box)) return new CollisionWorld(WorldRefusal.BAD_BOX);
    }
    long vertices = 0;
    long triangles = 0;
    for (WorldProto.CollisionMesh mesh : in.getMeshesList()) {
      int floats = mesh.getVerticesMCount();
      int indices = mesh.getIndicesCount();
      if (floats == 0 || floats % 3 != 0 || indices == 0 || indices % 3 != 0) {
        return new CollisionWorld(WorldRefusal.BAD_MESH);
      }
      vertices += floats / 3;
      triangles += indices / 3;
      if (vertices > MAX_VERTICES || triangles > MAX_TRIANGLES) {
        return new CollisionWorld(WorldRefusal.MESH_TOO_LARGE);
      }
      if (!finiteWithin(mesh.getVerticesMList(), MAX_COORDINATE_M)) {
        return new CollisionWorld(WorldRefusal.BAD_MESH);
      }
      for (int k = 0; k < indices; ++k) {
        if ((mesh.getIndices(k) & 0xFFFFFFFFL) >= floats / 3) {
          return new CollisionWorld(WorldRefusal.BAD_MESH);
        }
      }
    }
    return new CollisionWorld(in, movement, (int) triangles);
  }

  /** Null when usable; otherwise why the world was refused (and nothing is predicted). */
  public WorldRefusal refusal() {
    return refusal;
  }

  /** The players' sphere radius, m. */
  public float radiusM() {
    return radiusM;
  }

  /** The match's movement rules; null when refused. */
  public MovementRules movement() {
    return movement;
  }

  /** Planes, boxes and mesh triangles held. */
  public int shapeCount() {
    return planeCount + boxCount + triangleCount;
  }

  private static boolean boxValid(WorldProto.CollisionBox box) {
    if (box.getCenterMCount() != 3 || !finiteWithin(box.getCenterMList(), MAX_COORDINATE_M)) {
      return false;
    }
    if (box.getOrientationCount() != 4 || !finiteWithin(box.getOrientationList(), 1.01f)) {
      return false;
    }
    float[] q = {
        box.getOrientation(0), box.getOrientation(1), box.getOrientation(2), box.getOrientation(3)};
    if (Math.abs((float) Math.sqrt(squaredNorm4(q)) - 1) > 1e-3f) return false;
    if (box.getHalfExtentsMCount() != 3) return false;
    for (int k = 0; k < 3; ++k) {
      if (!MovementRules.within(box.getHalfExtentsM(k), 0.001f, MAX_COORDINATE_M)) return false;
    }
    return true;
  }

  private static boolean finiteWithin(java.util.List<Float> values, float limit) {
    for (int k = 0; k < values.size(); ++k) {
      float v = values.get(k);
      if (Float.isNaN(v) || Float.isInfinite(v) || Math.abs(v) > limit) return false;
    }
    return true;
  }

  private static float length(float x, float y, float z) {
    return (float) Math.sqrt(x * x + (y * y + z * z));
  }

  /** Eigen's Vector4f squared norm with SSE: (x² + z²) + (y² + w²). */
  private static float squaredNorm4(float[] q) {
    return (q[0] * q[0] + q[2] * q[2]) + (q[1] * q[1] + q[3] * q[3]);
  }

  private static void normalize(float[] q) {
    float norm = (float) Math.sqrt(squaredNorm4(q));
    for (int k = 0; k < 4; ++k) q[k] /= norm;
  }

  /** Eigen's Quaternion::toRotationMatrix, row-major into out[at, at + 9). */
  private static void rotationMatrix(float[] q, float[] out, int at) {
    float x = q[0], y = q[1], z = q[2], w = q[3];
    float tx = 2 * x, ty = 2 * y, tz = 2 * z;
    float twx = tx * w, twy = ty * w, twz = tz * w;
    float txx = tx * x, txy = ty * x, txz = tz * x;
    float tyy = ty * y, tyz = tz * y, tzz = tz * z;
    out[at] = 1 - (tyy + tzz);
    out[at + 1] = txy - twz;
    out[at + 2] = txz + twy;
    out[at + 3] = txy + twz;
    out[at + 4] = 1 - (txx + tzz);
    out[at + 5] = tyz - twx;
    out[at + 6] = txz - twy;
    out[at + 7] = tyz + twx;
    out[at + 8] = 1 - (txx + tyy);
  }
}
