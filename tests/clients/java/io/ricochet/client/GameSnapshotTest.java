package io.ricochet.client;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.core.game.ServerPayloadReader;
import io.ricochet.client.core.snapshot.QuantizationSpec;
import io.ricochet.client.core.snapshot.SnapshotDecoder;
import io.ricochet.client.core.snapshot.SnapshotView;
import io.ricochet.client.testing.Vectors;
import io.ricochet.wire.GameProto.PlayerStatus;
import io.ricochet.wire.GameProto.ServerPayload;
import io.ricochet.wire.SnapshotProto.Quantization;
import io.ricochet.wire.SnapshotProto.Snapshot;
import java.util.List;
import org.junit.jupiter.api.Test;

/**
 * The pooled copy the listener gets holds what the decoder's view and the payload held: every
 * entity's integers and values, the own player's status, snapshot after snapshot of the 64-player
 * and 901-sphere vector streams (its tables growing past their first 16 entities).
 */
class GameSnapshotTest {
  @Test
  void aFilledSnapshotEqualsTheViewAndThePayload() throws Exception {
    for (String set : new String[] {"snapshots_players64", "snapshots_spheres901"}) {
      List<Vectors.Record> records = Vectors.read(set);
      QuantizationSpec spec =
          QuantizationSpec.fromWire(Quantization.parseFrom(records.get(0).bytes("bytes")));
      SnapshotDecoder decoder = new SnapshotDecoder(spec);
      ServerPayloadReader reader = new ServerPayloadReader();
      GameSnapshot copy = new GameSnapshot(spec);
      int compared = 0;
      for (Vectors.Record record : records) {
        if (!record.kind.equals("snapshot")) continue;
        Snapshot snapshot = Snapshot.parseFrom(record.bytes("bytes"));
        assertTrue(decoder.decode(snapshot), set);
        byte[] payload = ServerPayload.newBuilder()
                             .setServerTick(snapshot.getTick())
                             .setYourEntityId(compared + 1)
                             .setLastInputSequence(compared * 3)
                             .setStatus(PlayerStatus.newBuilder()
                                            .setHealth(compared % 101)
                                            .setArmor(7)
                                            .setWeaponValue(2)
                                            .addAmmo(compared)
                                            .addAmmo(4)
                                            .setAlive(compared % 2 == 0)
                                            .setRespawnTick(compared + 100)
                                            .setProtectedUntilTick(compared + 50)
                                            .setTeamValue(1))
                             .build()
                             .toByteArray();
        assertTrue(reader.read(payload, 0, payload.length));
        copy.fill(decoder.view(), reader);
        assertSame(decoder.view(), reader, copy);
        ++compared;
      }
      assertTrue(compared > 10, set + ": " + compared);
    }
  }

  private static void assertSame(
      SnapshotView view, ServerPayloadReader payload, GameSnapshot copy) {
    assertEquals(view.tick(), copy.tick());
    assertEquals(view.count(), copy.count());
    float[] expected = new float[4];
    float[] actual = new float[4];
    for (int i = 0; i < view.count(); ++i) {
      assertEquals(view.id(i), copy.id(i));
      assertEquals(i, copy.indexOf(view.id(i)));
      for (int a = 0; a < 3; ++a) {
        assertEquals(view.positionSteps(i, a), copy.positionSteps(i, a));
        assertEquals(view.positionM(i, a), copy.positionM(i, a));
        assertEquals(view.velocityMps(i, a), copy.velocityMps(i, a));
      }
      view.orientation(i, expected);
      copy.orientation(i, actual);
      assertArrayEquals(expected, actual);
      assertEquals(view.flags(i), copy.flags(i));
    }
    assertEquals(-1, copy.indexOf(0x1_0000_0000L));
    assertThrows(IndexOutOfBoundsException.class, () -> copy.id(view.count()));
    assertEquals(payload.yourEntityId(), copy.yourEntityId());
    assertEquals(payload.lastInputSequence(), copy.lastInputSequence());
    assertTrue(copy.status().present());
    assertEquals(payload.status().health(), copy.status().health());
    assertEquals(7, copy.status().armor());
    assertEquals(2, copy.status().weapon());
    assertEquals(2, copy.status().ammoCount());
    assertEquals(payload.status().ammo(0), copy.status().ammo(0));
    assertEquals(4, copy.status().ammo(1));
    assertThrows(IndexOutOfBoundsException.class, () -> copy.status().ammo(2));
    assertEquals(payload.status().alive(), copy.status().alive());
    assertEquals(payload.status().respawnTick(), copy.status().respawnTick());
    assertEquals(payload.status().protectedUntilTick(), copy.status().protectedUntilTick());
    assertEquals(1, copy.status().team());
    assertFalse(copy.count() > 0 && copy.indexOf(copy.id(copy.count() - 1)) != copy.count() - 1);
  }
}
