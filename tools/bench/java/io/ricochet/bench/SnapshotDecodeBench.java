package io.ricochet.bench;

import io.ricochet.client.core.snapshot.QuantizationSpec;
import io.ricochet.client.core.snapshot.SnapshotDecoder;
import io.ricochet.wire.SnapshotProto.Quantization;
import io.ricochet.wire.SnapshotProto.Snapshot;
import java.io.IOException;
import java.lang.management.ManagementFactory;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Paths;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;

/**
 * The Java client's snapshot decoder on a recorded stream, tests/vectors/snapshots_*.txt: the
 * same bytes, rounds, tick shifts and fields as the C++ snapshot-decode-bench
 * (tools/bench/snapshot_decode_bench.cpp), so tools/bench/java_decode.sh can put the two side by
 * side in one run. Each decode of a snapshot's entity bytes (parsed from the message once, as the
 * C++ side parses its messages outside the timing) is timed with System.nanoTime; percentiles are
 * nearest rank. allocated_bytes_per_snapshot is what the decoding thread allocated over the
 * measured rounds (com.sun.management.ThreadMXBean.getThreadAllocatedBytes), per snapshot: 0 once
 * warm is the bar, checked by SnapshotAllocationTest.
 *
 * <pre>
 *   java -cp ... io.ricochet.bench.SnapshotDecodeBench --vectors FILE [--rounds 200]
 *        [--warmup-rounds 100] [--out FILE]
 * </pre>
 */
public final class SnapshotDecodeBench {
  private static final long ROUND_TICKS = 1L << 20; // a multiple of the 64-slot ring

  private SnapshotDecodeBench() {}

  /** Runs the bench; exits 1 when a snapshot is refused, 2 on bad options or input. */
  public static void main(String[] argv) throws IOException {
    Args args;
    try {
      args = new Args(argv, "vectors", "rounds", "warmup-rounds", "out");
      run(args.required("vectors"), args.integer("rounds", 200, 1, 3000),
          args.integer("warmup-rounds", 100, 0, 1000), args.text("out", null));
    } catch (IllegalArgumentException e) {
      System.err.println("SnapshotDecodeBench: " + e.getMessage());
      System.exit(2);
    }
  }

  private static void run(String vectors, int rounds, int warmupRounds, String out)
      throws IOException {
    QuantizationSpec spec = null;
    String scene = null;
    long entities = 0;
    List<Snapshot> snapshots = new ArrayList<>();
    for (String line : Files.readAllLines(Paths.get(vectors), StandardCharsets.UTF_8)) {
      if (line.startsWith("spec ")) {
        spec = QuantizationSpec.fromWire(Quantization.parseFrom(hex(field(line, "bytes"))));
        scene = field(line, "scene");
        entities = Long.parseLong(field(line, "entities"));
      } else if (line.startsWith("snapshot ")) {
        snapshots.add(Snapshot.parseFrom(hex(field(line, "bytes"))));
      }
    }
    if (spec == null || snapshots.isEmpty()) {
      throw new IllegalArgumentException(vectors + ": no usable spec or no snapshot");
    }
    int n = snapshots.size();
    long[] ticks = new long[n];
    long[] ages = new long[n];
    byte[][] bytes = new byte[n][];
    for (int i = 0; i < n; ++i) {
      ticks[i] = snapshots.get(i).getTick() & 0xFFFFFFFFL;
      ages[i] = snapshots.get(i).getBaselineAge() & 0xFFFFFFFFL;
      bytes[i] = snapshots.get(i).getEntities().toByteArray();
    }

    com.sun.management.ThreadMXBean threads =
        (com.sun.management.ThreadMXBean) ManagementFactory.getThreadMXBean();
    threads.setThreadAllocatedMemoryEnabled(true);
    long self = Thread.currentThread().getId();
    SnapshotDecoder decoder = new SnapshotDecoder(spec);
    double[] samplesUs = new double[rounds * n];
    int samples = 0;
    long refused = 0;
    long cpuNs = 0;
    long allocated = 0;
    double wallUs = 0;
    for (int round = 0; round < warmupRounds + rounds; ++round) {
      boolean measured = round >= warmupRounds;
      long offset = round * ROUND_TICKS;
      long allocatedBefore = threads.getThreadAllocatedBytes(self);
      long cpuBefore = threads.getCurrentThreadCpuTime();
      for (int i = 0; i < n; ++i) {
        long start = System.nanoTime();
        boolean ok = decoder.decode(
            (ticks[i] + offset) & 0xFFFFFFFFL, ages[i], bytes[i], 0, bytes[i].length);
        long elapsed = System.nanoTime() - start;
        if (!ok) ++refused;
        if (measured) {
          samplesUs[samples++] = elapsed / 1e3;
          wallUs += elapsed / 1e3;
        }
      }
      if (measured) {
        cpuNs += threads.getCurrentThreadCpuTime() - cpuBefore;
        allocated += threads.getThreadAllocatedBytes(self) - allocatedBefore;
      }
    }
    double[] sorted = Arrays.copyOf(samplesUs, samples);
    Arrays.sort(sorted);
    new JsonLine("snapshot_decode")
        .text("lang", "java")
        .text("scene", scene)
        .integer("entities", entities)
        .integer("stream_snapshots", n)
        .integer("rounds", rounds)
        .integer("warmup_rounds", warmupRounds)
        .number("decode_us", wallUs / samples, 3)
        .number("decode_us_p50", Percentiles.ofSorted(sorted, samples, 50), 3)
        .number("decode_us_p99", Percentiles.ofSorted(sorted, samples, 99), 3)
        .number("decode_us_min", sorted[0], 3)
        .number("cpu_us_per_snapshot", cpuNs / 1e3 / samples, 3)
        .number("allocated_bytes_per_snapshot", (double) allocated / samples, 3)
        .integer("refused", refused)
        .text("jvm", System.getProperty("java.vm.name") + " " + System.getProperty("java.version"))
        .write(out);
    if (refused > 0) System.exit(1);
  }

  /** The value of {@code key=} in a record line of a vector file. */
  private static String field(String line, String key) {
    for (String part : line.split(" ")) {
      if (part.startsWith(key + "=")) return part.substring(key.length() + 1);
    }
    throw new IllegalArgumentException("no " + key + " in " + line);
  }

  private static byte[] hex(String text) {
    if (text.length() % 2 != 0) throw new IllegalArgumentException("odd hex length");
    byte[] bytes = new byte[text.length() / 2];
    for (int i = 0; i < bytes.length; ++i) {
      bytes[i] = (byte) Integer.parseInt(text.substring(2 * i, 2 * i + 2), 16);
    }
    return bytes;
  }
}
