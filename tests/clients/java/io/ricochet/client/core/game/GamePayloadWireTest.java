package io.ricochet.client.core.game;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import com.google.protobuf.ByteString;
import com.google.protobuf.InvalidProtocolBufferException;
import io.ricochet.wire.GameProto.ClientPayload;
import io.ricochet.wire.GameProto.Input;
import io.ricochet.wire.GameProto.PlayerStatus;
import io.ricochet.wire.GameProto.ServerPayload;
import io.ricochet.wire.SnapshotProto.Snapshot;
import java.util.Arrays;
import java.util.Random;
import org.junit.jupiter.api.Test;

/**
 * The hand-written ClientPayload writer and ServerPayload reader against protobuf's own
 * serialiser and parser: the same bytes out, the same values in, the same refusals.
 */
class GamePayloadWireTest {
  @Test
  void clientPayloadsAreTheBytesProtobufWrites() throws Exception {
    Random random = new Random(30);
    InputHistory history = new InputHistory();
    InputState input = new InputState();
    Input[] sent = new Input[200];
    byte[] out = new byte[ClientPayloadWriter.MAX_BYTES];
    for (int n = 0; n < sent.length; ++n) {
      input.set(random.nextFloat() * 2.4f - 1.2f, n % 5 == 0 ? 0f : random.nextFloat() * 2 - 1,
          n % 7 == 0 ? -0.0f : (random.nextFloat() - 0.5f) * 20, (random.nextFloat() - 0.5f) * 4,
          random.nextInt(8), random.nextInt(10));
      long viewTick = n % 3 == 0 ? 0 : 0xFFFFFFFFL - random.nextInt(1000);
      int fraction = random.nextInt(256);
      history.push(input, viewTick, fraction);
      sent[n] = Input.newBuilder()
                    .setSequence(n + 1)
                    .setMoveRight(input.moveRight())
                    .setMoveForward(input.moveForward())
                    .setYaw(input.yaw())
                    .setPitch(input.pitch())
                    .setButtons(input.buttons())
                    .setWeaponSlot(input.weaponSlot())
                    .setViewTick((int) viewTick)
                    .setViewFraction(fraction)
                    .build();
      assertTrue(Math.abs(input.moveRight()) <= 127 && Math.abs(input.yaw()) <= Math.PI);
      assertTrue(Math.abs(input.pitch()) <= Math.PI / 2 + 1e-6);
      int count = 1 + random.nextInt(Math.min(history.held(), InputHistory.MAX_PER_PAYLOAD));
      long ack = random.nextBoolean() ? 0 : random.nextInt(Integer.MAX_VALUE) * 2L;
      ClientPayload.Builder expected = ClientPayload.newBuilder().setAckSnapshotTick((int) ack);
      for (int i = n + 1 - count; i <= n; ++i) expected.addInputs(sent[i]);
      int length = ClientPayloadWriter.write(history, count, ack, out);
      assertArrayEquals(expected.build().toByteArray(), Arrays.copyOf(out, length), "payload " + n);
    }
    assertEquals(200, history.lastSequence());
    assertTrue(history.acknowledge(150));
    assertFalse(history.acknowledge(201), "a sequence never sent");
    assertTrue(history.acknowledge(100), "an older ack is not an error");
    assertEquals(150, history.acknowledged());
  }

  @Test
  void inputStateRefusesWhatTheServerWould() {
    InputState input = new InputState();
    assertThrows(IllegalArgumentException.class, () -> input.set(Float.NaN, 0, 0, 0, 0, 0));
    assertThrows(
        IllegalArgumentException.class, () -> input.set(0, 0, Float.POSITIVE_INFINITY, 0, 0, 0));
    assertThrows(IllegalArgumentException.class, () -> input.set(0, 0, 0, 0, 8, 0));
    assertThrows(IllegalArgumentException.class, () -> input.set(0, 0, 0, 0, 0, 10));
    input.set(2f, -1f, (float) (3 * Math.PI), 3f, InputState.BUTTON_FIRE, 3);
    assertEquals(127, input.moveRight());
    assertEquals(-127, input.moveForward());
    assertEquals(Math.PI, Math.abs(input.yaw()), 1e-5);
    assertEquals((float) (Math.PI / 2), input.pitch());
  }

  @Test
  void serverPayloadsReadAsProtobufParsesThem() {
    Random random = new Random(31);
    ServerPayloadReader reader = new ServerPayloadReader();
    for (int n = 0; n < 500; ++n) {
      ServerPayload payload = randomPayload(random);
      byte[] bytes = payload.toByteArray();
      byte[] framed = new byte[bytes.length + 7];
      System.arraycopy(bytes, 0, framed, 3, bytes.length);
      assertTrue(reader.read(framed, 3, bytes.length), "payload " + n);
      assertSame(payload, reader, framed);
    }
  }

  @Test
  void unknownFieldsAreSkippedAndRepeatedMessagesMerged() throws Exception {
    ServerPayload first = ServerPayload.newBuilder()
                              .setServerTick(9)
                              .setSnapshot(Snapshot.newBuilder().setTick(9).setBaselineAge(2))
                              .setStatus(PlayerStatus.newBuilder().addAmmo(5).setHealth(40))
                              .build();
    ServerPayload second =
        ServerPayload.newBuilder()
            .setSnapshot(Snapshot.newBuilder().setEntities(ByteString.copyFrom(new byte[] {1, 2})))
            .setStatus(PlayerStatus.newBuilder().addAmmo(6).addAmmo(7))
            .build();
    byte[] unknown = {(byte) 0xA8, 0x06, (byte) 0x96, 0x01, // field 101 varint
        (byte) 0xB5, 0x06, 1, 2, 3, 4, // field 102 fixed32
        (byte) 0xBB, 0x06, (byte) 0xC0, 0x06, 0x01, (byte) 0xBC, 0x06}; // group 103 { 104: 1 }
    byte[] bytes = concat(first.toByteArray(), unknown, second.toByteArray());
    ServerPayload parsed = ServerPayload.parseFrom(bytes);
    ServerPayloadReader reader = new ServerPayloadReader();
    assertTrue(reader.read(bytes, 0, bytes.length));
    assertSame(parsed, reader, bytes);
    assertEquals(3, reader.status().ammoCount());
    assertEquals(2, reader.baselineAge());
  }

  @Test
  void refusesWhatProtobufRefusesAndNeverThrows() {
    Random random = new Random(32);
    ServerPayloadReader reader = new ServerPayloadReader();
    int refused = 0;
    for (int n = 0; n < 3000; ++n) {
      byte[] bytes = randomPayload(random).toByteArray();
      if (bytes.length == 0) continue;
      switch (n % 3) {
        case 0:
          bytes = Arrays.copyOf(bytes, random.nextInt(bytes.length));
          break;
        case 1:
          bytes[random.nextInt(bytes.length)] = (byte) random.nextInt(256);
          break;
        default:
          for (int i = 0; i < bytes.length; ++i) bytes[i] = (byte) random.nextInt(256);
      }
      ServerPayload parsed;
      try {
        parsed = ServerPayload.parseFrom(bytes);
      } catch (InvalidProtocolBufferException e) {
        parsed = null;
      }
      boolean read = reader.read(bytes, 0, bytes.length);
      assertEquals(parsed != null, read, "acceptance of " + Arrays.toString(bytes));
      if (parsed != null) {
        assertSame(parsed, reader, bytes);
      } else {
        ++refused;
        assertFalse(reader.hasSnapshot() || reader.status().present() || reader.serverTick() != 0);
      }
    }
    assertTrue(refused > 500, "refused " + refused);
  }

  private static ServerPayload randomPayload(Random random) {
    ServerPayload.Builder payload = ServerPayload.newBuilder();
    if (random.nextInt(4) != 0) {
      byte[] entities = new byte[random.nextInt(40)];
      random.nextBytes(entities);
      payload.setSnapshot(Snapshot.newBuilder()
                              .setTick(random.nextInt())
                              .setBaselineAge(random.nextInt(70))
                              .setEntities(ByteString.copyFrom(entities)));
    }
    payload.setLastInputSequence(random.nextInt()).setServerTick(random.nextInt(100000));
    payload.setYourEntityId(random.nextInt(64));
    if (random.nextInt(3) != 0) {
      PlayerStatus.Builder status = PlayerStatus.newBuilder()
                                        .setHealth(random.nextInt(101) - random.nextInt(2) * 300)
                                        .setArmor(random.nextInt(101))
                                        .setWeaponValue(random.nextInt(4))
                                        .setAlive(random.nextBoolean())
                                        .setRespawnTick(random.nextInt())
                                        .setProtectedUntilTick(random.nextInt(1000))
                                        .setTeamValue(random.nextInt(3));
      for (int i = random.nextInt(4); i > 0; --i) status.addAmmo(random.nextInt(200) - 10);
      payload.setStatus(status);
    }
    return payload.build();
  }

  private static void assertSame(ServerPayload expected, ServerPayloadReader reader, byte[] bytes) {
    assertEquals(expected.hasSnapshot(), reader.hasSnapshot());
    assertEquals(expected.getSnapshot().getTick() & 0xFFFFFFFFL, reader.snapshotTick());
    assertEquals(expected.getSnapshot().getBaselineAge() & 0xFFFFFFFFL, reader.baselineAge());
    assertArrayEquals(expected.getSnapshot().getEntities().toByteArray(),
        Arrays.copyOfRange(
            bytes, reader.entitiesOffset(), reader.entitiesOffset() + reader.entitiesLength()));
    assertEquals(expected.getLastInputSequence() & 0xFFFFFFFFL, reader.lastInputSequence());
    assertEquals(expected.getServerTick() & 0xFFFFFFFFL, reader.serverTick());
    assertEquals(expected.getYourEntityId() & 0xFFFFFFFFL, reader.yourEntityId());
    PlayerStatus status = expected.getStatus();
    assertEquals(expected.hasStatus(), reader.status().present());
    assertEquals(status.getHealth(), reader.status().health());
    assertEquals(status.getArmor(), reader.status().armor());
    assertEquals(status.getWeaponValue(), reader.status().weapon());
    assertEquals(
        Math.min(status.getAmmoCount(), io.ricochet.client.core.game.PlayerStatus.MAX_AMMO),
        reader.status().ammoCount());
    for (int i = 0; i < reader.status().ammoCount(); ++i)
      assertEquals(status.getAmmo(i), reader.status().ammo(i));
    assertEquals(status.getAlive(), reader.status().alive());
    assertEquals(status.getRespawnTick() & 0xFFFFFFFFL, reader.status().respawnTick());
    assertEquals(
        status.getProtectedUntilTick() & 0xFFFFFFFFL, reader.status().protectedUntilTick());
    assertEquals(status.getTeamValue(), reader.status().team());
  }

  private static byte[] concat(byte[]... parts) {
    int length = 0;
    for (byte[] part : parts) length += part.length;
    byte[] out = new byte[length];
    int at = 0;
    for (byte[] part : parts) {
      System.arraycopy(part, 0, out, at, part.length);
      at += part.length;
    }
    return out;
  }
}
