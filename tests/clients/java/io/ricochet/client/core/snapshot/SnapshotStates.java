package io.ricochet.client.core.snapshot;

import io.ricochet.client.testing.Vectors;
import io.ricochet.wire.SnapshotProto.Quantization;
import io.ricochet.wire.SnapshotProto.Snapshot;
import java.io.ByteArrayOutputStream;
import java.util.ArrayList;
import java.util.List;

/**
 * What tests/vectors/snapshots_*.txt hold of a decoded state, computed from a SnapshotView the
 * way tools/vectors/snapshots_vectors.cpp computes it from the C++ decoder's entities: canonical
 * bytes (42 per entity, little-endian), the dequantised floats' bits and FNV-1a 64 hashes.
 */
final class SnapshotStates {
  private SnapshotStates() {}

  /** One stream's records, parsed. */
  static final class Stream {
    final String set;
    final QuantizationSpec spec;
    final List<Vectors.Record> records;
    final List<Snapshot> snapshots = new ArrayList<>();

    Stream(String set) throws Exception {
      this.set = set;
      records = Vectors.read(set);
      Vectors.Record first = records.get(0);
      if (!first.kind.equals("spec")) throw new IllegalStateException(set + ": no spec first");
      spec = QuantizationSpec.fromWire(Quantization.parseFrom(first.bytes("bytes")));
      if (spec == null) throw new IllegalStateException(set + ": unusable spec");
      for (Vectors.Record record : records) {
        if (record.kind.equals("snapshot"))
          snapshots.add(Snapshot.parseFrom(record.bytes("bytes")));
      }
    }
  }

  static byte[] canonicalBytes(SnapshotView view) {
    ByteArrayOutputStream out = new ByteArrayOutputStream(42 * view.count());
    for (int i = 0; i < view.count(); ++i) {
      putLe(out, (int) view.id(i), 4);
      for (int a = 0; a < 3; ++a) putLe(out, view.positionSteps(i, a), 4);
      for (int a = 0; a < 3; ++a) putLe(out, view.velocitySteps(i, a), 4);
      putLe(out, view.orientationLargest(i), 1);
      for (int k = 0; k < 3; ++k) putLe(out, view.orientationSteps(i, k), 4);
      putLe(out, view.flags(i), 1);
    }
    return out.toByteArray();
  }

  static byte[] dequantizedBytes(SnapshotView view) {
    ByteArrayOutputStream out = new ByteArrayOutputStream(40 * view.count());
    float[] xyzw = new float[4];
    for (int i = 0; i < view.count(); ++i) {
      for (int a = 0; a < 3; ++a) putLe(out, Float.floatToRawIntBits(view.positionM(i, a)), 4);
      for (int a = 0; a < 3; ++a) putLe(out, Float.floatToRawIntBits(view.velocityMps(i, a)), 4);
      view.orientation(i, xyzw);
      for (float f : xyzw) putLe(out, Float.floatToRawIntBits(f), 4);
    }
    return out.toByteArray();
  }

  static byte[] fnv1a64(byte[] bytes) {
    long hash = 0xcbf29ce484222325L;
    for (byte b : bytes) {
      hash ^= b & 0xFF;
      hash *= 0x100000001b3L;
    }
    byte[] out = new byte[8];
    for (int k = 0; k < 8; ++k) out[k] = (byte) (hash >>> (56 - 8 * k));
    return out;
  }

  private static void putLe(ByteArrayOutputStream out, int value, int bytes) {
    for (int k = 0; k < bytes; ++k) out.write(value >>> (8 * k));
  }
}
