package io.ricochet.bot;

import io.ricochet.client.PinStore;
import java.nio.file.Paths;
import java.util.ArrayList;
import java.util.List;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.Executors;
import java.util.concurrent.Future;
import java.util.concurrent.ScheduledExecutorService;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicBoolean;

/**
 * ricochet-java-bot: N headless players on the Java client library ({@code io.ricochet.client},
 * its public API only), as ricochet-bot is on proto/'s public headers. Each bot is its own {@link
 * RicochetClient}; every callback of every bot runs on one loop thread. It prints one JSON line of
 * figures when it stops: after --matches match results, at the end of --duration-s, or on SIGINT
 * or SIGTERM (a shutdown hook). Exit code 0; 1 when a bot failed; 2 for a bad option.
 */
public final class Main {
  private static final long STOP_WAIT_MS = 15_000;
  private static final long REPORT_WAIT_MS = 5_000;

  private Main() {}

  /** Runs the bots of the command line {@code args} (see {@link BotOptions#USAGE}). */
  public static void main(String[] args) throws InterruptedException {
    BotOptions options;
    try {
      options = BotOptions.parse(args);
    } catch (BotOptions.UsageException e) {
      System.err.println("ricochet-java-bot: " + e.getMessage() + " (--help lists the options)");
      System.exit(2);
      return;
    }
    if (options.help) {
      System.out.print(BotOptions.USAGE);
      return;
    }
    ScheduledExecutorService loop = Executors.newSingleThreadScheduledExecutor(runnable -> {
      Thread thread = new Thread(runnable, "ricochet-java-bot");
      thread.setDaemon(true);
      return thread;
    });
    PinStore pinStore =
        options.trustFile.isEmpty() ? null : new FilePinStore(Paths.get(options.trustFile));
    CountDownLatch done = new CountDownLatch(options.bots);
    List<JavaBot> bots = new ArrayList<>();
    for (int k = 1; k <= options.bots; ++k) {
      bots.add(new JavaBot(options, k, loop, pinStore, done::countDown, System.err));
    }
    AtomicBoolean reported = new AtomicBoolean();
    AtomicBoolean exiting = new AtomicBoolean();
    Thread hook = new Thread(() -> {
      if (exiting.get()) return; // main's own System.exit: it reported already
      stopAll(loop, bots, "stopped by a signal");
      awaitQuietly(done, STOP_WAIT_MS);
      report(loop, bots, reported);
      // As ricochet-bot: a stop by SIGINT or SIGTERM is a normal end (the JVM would say 143).
      Runtime.getRuntime().halt(exitCode(bots));
    }, "ricochet-java-bot-exit");
    Runtime.getRuntime().addShutdownHook(hook);
    for (int k = 0; k < bots.size(); ++k) {
      JavaBot bot = bots.get(k);
      loop.schedule(bot::start, (long) k * options.spacingMs, TimeUnit.MILLISECONDS);
    }
    boolean finished = options.durationS > 0
        ? done.await((long) (options.durationS * 1000), TimeUnit.MILLISECONDS)
        : awaitForever(done);
    if (!finished) {
      stopAll(loop, bots, "duration reached");
      awaitQuietly(done, STOP_WAIT_MS);
    }
    report(loop, bots, reported);
    exiting.set(true);
    System.exit(exitCode(bots));
  }

  /** 1 when a bot failed, else 0. */
  private static int exitCode(List<JavaBot> bots) {
    for (JavaBot bot : bots) {
      if (!bot.error().isEmpty()) return 1;
    }
    return 0;
  }

  private static boolean awaitForever(CountDownLatch done) throws InterruptedException {
    done.await();
    return true;
  }

  private static void awaitQuietly(CountDownLatch done, long limitMs) {
    try {
      done.await(limitMs, TimeUnit.MILLISECONDS);
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
    }
  }

  private static void stopAll(ScheduledExecutorService loop, List<JavaBot> bots, String why) {
    for (JavaBot bot : bots) loop.execute(() -> bot.stop(why));
  }

  /**
   * Prints the JSON line once (made on the loop, where the bots' figures live); a second caller
   * (main and the shutdown hook, racing) returns once it is printed.
   */
  private static synchronized void report(
      ScheduledExecutorService loop, List<JavaBot> bots, AtomicBoolean reported) {
    if (reported.getAndSet(true)) return;
    String json;
    try {
      Future<String> made = loop.submit(() -> Report.json(bots));
      json = made.get(REPORT_WAIT_MS, TimeUnit.MILLISECONDS);
    } catch (Exception e) {
      json = Report.json(bots); // the loop is stuck: read what is there
    }
    System.out.println(json);
    System.out.flush();
  }
}
