package io.ricochet.client.core.predict;

import io.ricochet.wire.WorldProto;

/** Collision worlds for the prediction tests, built as a join reply would carry them. */
final class Worlds {
  private Worlds() {}

  /** The sample server's body, gravity and movement rules, no shapes. */
  static WorldProto.CollisionWorld.Builder empty() {
    return WorldProto.CollisionWorld.newBuilder()
        .setPlayerRadiusM(0.4f)
        .setPlayerMassKg(80)
        .addGravityMps2(0)
        .addGravityMps2(-9.81f)
        .addGravityMps2(0)
        .setMovement(WorldProto.MovementRules.newBuilder()
                         .setMaxSpeedMps(7)
                         .setGroundAcceleration(10)
                         .setAirAcceleration(1)
                         .setFriction(6)
                         .setStopSpeedMps(2)
                         .setJumpSpeedMps(5)
                         .setGroundMaxSlopeDeg(50)
                         .setGroundProbeM(0.05f));
  }

  static WorldProto.CollisionPlane plane(float nx, float ny, float nz, float offsetM) {
    return WorldProto.CollisionPlane.newBuilder()
        .addNormal(nx)
        .addNormal(ny)
        .addNormal(nz)
        .setOffsetM(offsetM)
        .build();
  }

  static WorldProto.CollisionBox box(float cx, float cy, float cz, float hx, float hy, float hz) {
    return WorldProto.CollisionBox.newBuilder()
        .addCenterM(cx)
        .addCenterM(cy)
        .addCenterM(cz)
        .addOrientation(0)
        .addOrientation(0)
        .addOrientation(0)
        .addOrientation(1)
        .addHalfExtentsM(hx)
        .addHalfExtentsM(hy)
        .addHalfExtentsM(hz)
        .build();
  }

  /** A square of two triangles at height y, ±half m in x and z. */
  static WorldProto.CollisionMesh floorMesh(float y, float half) {
    return WorldProto.CollisionMesh.newBuilder()
        .addVerticesM(-half)
        .addVerticesM(y)
        .addVerticesM(-half)
        .addVerticesM(half)
        .addVerticesM(y)
        .addVerticesM(-half)
        .addVerticesM(half)
        .addVerticesM(y)
        .addVerticesM(half)
        .addVerticesM(-half)
        .addVerticesM(y)
        .addVerticesM(half)
        .addIndices(0)
        .addIndices(2)
        .addIndices(1)
        .addIndices(0)
        .addIndices(3)
        .addIndices(2)
        .build();
  }

  static CollisionWorld of(WorldProto.CollisionWorld.Builder builder) {
    CollisionWorld world = CollisionWorld.parse(builder.build().toByteArray());
    if (world.refusal() != null) throw new AssertionError("refused: " + world.refusal());
    return world;
  }
}
