package io.ricochet.client.core.predict;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNull;

import io.ricochet.wire.WorldProto;
import org.junit.jupiter.api.Test;

/** Each rule of PROTOCOL.md's collision world table refuses the whole world with its reason. */
class CollisionWorldTest {
  private static WorldRefusal refusalOf(WorldProto.CollisionWorld.Builder world) {
    return CollisionWorld.parse(world.build().toByteArray()).refusal();
  }

  @Test
  void aWorldWithinEveryRuleIsKept() {
    CollisionWorld world = CollisionWorld.parse(Worlds.empty()
                                                    .addPlanes(Worlds.plane(0, 2, 0, 0))
                                                    .addBoxes(Worlds.box(0, 1, 0, 1, 1, 1))
                                                    .addMeshes(Worlds.floorMesh(0, 5))
                                                    .build()
                                                    .toByteArray());
    assertNull(world.refusal());
    assertEquals(1 + 1 + 2, world.shapeCount());
    assertEquals(1f, world.planes[1], 0f); // the normal is normalised
  }

  @Test
  void bytesThatAreNotAWorldAreMalformed() {
    assertEquals(WorldRefusal.MALFORMED, CollisionWorld.parse(new byte[] {(byte) 0xFF}).refusal());
    assertEquals(WorldRefusal.MALFORMED, CollisionWorld.parse(null).refusal());
  }

  @Test
  void movementRulesAreRequiredAndInRange() {
    assertEquals(WorldRefusal.BAD_MOVEMENT, refusalOf(Worlds.empty().clearMovement()));
    WorldProto.CollisionWorld.Builder steep = Worlds.empty();
    steep.setMovement(steep.getMovement().toBuilder().setGroundMaxSlopeDeg(90));
    assertEquals(WorldRefusal.BAD_MOVEMENT, refusalOf(steep));
    WorldProto.CollisionWorld.Builder slow = Worlds.empty();
    slow.setMovement(slow.getMovement().toBuilder().setMaxSpeedMps(0.05f));
    assertEquals(WorldRefusal.BAD_MOVEMENT, refusalOf(slow));
    WorldProto.CollisionWorld.Builder probe = Worlds.empty();
    probe.setMovement(probe.getMovement().toBuilder().setGroundProbeM(Float.NaN));
    assertEquals(WorldRefusal.BAD_MOVEMENT, refusalOf(probe));
  }

  @Test
  void theBodyIsChecked() {
    assertEquals(WorldRefusal.BAD_BODY, refusalOf(Worlds.empty().setPlayerRadiusM(0.04f)));
    assertEquals(WorldRefusal.BAD_BODY, refusalOf(Worlds.empty().setPlayerRadiusM(5.5f)));
    assertEquals(WorldRefusal.BAD_BODY, refusalOf(Worlds.empty().setPlayerMassKg(0.5f)));
  }

  @Test
  void gravityIsThreeFiniteValuesOfLengthAtMostOneHundred() {
    assertEquals(WorldRefusal.BAD_GRAVITY, refusalOf(Worlds.empty().addGravityMps2(0)));
    assertEquals(WorldRefusal.BAD_GRAVITY,
        refusalOf(Worlds.empty().setGravityMps2(0, 80).setGravityMps2(1, -80)));
    assertEquals(WorldRefusal.BAD_GRAVITY,
        refusalOf(Worlds.empty().setGravityMps2(1, Float.POSITIVE_INFINITY)));
  }

  @Test
  void tooManyShapesAreRefused() {
    WorldProto.CollisionWorld.Builder planes = Worlds.empty();
    for (int i = 0; i < 17; ++i) planes.addPlanes(Worlds.plane(0, 1, 0, -i));
    assertEquals(WorldRefusal.TOO_MANY_SHAPES, refusalOf(planes));
    WorldProto.CollisionWorld.Builder meshes = Worlds.empty();
    for (int i = 0; i < 65; ++i) meshes.addMeshes(Worlds.floorMesh(i, 1));
    assertEquals(WorldRefusal.TOO_MANY_SHAPES, refusalOf(meshes));
  }

  @Test
  void aPlaneNeedsAFiniteNonZeroNormalAndAnOffsetInRange() {
    assertEquals(
        WorldRefusal.BAD_PLANE, refusalOf(Worlds.empty().addPlanes(Worlds.plane(0, 0, 0, 0))));
    assertEquals(WorldRefusal.BAD_PLANE,
        refusalOf(Worlds.empty().addPlanes(Worlds.plane(0, Float.NaN, 0, 0))));
    assertEquals(
        WorldRefusal.BAD_PLANE, refusalOf(Worlds.empty().addPlanes(Worlds.plane(0, 1, 0, 200000))));
    assertEquals(WorldRefusal.BAD_PLANE,
        refusalOf(Worlds.empty().addPlanes(Worlds.plane(0, 1, 0, 0).toBuilder().addNormal(1))));
  }

  @Test
  void aBoxNeedsACentreInRangeAUnitQuaternionAndHalfExtentsOfAMillimetreOrMore() {
    WorldProto.CollisionBox good = Worlds.box(0, 0, 0, 1, 1, 1);
    assertEquals(WorldRefusal.BAD_BOX,
        refusalOf(Worlds.empty().addBoxes(good.toBuilder().setCenterM(0, 1e6f))));
    assertEquals(WorldRefusal.BAD_BOX,
        refusalOf(Worlds.empty().addBoxes(good.toBuilder().setOrientation(3, 0.9f))));
    assertEquals(WorldRefusal.BAD_BOX,
        refusalOf(Worlds.empty().addBoxes(good.toBuilder().setHalfExtentsM(2, 0.0005f))));
    assertEquals(
        WorldRefusal.BAD_BOX, refusalOf(Worlds.empty().addBoxes(good.toBuilder().addCenterM(1))));
    // within 0.001 of unit length is accepted
    assertNull(refusalOf(Worlds.empty().addBoxes(good.toBuilder().setOrientation(3, 1.0005f))));
  }

  @Test
  void aMeshNeedsWholeVerticesInRangeAndIndicesBelowItsVertexCount() {
    WorldProto.CollisionMesh good = Worlds.floorMesh(0, 1);
    assertEquals(WorldRefusal.BAD_MESH,
        refusalOf(Worlds.empty().addMeshes(good.toBuilder().addVerticesM(1))));
    assertEquals(WorldRefusal.BAD_MESH,
        refusalOf(Worlds.empty().addMeshes(good.toBuilder().setIndices(0, 4))));
    assertEquals(
        WorldRefusal.BAD_MESH, refusalOf(Worlds.empty().addMeshes(good.toBuilder().addIndices(0))));
    assertEquals(WorldRefusal.BAD_MESH,
        refusalOf(Worlds.empty().addMeshes(good.toBuilder().setVerticesM(1, Float.NaN))));
    assertEquals(WorldRefusal.BAD_MESH,
        refusalOf(Worlds.empty().addMeshes(good.toBuilder().setVerticesM(0, -200000))));
    assertEquals(WorldRefusal.BAD_MESH,
        refusalOf(Worlds.empty().addMeshes(
            WorldProto.CollisionMesh.newBuilder().addIndices(0).addIndices(0).addIndices(0))));
  }

  @Test
  void moreThan65536TrianglesOverAllMeshesAreRefused() {
    WorldProto.CollisionMesh.Builder big = Worlds.floorMesh(0, 1).toBuilder().clearIndices();
    for (int t = 0; t < 40000; ++t) big.addIndices(0).addIndices(1).addIndices(2);
    WorldProto.CollisionMesh mesh = big.build();
    assertNull(refusalOf(Worlds.empty().addMeshes(mesh)));
    assertEquals(
        WorldRefusal.MESH_TOO_LARGE, refusalOf(Worlds.empty().addMeshes(mesh).addMeshes(mesh)));
  }

  @Test
  void everyReasonHasACounterName() {
    for (WorldRefusal reason : WorldRefusal.values()) {
      assertEquals(reason.name().toLowerCase(java.util.Locale.ROOT), reason.counterName());
    }
  }
}
