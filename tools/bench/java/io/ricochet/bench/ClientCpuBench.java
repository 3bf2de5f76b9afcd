package io.ricochet.bench;

import io.ricochet.client.GameConnection;
import io.ricochet.client.GameListener;
import io.ricochet.client.GameSnapshot;
import io.ricochet.client.GameStats;
import io.ricochet.client.MatchInfo;
import io.ricochet.client.RicochetClient;
import java.io.IOException;
import java.lang.management.ManagementFactory;
import java.lang.management.ThreadMXBean;
import java.util.List;
import java.util.Random;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicLong;

/**
 * What a whole Java client costs per second of play: it signs in to a running ricochet-server
 * (pinned), joins its first match and plays for {@code --seconds} while an input loop calls
 * setInput at {@code --rate} Hz (a render loop's cadence: running in circles, turning), then
 * prints one JSON line. The CPU time is measured after a warm-up second, over the measured
 * seconds: the JVM process's ({@code OperatingSystemMXBean.getProcessCpuTime}: JIT and GC
 * included), the client's own threads' ({@code ricochet-*}: game I/O, listener) and the input
 * loop's, each in ms of CPU per second of play; with the snapshots, RTT and prediction error the
 * client saw. tools/bench/java_decode.sh starts the server and runs it.
 *
 * <pre>
 *   java -cp ... io.ricochet.bench.ClientCpuBench --host 127.0.0.1 --control-port P --pin FP
 *        [--seconds 20] [--rate 60] [--out FILE]
 * </pre>
 */
public final class ClientCpuBench {
  private static final long WARMUP_MS = 1_000;

  private ClientCpuBench() {}

  /** Runs the bench; exits 1 when the client cannot play, 2 on bad options. */
  public static void main(String[] argv) throws Exception {
    Args args;
    try {
      args = new Args(argv, "host", "control-port", "pin", "seconds", "rate", "out");
    } catch (IllegalArgumentException e) {
      System.err.println("ClientCpuBench: " + e.getMessage());
      System.exit(2);
      return;
    }
    String host = args.text("host", "127.0.0.1");
    int port = args.integer("control-port", 7777, 1, 65535);
    String pin = args.required("pin");
    int seconds = args.integer("seconds", 20, 1, 3600);
    int rateHz = args.integer("rate", 60, 1, 1000);
    String out = args.text("out", null);

    AtomicLong snapshots = new AtomicLong();
    GameListener listener = new GameListener() {
      @Override
      public void onSnapshot(GameSnapshot snapshot) {
        snapshots.incrementAndGet();
      }
    };
    String username = "cpu_bench_" + Integer.toHexString(new Random().nextInt() & 0xFFFFFF);
    String password = "password-" + username;
    try (RicochetClient client =
             RicochetClient.builder().host(host).controlPort(port).pinSha256(pin).build()) {
      client.register(username, password).get(60, TimeUnit.SECONDS);
      client.login(username, password).get(60, TimeUnit.SECONDS);
      List<MatchInfo> matches = client.listMatches().get(60, TimeUnit.SECONDS);
      if (matches.isEmpty()) throw new IllegalStateException("the server has no match");
      GameConnection game =
          client.joinMatch(matches.get(0).matchId(), listener).get(60, TimeUnit.SECONDS);
      play(game, rateHz, WARMUP_MS, null);
      long snapshotsBefore = snapshots.get();
      Measure measure = new Measure();
      play(game, rateHz, seconds * 1000L, measure);
      long played = snapshots.get() - snapshotsBefore;
      GameStats stats = game.stats();
      boolean open = game.isOpen();
      game.close();
      double playS = measure.wallNs / 1e9;
      new JsonLine("java_client_cpu")
          .integer("seconds", seconds)
          .integer("input_rate_hz", rateHz)
          .number("play_s", playS, 3)
          .number("process_cpu_ms_per_s", measure.processCpuNs / 1e6 / playS, 3)
          .number("client_threads_cpu_ms_per_s", measure.clientThreadsCpuNs / 1e6 / playS, 3)
          .number("input_loop_cpu_ms_per_s", measure.inputLoopCpuNs / 1e6 / playS, 3)
          .number("snapshots_per_s", played / playS, 2)
          .number("rtt_ms", stats == null ? Double.NaN : stats.rttMs(), 2)
          .number(
              "prediction_error_p99_m", stats == null ? Double.NaN : stats.predictionErrorP99M(), 5)
          .flag("open_at_end", open)
          .integer("available_processors", Runtime.getRuntime().availableProcessors())
          .text(
              "jvm", System.getProperty("java.vm.name") + " " + System.getProperty("java.version"))
          .write(out);
      if (!open || played == 0) System.exit(1);
    } catch (IOException e) {
      System.err.println("ClientCpuBench: " + e);
      System.exit(1);
    }
  }

  /** CPU and wall time of the measured play. */
  private static final class Measure {
    long wallNs;
    long processCpuNs;
    long clientThreadsCpuNs;
    long inputLoopCpuNs;
  }

  /**
   * Calls setInput {@code rateHz} times a second for {@code durationMs} on this thread (the input
   * loop); with {@code measure}, the CPU time of the process, the client's threads and this loop
   * over that time.
   */
  private static void play(GameConnection game, int rateHz, long durationMs, Measure measure)
      throws InterruptedException {
    ThreadMXBean threads = ManagementFactory.getThreadMXBean();
    com.sun.management.OperatingSystemMXBean os =
        (com.sun.management.OperatingSystemMXBean) ManagementFactory.getOperatingSystemMXBean();
    long processBefore = os.getProcessCpuTime();
    long clientBefore = clientThreadsCpuNs(threads);
    long loopBefore = threads.getCurrentThreadCpuTime();
    long start = System.nanoTime();
    long periodNs = 1_000_000_000L / rateHz;
    long frames = durationMs * rateHz / 1000;
    for (long frame = 0; frame < frames; ++frame) {
      double t = frame / (double) rateHz;
      game.setInput((float) Math.sin(t), 1, (float) (0.5 * t), 0, frame % 120 < 10 ? 1 : 0, 0);
      long next = start + (frame + 1) * periodNs;
      long waitNs = next - System.nanoTime();
      if (waitNs > 0) TimeUnit.NANOSECONDS.sleep(waitNs);
    }
    if (measure == null) return;
    measure.wallNs = System.nanoTime() - start;
    measure.processCpuNs = os.getProcessCpuTime() - processBefore;
    measure.clientThreadsCpuNs = clientThreadsCpuNs(threads) - clientBefore;
    measure.inputLoopCpuNs = threads.getCurrentThreadCpuTime() - loopBefore;
  }

  /** The CPU time of the live threads named "ricochet-*" (the library's), ns. */
  private static long clientThreadsCpuNs(ThreadMXBean threads) {
    long total = 0;
    for (java.lang.management.ThreadInfo info : threads.getThreadInfo(threads.getAllThreadIds())) {
      if (info == null || !info.getThreadName().startsWith("ricochet-")) continue;
      long cpu = threads.getThreadCpuTime(info.getThreadId());
      if (cpu > 0) total += cpu;
    }
    return total;
  }
}
