package io.ricochet.client.core.predict;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertTrue;

import org.junit.jupiter.api.Test;

/** One physics step of the own sphere against planes, boxes and meshes, by hand-computed cases. */
class SphereWorldTest {
  private static final float DT = 1f / 60;

  private static SphereWorld at(
      CollisionWorld world, float x, float y, float z, float vx, float vy, float vz) {
    SphereWorld sphere = new SphereWorld(world);
    sphere.seed(new float[] {x, y, z}, new float[] {vx, vy, vz});
    return sphere;
  }

  private static float[] position(SphereWorld sphere) {
    float[] p = new float[3];
    sphere.position(p);
    return p;
  }

  @Test
  void groundedOnAPlaneWithinTheProbeAndNotAboveIt() {
    CollisionWorld floor = Worlds.of(Worlds.empty().addPlanes(Worlds.plane(0, 1, 0, 0)));
    assertTrue(at(floor, 0, 0.4f, 0, 0, 0, 0).grounded()); // resting
    // the cast sphere (0.38 m) reaches 0.02 + 0.05 m down: a gap up to 0.05 m still counts
    assertTrue(at(floor, 0, 0.44f, 0, 0, 0, 0).grounded());
    assertFalse(at(floor, 0, 0.46f, 0, 0, 0, 0).grounded());
  }

  @Test
  void aSlopeSteeperThanTheMaximumIsAWall() {
    for (int degrees : new int[] {40, 60}) {
      double a = Math.toRadians(degrees);
      float nx = (float) Math.sin(a), ny = (float) Math.cos(a);
      CollisionWorld slope = Worlds.of(Worlds.empty().addPlanes(Worlds.plane(nx, ny, 0, 0)));
      // resting on the slope: the centre 0.4 m along its normal from the origin
      SphereWorld sphere = at(slope, 0.4f * nx, 0.4f * ny, 0, 0, 0, 0);
      assertEquals(degrees < 50, sphere.grounded(), degrees + "°");
    }
  }

  @Test
  void aSphereRestingOnAPlaneStaysWithoutSinking() {
    CollisionWorld floor = Worlds.of(Worlds.empty().addPlanes(Worlds.plane(0, 1, 0, 0)));
    SphereWorld sphere = at(floor, 1, 0.4f, 2, 0, 0, 0);
    for (int i = 0; i < 600; ++i) sphere.step(DT);
    float[] p = position(sphere);
    // gravity's 0.1635 m/s each step is taken out by the contact before the move: no sinking
    assertEquals(0.4f, p[1], 1e-6f);
    assertEquals(1f, p[0], 0f);
    assertEquals(2f, p[2], 0f);
    assertEquals(1, sphere.contactCount());
  }

  @Test
  void aFallingSphereStopsAtThePlaneAndGoesNoDeeperThanTheSlop() {
    CollisionWorld floor = Worlds.of(Worlds.empty().addPlanes(Worlds.plane(0, 1, 0, 0)));
    SphereWorld sphere = at(floor, 0, 3, 0, 0, 0, 0);
    float lowest = 3;
    for (int i = 0; i < 240; ++i) {
      sphere.step(DT);
      lowest = Math.min(lowest, position(sphere)[1]);
    }
    assertTrue(lowest >= 0.4f - 0.005f, "lowest " + lowest);
    assertEquals(0.4f, position(sphere)[1], 0.005f);
  }

  @Test
  void freeFallIsSemiImplicitEuler() {
    CollisionWorld none = Worlds.of(Worlds.empty());
    SphereWorld sphere = at(none, 0, 100, 0, 0, 0, 0);
    sphere.step(0.5f);
    sphere.step(0.5f);
    // v1 = -4.905, x1 = 100 - 2.4525; v2 = -9.81, x2 = x1 - 4.905
    assertEquals(100 - 2.4525f - 4.905f, position(sphere)[1], 1e-4f);
  }

  @Test
  void aSphereRunningIntoABoxSlidesAlongItsFace() {
    // a wall: x from 1 to 3, on a floor
    CollisionWorld walled = Worlds.of(
        Worlds.empty().addPlanes(Worlds.plane(0, 1, 0, 0)).addBoxes(Worlds.box(2, 1, 0, 1, 1, 10)));
    SphereWorld sphere = at(walled, 0, 0.4f, 0, 5, 0, 3);
    for (int i = 0; i < 60; ++i) sphere.step(DT);
    float[] p = position(sphere);
    assertTrue(p[0] <= 0.6f + 1e-5f && p[0] >= 0.6f - 0.005f, "x " + p[0]);
    assertEquals(3f, p[2], 1e-3f); // frictionless: 1 s at 3 m/s along the face
    assertEquals(0.4f, p[1], 1e-5f);
  }

  @Test
  void theTopOfABoxIsGround() {
    CollisionWorld boxed = Worlds.of(Worlds.empty().addBoxes(Worlds.box(0, -1, 0, 5, 1, 5)));
    SphereWorld sphere = at(boxed, 1, 0.4f, 1, 0, 0, 0);
    assertTrue(sphere.grounded());
    for (int i = 0; i < 120; ++i) sphere.step(DT);
    assertEquals(0.4f, position(sphere)[1], 1e-5f);
    assertFalse(at(boxed, 6, 0.4f, 1, 0, 0, 0).grounded()); // beyond its edge: nothing below
  }

  @Test
  void aTriangleMeshFloorHoldsAndCarriesASphereAcrossItsInternalEdge() {
    CollisionWorld meshed = Worlds.of(Worlds.empty().addMeshes(Worlds.floorMesh(0, 10)));
    SphereWorld resting = at(meshed, 1, 0.4f, -1, 0, 0, 0);
    assertTrue(resting.grounded());
    for (int i = 0; i < 120; ++i) resting.step(DT);
    assertEquals(0.4f, position(resting)[1], 1e-5f);

    // across the diagonal x = z of the two triangles: no bump from the internal edge
    SphereWorld rolling = at(meshed, -3, 0.4f, 3, 6, 0, -6);
    float highest = 0;
    for (int i = 0; i < 60; ++i) {
      rolling.step(DT);
      highest = Math.max(highest, position(rolling)[1]);
    }
    float[] p = position(rolling);
    assertEquals(3f, p[0], 1e-3f);
    assertEquals(-3f, p[2], 1e-3f);
    assertTrue(highest <= 0.4f + 1e-5f, "highest " + highest);
  }

  @Test
  void aTriangleIsTwoSided() {
    CollisionWorld meshed = Worlds.of(Worlds.empty().addMeshes(Worlds.floorMesh(2, 10)));
    // under the mesh, moving up into it: stopped 0.4 m below it
    SphereWorld sphere = at(meshed, 0, 1.0f, 0, 0, 5, 0); // would rise to 2.27 m unhindered
    float highest = 0;
    for (int i = 0; i < 30; ++i) {
      sphere.step(DT);
      highest = Math.max(highest, position(sphere)[1]);
    }
    assertTrue(highest <= 1.6f + 1e-5f && highest > 1.55f, "highest " + highest);
  }
}
