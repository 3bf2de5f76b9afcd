package io.ricochet.client.core.predict;

/**
 * The prediction world of one player's sphere against a {@link CollisionWorld}'s static shapes:
 * what one step of the physics core's World does to a locked-rotation, frictionless sphere under
 * profiles::arena_players() (1 substep, 4 velocity iterations, Baumgarte correction, warm
 * starting, no restitution for a player), in single precision with the C++ operations in their
 * order: speculative contacts with planes, oriented boxes and two-sided triangles (the mesh's
 * internal-edge filter included), gravity by semi-implicit Euler, sequential impulses along the
 * contact normals, then the move. The ground test is the core's is_grounded: a sphere 2 cm
 * smaller swept down by 2 cm + the probe. Three-term sums that are Eigen reductions in the C++
 * (dot products, norms, matrix times vector) add as x + (y + z), Eigen's order; the solver's
 * normal velocity, written out in the C++, adds left to right.
 *
 * <p>Sans-IO and allocation-free once warm (contact arrays grow to the most contacts seen). Not
 * thread-safe. What differs from the C++: primitives are visited in their map order rather than
 * the C++ bounding-volume tree's order, which changes the solving order only where the sphere
 * touches several boxes or triangles at once.
 */
public final class SphereWorld {
  private static final float LINEAR_SLOP = 0.005f;
  private static final float BAUMGARTE = 0.2f;
  private static final float MAX_CORRECTION_SPEED = 4;
  private static final float MAX_SPECULATIVE_DISTANCE = 0.25f;
  private static final float MAX_LINEAR_SPEED = 10000;
  private static final int ITERATIONS = 4;

  private final CollisionWorld world;
  private final float radius;
  private final float inverseMass;
  private final float normalMass;
  private final float minGroundNormalY;
  /** Position, m, and velocity, m/s. */
  private final float[] position = new float[3];
  private final float[] velocity = new float[3];

  // This step's contacts and last step's (for warm starting), by key.
  private long[] keys = new long[8];
  private float[] normals = new float[24];
  private float[] separations = new float[8];
  private float[] impulses = new float[8];
  private int count;
  private long[] previousKeys = new long[8];
  private float[] previousImpulses = new float[8];
  private int previousCount;
  // Mesh hits of this step: primitive, on-face flag and closest point, before the edge filter.
  private int[] meshHitTriangle = new int[8];
  private boolean[] meshHitOnFace = new boolean[8];
  private float[] meshHitFeature = new float[56]; // point (3), normal (3), distance
  private int meshHits;

  private final float[] feature = new float[7]; // point (3), normal (3), distance
  // Scratch vectors of the contact and sweep tests (nothing allocated per step).
  private final float[] clamped = new float[3];
  private final float[] faceNormal = new float[3];
  private final float[] surface = new float[3];
  private final float[] castOrigin = new float[3];
  private final float[] castPath = new float[3];
  private final float[] hitNormal = new float[3];
  private final float[] edgeStart = new float[3];
  private final float[] edgeEnd = new float[3];
  private final float[] cornerA = new float[3];
  private final float[] cornerB = new float[3];
  private final float[] cornerC = new float[3];
  private final float[] scratch = new float[12];
  private float sweepT;
  private final float[] sweepNormal = new float[3];

  /** A world for {@code world} (not refused), the sphere at the origin, at rest. */
  public SphereWorld(CollisionWorld world) {
    if (world.refusal() != null) throw new IllegalArgumentException("refused collision world");
    this.world = world;
    this.radius = world.radiusM;
    this.inverseMass = 1 / world.massKg;
    this.normalMass = 1 / (inverseMass + 0f);
    this.minGroundNormalY = CharacterMotion.minGroundNormalY(world.movement);
  }

  /** Moves the sphere to {@code positionM} with {@code velocityMps} (each float[3]). */
  public void seed(float[] positionM, float[] velocityMps) {
    System.arraycopy(positionM, 0, position, 0, 3);
    System.arraycopy(velocityMps, 0, velocity, 0, 3);
  }

  /** Writes the sphere's position, m, into {@code out} (float[3]). */
  public void position(float[] out) {
    System.arraycopy(position, 0, out, 0, 3);
  }

  /** Writes the sphere's velocity, m/s, into {@code out} (float[3]). */
  public void velocity(float[] out) {
    System.arraycopy(velocity, 0, out, 0, 3);
  }

  /** Sets the velocity, m/s (as World::set_linear_velocity before a step). */
  public void setVelocity(float[] velocityMps) {
    System.arraycopy(velocityMps, 0, velocity, 0, 3);
  }

  /** The contacts of the last step (speculative ones included). */
  public int contactCount() {
    return count;
  }

  /**
   * Whether the sphere stands on a surface no steeper than the rules' slope within the probe below
   * it (is_grounded against the static shapes).
   */
  public boolean grounded() {
    float inset = Math.min(0.02f, radius / 2);
    float castRadius = radius - inset;
    float distance = inset + world.movement.groundProbeM;
    float dy = -1 * distance; // direction (0, -1, 0) normalised, times the distance
    sweepT = 1;
    boolean found = false;
    for (int i = 0; i < world.planeCount; ++i) {
      found |= sweepPlane(i, castRadius, dy);
    }
    for (int b = 0; b < world.boxCount; ++b) {
      found |= sweepBox(b, castRadius, dy);
    }
    for (int t = 0; t < world.triangleCount; ++t) {
      found |= sweepTriangle(t, castRadius, dy);
    }
    return found && sweepNormal[1] >= minGroundNormalY;
  }

  /** One physics step of {@code dtS} seconds (the tick) with the velocity as set. */
  public void step(float dtS) {
    float speed = (float) Math.sqrt(dot(velocity, velocity));
    float margin = 4 * LINEAR_SLOP + Math.min(speed * dtS, MAX_SPECULATIVE_DISTANCE);
    swapContacts();
    findContacts(margin);
    // integrate velocities
    float[] g = world.gravityMps2;
    for (int k = 0; k < 3; ++k) velocity[k] = velocity[k] + dtS * g[k];
    float v2 = dot(velocity, velocity);
    if (v2 > MAX_LINEAR_SPEED * MAX_LINEAR_SPEED) {
      float scale = MAX_LINEAR_SPEED / (float) Math.sqrt(v2);
      for (int k = 0; k < 3; ++k) velocity[k] *= scale;
    }
    // warm start
    for (int c = 0; c < count; ++c) {
      float impulse = impulses[c];
      for (int k = 0; k < 3; ++k) {
        float linear = normals[3 * c + k] * impulse + 0f;
        velocity[k] = velocity[k] - inverseMass * linear;
      }
    }
    float inverseH = 1 / dtS;
    for (int i = 0; i < ITERATIONS; ++i) {
      for (int c = 0; c < count; ++c) solveNormal(c, inverseH);
    }
    for (int k = 0; k < 3; ++k) position[k] += velocity[k] * dtS;
  }

  private void solveNormal(int c, float inverseH) {
    float separation = separations[c];
    float bias = separation * inverseH;
    if (!(separation > 0)) {
      float correction = Math.max(
          BAUMGARTE * inverseH * Math.min(separation + LINEAR_SLOP, 0f), -MAX_CORRECTION_SPEED);
      bias = correction;
    }
    float nx = normals[3 * c], ny = normals[3 * c + 1], nz = normals[3 * c + 2];
    float vn = (0f - velocity[0]) * nx + (0f - velocity[1]) * ny + (0f - velocity[2]) * nz;
    float impulse = -normalMass * 1f * (vn + bias);
    float accumulated = Math.max(impulses[c] + impulse, 0f);
    float applied = accumulated - impulses[c];
    impulses[c] = accumulated;
    float pa = inverseMass * applied;
    velocity[0] -= pa * nx;
    velocity[1] -= pa * ny;
    velocity[2] -= pa * nz;
  }

  private void swapContacts() {
    long[] k = previousKeys;
    previousKeys = keys;
    keys = k;
    float[] i = previousImpulses;
    previousImpulses = impulses;
    impulses = i;
    previousCount = count;
    count = 0;
    if (keys.length < previousKeys.length) keys = new long[previousKeys.length];
    if (impulses.length < previousImpulses.length) impulses = new float[previousImpulses.length];
  }

  private void findContacts(float margin) {
    for (int i = 0; i < world.planeCount; ++i) {
      float[] p = world.planes;
      float separation =
          (p[4 * i] * position[0] + (p[4 * i + 1] * position[1] + p[4 * i + 2] * position[2]))
          - p[4 * i + 3] - radius;
      if (separation < margin) {
        addContact(key(i, 0), p[4 * i], p[4 * i + 1], p[4 * i + 2], separation);
      }
    }
    for (int b = 0; b < world.boxCount; ++b) {
      if (!nearBox(b, radius + margin)) continue;
      closestOnBox(b);
      if (feature[6] - radius >= margin) continue;
      addContact(
          key(world.planeCount + b, 0), feature[3], feature[4], feature[5], feature[6] - radius);
    }
    meshHits = 0;
    for (int t = 0; t < world.triangleCount; ++t) {
      if (!nearTriangle(t, radius + margin)) continue;
      boolean onFace = closestOnTriangle(t);
      if (feature[6] - radius >= margin) continue;
      addMeshHit(t, onFace);
    }
    for (int h = 0; h < meshHits; ++h) {
      if (!meshHitOnFace[h] && edgeCoveredByFace(h)) continue;
      int t = meshHitTriangle[h];
      float[] f = meshHitFeature;
      addContact(
          key(world.planeCount + world.boxCount + world.triangleMesh[t], world.triangleIndex[t]),
          f[7 * h + 3], f[7 * h + 4], f[7 * h + 5], f[7 * h + 6] - radius);
    }
  }

  private static long key(int shape, int triangle) {
    return ((long) shape << 32) | (triangle & 0xFFFFFFFFL);
  }

  /** A contact whose outward normal is {@code n}: the solver's normal points into the shape. */
  private void addContact(long key, float nx, float ny, float nz, float separation) {
    if (count == keys.length) {
      keys = java.util.Arrays.copyOf(keys, 2 * count);
      impulses = java.util.Arrays.copyOf(impulses, 2 * count);
      separations = java.util.Arrays.copyOf(separations, 2 * count);
      normals = java.util.Arrays.copyOf(normals, 6 * count);
    }
    keys[count] = key;
    normals[3 * count] = -nx;
    normals[3 * count + 1] = -ny;
    normals[3 * count + 2] = -nz;
    separations[count] = separation;
    float warm = 0;
    for (int i = 0; i < previousCount; ++i) {
      if (previousKeys[i] == key) {
        warm = previousImpulses[i];
        break;
      }
    }
    impulses[count] = warm;
    ++count;
  }

  private void addMeshHit(int triangle, boolean onFace) {
    if (meshHits == meshHitTriangle.length) {
      meshHitTriangle = java.util.Arrays.copyOf(meshHitTriangle, 2 * meshHits);
      meshHitOnFace = java.util.Arrays.copyOf(meshHitOnFace, 2 * meshHits);
      meshHitFeature = java.util.Arrays.copyOf(meshHitFeature, 14 * meshHits);
    }
    meshHitTriangle[meshHits] = triangle;
    meshHitOnFace[meshHits] = onFace;
    System.arraycopy(feature, 0, meshHitFeature, 7 * meshHits, 7);
    ++meshHits;
  }

  private boolean edgeCoveredByFace(int edge) {
    int mesh = world.triangleMesh[meshHitTriangle[edge]];
    float px = meshHitFeature[7 * edge], py = meshHitFeature[7 * edge + 1],
          pz = meshHitFeature[7 * edge + 2];
    float tolerance = 1e-5f + 1e-6f * (float) Math.sqrt(px * px + (py * py + pz * pz));
    for (int h = 0; h < meshHits; ++h) {
      int t = meshHitTriangle[h];
      if (!meshHitOnFace[h] || world.triangleMesh[t] != mesh) continue;
      closestPointOnTriangle(px, py, pz, t, scratch);
      float dx = scratch[0] - px, dy = scratch[1] - py, dz = scratch[2] - pz;
      if (dx * dx + (dy * dy + dz * dz) <= tolerance * tolerance) return true;
    }
    return false;
  }

  private boolean nearBox(int b, float reach) {
    float[] s = world.boxes;
    int at = 15 * b;
    for (int i = 0; i < 3; ++i) {
      float extent = Math.abs(s[at + 3 + 3 * i]) * s[at + 12]
          + (Math.abs(s[at + 4 + 3 * i]) * s[at + 13] + Math.abs(s[at + 5 + 3 * i]) * s[at + 14]);
      if (Math.abs(position[i] - s[at + i]) > extent + reach + 1e-3f) return false;
    }
    return true;
  }

  private boolean nearTriangle(int t, float reach) {
    float[] v = world.triangles;
    for (int i = 0; i < 3; ++i) {
      float lo = Math.min(v[9 * t + i], Math.min(v[9 * t + 3 + i], v[9 * t + 6 + i]));
      float hi = Math.max(v[9 * t + i], Math.max(v[9 * t + 3 + i], v[9 * t + 6 + i]));
      if (position[i] < lo - reach - 1e-3f || position[i] > hi + reach + 1e-3f) return false;
    }
    return true;
  }

  /** StaticGeometry::closest_feature for a box, into {@link #feature}. */
  private void closestOnBox(int b) {
    float[] s = world.boxes;
    int at = 15 * b;
    float dx = position[0] - s[at], dy = position[1] - s[at + 1], dz = position[2] - s[at + 2];
    float[] local = scratch;
    for (int i = 0; i < 3; ++i) { // rotationᵀ · d
      local[i] = s[at + 3 + i] * dx + (s[at + 6 + i] * dy + s[at + 9 + i] * dz);
    }
    boolean outside = false;
    for (int i = 0; i < 3; ++i) {
      float h = s[at + 12 + i];
      clamped[i] = Math.min(Math.max(local[i], -h), h);
      outside |= clamped[i] != local[i];
    }
    if (outside) {
      float nx = local[0] - clamped[0], ny = local[1] - clamped[1], nz = local[2] - clamped[2];
      float dist = (float) Math.sqrt(nx * nx + (ny * ny + nz * nz));
      nx /= dist;
      ny /= dist;
      nz /= dist;
      rotate(at, clamped[0], clamped[1], clamped[2], 0);
      for (int i = 0; i < 3; ++i) feature[i] += s[at + i];
      rotate(at, nx, ny, nz, 3);
      feature[6] = dist;
      return;
    }
    int axis = 0;
    float best = s[at + 12] - Math.abs(local[0]);
    for (int k = 1; k < 3; ++k) {
      float depth = s[at + 12 + k] - Math.abs(local[k]);
      if (depth < best) {
        best = depth;
        axis = k;
      }
    }
    float[] n = faceNormal;
    n[0] = 0;
    n[1] = 0;
    n[2] = 0;
    n[axis] = local[axis] >= 0 ? 1f : -1f;
    System.arraycopy(local, 0, surface, 0, 3);
    surface[axis] = n[axis] * s[at + 12 + axis];
    rotate(at, surface[0], surface[1], surface[2], 0);
    for (int i = 0; i < 3; ++i) feature[i] += s[at + i];
    rotate(at, n[0], n[1], n[2], 3);
    feature[6] = -best;
  }

  /** feature[to..to+3) = rotation · (x, y, z). */
  private void rotate(int at, float x, float y, float z, int to) {
    float[] s = world.boxes;
    for (int i = 0; i < 3; ++i) {
      feature[to + i] = s[at + 3 + 3 * i] * x + (s[at + 4 + 3 * i] * y + s[at + 5 + 3 * i] * z);
    }
  }

  /** StaticGeometry::closest_feature for a triangle, into {@link #feature}; true: on the face. */
  private boolean closestOnTriangle(int t) {
    float[] v = world.triangles;
    int a = 9 * t;
    closestPointOnTriangle(position[0], position[1], position[2], t, scratch);
    float qx = scratch[0], qy = scratch[1], qz = scratch[2];
    float abx = v[a + 3] - v[a], aby = v[a + 4] - v[a + 1], abz = v[a + 5] - v[a + 2];
    float acx = v[a + 6] - v[a], acy = v[a + 7] - v[a + 1], acz = v[a + 8] - v[a + 2];
    float fx = aby * acz - abz * acy, fy = abz * acx - abx * acz, fz = abx * acy - aby * acx;
    float faceLength = (float) Math.sqrt(fx * fx + (fy * fy + fz * fz));
    if (faceLength > 0) {
      fx /= faceLength;
      fy /= faceLength;
      fz /= faceLength;
    } else {
      fx = 0;
      fy = 1;
      fz = 0;
    }
    float nx = position[0] - qx, ny = position[1] - qy, nz = position[2] - qz;
    float dist = (float) Math.sqrt(nx * nx + (ny * ny + nz * nz));
    float along = fx * nx + (fy * ny + fz * nz);
    float sx = nx - fx * along, sy = ny - fy * along, sz = nz - fz * along;
    boolean onFace = sx * sx + (sy * sy + sz * sz) <= 1e-8f * (dist * dist) + 1e-12f;
    float pointNorm = (float) Math.sqrt(
        position[0] * position[0] + (position[1] * position[1] + position[2] * position[2]));
    if (dist > 1e-12f * (1f + pointNorm)) {
      nx /= dist;
      ny /= dist;
      nz /= dist;
    } else {
      nx = fx;
      ny = fy;
      nz = fz;
    }
    feature[0] = qx;
    feature[1] = qy;
    feature[2] = qz;
    feature[3] = nx;
    feature[4] = ny;
    feature[5] = nz;
    feature[6] = dist;
    return onFace;
  }

  /** geometry.cpp's closest_point_on_triangle of p to triangle t, into out[0..3). */
  private void closestPointOnTriangle(float px, float py, float pz, int t, float[] out) {
    float[] v = world.triangles;
    int i = 9 * t;
    float ax = v[i], ay = v[i + 1], az = v[i + 2];
    float bx = v[i + 3], by = v[i + 4], bz = v[i + 5];
    float cx = v[i + 6], cy = v[i + 7], cz = v[i + 8];
    float abx = bx - ax, aby = by - ay, abz = bz - az;
    float acx = cx - ax, acy = cy - ay, acz = cz - az;
    float apx = px - ax, apy = py - ay, apz = pz - az;
    float d1 = abx * apx + (aby * apy + abz * apz), d2 = acx * apx + (acy * apy + acz * apz);
    if (d1 <= 0 && d2 <= 0) {
      set(out, ax, ay, az);
      return;
    }
    float bpx = px - bx, bpy = py - by, bpz = pz - bz;
    float d3 = abx * bpx + (aby * bpy + abz * bpz), d4 = acx * bpx + (acy * bpy + acz * bpz);
    if (d3 >= 0 && d4 <= d3) {
      set(out, bx, by, bz);
      return;
    }
    float vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
      float s = d1 / (d1 - d3);
      set(out, ax + abx * s, ay + aby * s, az + abz * s);
      return;
    }
    float cpx = px - cx, cpy = py - cy, cpz = pz - cz;
    float d5 = abx * cpx + (aby * cpy + abz * cpz), d6 = acx * cpx + (acy * cpy + acz * cpz);
    if (d6 >= 0 && d5 <= d6) {
      set(out, cx, cy, cz);
      return;
    }
    float vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
      float s = d2 / (d2 - d6);
      set(out, ax + acx * s, ay + acy * s, az + acz * s);
      return;
    }
    float va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
      float s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
      set(out, bx + (cx - bx) * s, by + (cy - by) * s, bz + (cz - bz) * s);
      return;
    }
    float denom = 1 / (va + vb + vc);
    float sb = vb * denom, sc = vc * denom;
    set(out, (ax + abx * sb) + acx * sc, (ay + aby * sb) + acy * sc, (az + abz * sb) + acz * sc);
  }

  private static void set(float[] out, float x, float y, float z) {
    out[0] = x;
    out[1] = y;
    out[2] = z;
  }

  private static float dot(float[] a, float[] b) {
    return a[0] * b[0] + (a[1] * b[1] + a[2] * b[2]);
  }

  // --- the ground probe: sweeps of a sphere from the position along (0, dy, 0) ---

  private boolean record(float t, float nx, float ny, float nz) {
    if (t >= sweepT) return false;
    sweepT = t;
    sweepNormal[0] = nx;
    sweepNormal[1] = ny;
    sweepNormal[2] = nz;
    return true;
  }

  private boolean sweepPlane(int i, float castRadius, float dy) {
    float[] p = world.planes;
    float nx = p[4 * i], ny = p[4 * i + 1], nz = p[4 * i + 2];
    float start =
        (nx * position[0] + (ny * position[1] + nz * position[2])) - p[4 * i + 3] - castRadius;
    float speed = nx * 0f + (ny * dy + nz * 0f);
    if (start < 0 || speed >= 0) return false;
    float t = -start / speed;
    if (t > 1) return false;
    return record(t, nx, ny, nz);
  }

  private boolean sweepBox(int b, float castRadius, float dy) {
    float[] s = world.boxes;
    int at = 15 * b;
    float rx = position[0] - s[at], ry = position[1] - s[at + 1], rz = position[2] - s[at + 2];
    float[] o = castOrigin;
    float[] d = castPath;
    for (int i = 0; i < 3; ++i) {
      o[i] = s[at + 3 + i] * rx + (s[at + 6 + i] * ry + s[at + 9 + i] * rz);
      d[i] = s[at + 3 + i] * 0f + (s[at + 6 + i] * dy + s[at + 9 + i] * 0f);
    }
    float enter = 0, leave = 1;
    for (int axis = 0; axis < 3; ++axis) {
      float extent = s[at + 12 + axis] + castRadius;
      if (d[axis] == 0) {
        if (Math.abs(o[axis]) > extent) return false;
        continue;
      }
      float t0 = (-extent - o[axis]) / d[axis], t1 = (extent - o[axis]) / d[axis];
      if (t0 > t1) {
        float swap = t0;
        t0 = t1;
        t1 = swap;
      }
      enter = Math.max(enter, t0);
      leave = Math.min(leave, t1);
      if (enter > leave) return false;
    }
    float savedT = sweepT;
    sweepT = Math.min(sweepT, 1); // the local sweep records into the same best hit
    boolean found = false;
    float[] n = hitNormal;
    for (int axis = 0; axis < 3; ++axis) {
      for (int sign = -1; sign <= 1; sign += 2) {
        float start = o[axis] * sign - (s[at + 12 + axis] + castRadius);
        float speed = d[axis] * sign;
        if (start < 0 || speed >= 0) continue;
        float t = -start / speed;
        if (t > 1) continue;
        int u = (axis + 1) % 3, v = (axis + 2) % 3;
        float pu = o[u] + d[u] * t, pv = o[v] + d[v] * t;
        if (Math.abs(pu) <= s[at + 12 + u] && Math.abs(pv) <= s[at + 12 + v]) {
          n[0] = 0;
          n[1] = 0;
          n[2] = 0;
          n[axis] = sign;
          found |= recordLocal(at, t, n);
        }
      }
    }
    if (found) return true;
    for (int axis = 0; axis < 3; ++axis) {
      int u = (axis + 1) % 3, v = (axis + 2) % 3;
      for (int su = -1; su <= 1; su += 2) {
        for (int sv = -1; sv <= 1; sv += 2) {
          float[] p = edgeStart;
          float[] q = edgeEnd;
          p[axis] = -s[at + 12 + axis];
          q[axis] = s[at + 12 + axis];
          p[u] = q[u] = su * s[at + 12 + u];
          p[v] = q[v] = sv * s[at + 12 + v];
          found |= sweepSegment(o, d, castRadius, p, q, at);
        }
      }
    }
    if (!found) sweepT = savedT;
    return found;
  }

  /** Records a hit whose normal is in the box's frame (at: the box; -1: world frame). */
  private boolean recordLocal(int at, float t, float[] n) {
    if (at < 0) return record(t, n[0], n[1], n[2]);
    float[] s = world.boxes;
    float x = s[at + 3] * n[0] + (s[at + 4] * n[1] + s[at + 5] * n[2]);
    float y = s[at + 6] * n[0] + (s[at + 7] * n[1] + s[at + 8] * n[2]);
    float z = s[at + 9] * n[0] + (s[at + 10] * n[1] + s[at + 11] * n[2]);
    return record(t, x, y, z);
  }

  private boolean sweepPoint(float[] o, float[] d, float r, float[] c, int at) {
    float mx = o[0] - c[0], my = o[1] - c[1], mz = o[2] - c[2];
    float cc = (mx * mx + (my * my + mz * mz)) - r * r;
    if (cc <= 0) return false;
    float a = d[0] * d[0] + (d[1] * d[1] + d[2] * d[2]);
    float b = mx * d[0] + (my * d[1] + mz * d[2]);
    if (b >= 0 || a <= 0) return false;
    float disc = b * b - a * cc;
    if (disc < 0) return false;
    float t = (-b - (float) Math.sqrt(disc)) / a;
    if (!(t >= 0 && t <= 1)) return false;
    float nx = o[0] + d[0] * t - c[0], ny = o[1] + d[1] * t - c[1], nz = o[2] + d[2] * t - c[2];
    float len = (float) Math.sqrt(nx * nx + (ny * ny + nz * nz));
    setNormal(len, nx, ny, nz);
    return recordLocal(at, t, hitNormal);
  }

  private boolean sweepSegment(float[] o, float[] d, float r, float[] p, float[] q, int at) {
    boolean found = sweepPoint(o, d, r, p, at);
    found = sweepPoint(o, d, r, q, at) || found;
    float ax = q[0] - p[0], ay = q[1] - p[1], az = q[2] - p[2];
    float axisLen2 = ax * ax + (ay * ay + az * az);
    if (axisLen2 <= 0) return found;
    float mx = o[0] - p[0], my = o[1] - p[1], mz = o[2] - p[2];
    float ma = (mx * ax + (my * ay + mz * az)) / axisLen2;
    float da = (d[0] * ax + (d[1] * ay + d[2] * az)) / axisLen2;
    float mpx = mx - ax * ma, mpy = my - ay * ma, mpz = mz - az * ma;
    float dpx = d[0] - ax * da, dpy = d[1] - ay * da, dpz = d[2] - az * da;
    float a = dpx * dpx + (dpy * dpy + dpz * dpz);
    float b = mpx * dpx + (mpy * dpy + mpz * dpz);
    float cc = (mpx * mpx + (mpy * mpy + mpz * mpz)) - r * r;
    if (a <= 0 || b >= 0) return found;
    if (cc <= 0) {
      float s = (mx * ax + (my * ay + mz * az)) / axisLen2;
      if (s >= 0 && s <= 1) return found;
    }
    float disc = b * b - a * cc;
    if (disc < 0) return found;
    float t = (-b - (float) Math.sqrt(disc)) / a;
    if (t < 0 || t > 1) return found;
    float cx = o[0] + d[0] * t, cy = o[1] + d[1] * t, cz = o[2] + d[2] * t;
    float s = ((cx - p[0]) * ax + ((cy - p[1]) * ay + (cz - p[2]) * az)) / axisLen2;
    if (s < 0 || s > 1) return found;
    float nx = cx - (p[0] + ax * s), ny = cy - (p[1] + ay * s), nz = cz - (p[2] + az * s);
    float len = (float) Math.sqrt(nx * nx + (ny * ny + nz * nz));
    setNormal(len, nx, ny, nz);
    return recordLocal(at, t, hitNormal) || found;
  }

  private boolean sweepTriangle(int t, float castRadius, float dy) {
    float[] v = world.triangles;
    int i = 9 * t;
    float[] a = cornerA;
    float[] b = cornerB;
    float[] c = cornerC;
    float[] o = castOrigin;
    float[] d = castPath;
    set(a, v[i], v[i + 1], v[i + 2]);
    set(b, v[i + 3], v[i + 4], v[i + 5]);
    set(c, v[i + 6], v[i + 7], v[i + 8]);
    set(o, position[0], position[1], position[2]);
    set(d, 0f, dy, 0f);
    float abx = b[0] - a[0], aby = b[1] - a[1], abz = b[2] - a[2];
    float acx = c[0] - a[0], acy = c[1] - a[1], acz = c[2] - a[2];
    float wx = aby * acz - abz * acy, wy = abz * acx - abx * acz, wz = abx * acy - aby * acx;
    float windingLen = (float) Math.sqrt(wx * wx + (wy * wy + wz * wz));
    boolean found = false;
    if (windingLen > 0) {
      float nx = wx / windingLen, ny = wy / windingLen, nz = wz / windingLen;
      float side = nx * (o[0] - a[0]) + (ny * (o[1] - a[1]) + nz * (o[2] - a[2]));
      if (side < 0) {
        nx = -nx;
        ny = -ny;
        nz = -nz;
        side = -side;
      }
      float approach = nx * d[0] + (ny * d[1] + nz * d[2]);
      if (side > castRadius && approach < 0) {
        float tt = (castRadius - side) / approach;
        if (tt >= 0 && tt <= 1) {
          float px = o[0] + d[0] * tt - nx * castRadius;
          float py = o[1] + d[1] * tt - ny * castRadius;
          float pz = o[2] + d[2] * tt - nz * castRadius;
          boolean inside = edgeSide(a, b, px, py, pz, wx, wy, wz) >= 0
              && edgeSide(b, c, px, py, pz, wx, wy, wz) >= 0
              && edgeSide(c, a, px, py, pz, wx, wy, wz) >= 0;
          if (inside) found = record(tt, nx, ny, nz);
        }
      }
    }
    if (found) return true;
    found = sweepSegment(o, d, castRadius, a, b, -1) || found;
    found = sweepSegment(o, d, castRadius, b, c, -1) || found;
    found = sweepSegment(o, d, castRadius, c, a, -1) || found;
    return found;
  }

  /** The hit normal: (x, y, z) / len, or +Y (the core's fallback normal) when len is 0. */
  private void setNormal(float len, float x, float y, float z) {
    if (len > 0) {
      set(hitNormal, x / len, y / len, z / len);
    } else {
      set(hitNormal, 0, 1, 0);
    }
  }

  /** (q - p) × (touch - p) · winding. */
  private static float edgeSide(
      float[] p, float[] q, float x, float y, float z, float wx, float wy, float wz) {
    float ex = q[0] - p[0], ey = q[1] - p[1], ez = q[2] - p[2];
    float tx = x - p[0], ty = y - p[1], tz = z - p[2];
    float cx = ey * tz - ez * ty, cy = ez * tx - ex * tz, cz = ex * ty - ey * tx;
    return cx * wx + (cy * wy + cz * wz);
  }
}
