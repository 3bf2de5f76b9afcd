package io.ricochet.client.core.predict;

/**
 * Why a join reply's collision world was refused (PROTOCOL.md The collision world): the client
 * then does not predict. One reason per rule of the protocol's table; {@link #counterName} is the
 * name a client's stats report it under.
 */
public enum WorldRefusal {
  /** The bytes are not a CollisionWorld message. */
  MALFORMED("malformed"),
  /** More than 16 planes, 1024 boxes or 64 meshes. */
  TOO_MANY_SHAPES("too_many_shapes"),
  /** A plane's normal is not three finite values, or is zero; or its offset is out of range. */
  BAD_PLANE("bad_plane"),
  /** A box's centre, orientation (a unit quaternion) or half extents are out of range. */
  BAD_BOX("bad_box"),
  /** A mesh's vertices or indices break the rules. */
  BAD_MESH("bad_mesh"),
  /** More than 65 536 vertices or 65 536 triangles over all meshes. */
  MESH_TOO_LARGE("mesh_too_large"),
  /** The player radius is not 0.05..5 m or the mass not 1..10 000 kg. */
  BAD_BODY("bad_body"),
  /** Gravity is not three finite values of length at most 100 m/s². */
  BAD_GRAVITY("bad_gravity"),
  /** The movement rules are missing or a field is out of its range. */
  BAD_MOVEMENT("bad_movement");

  private final String counterName;

  WorldRefusal(String counterName) {
    this.counterName = counterName;
  }

  /** The name stats report this reason under. */
  public String counterName() {
    return counterName;
  }
}
