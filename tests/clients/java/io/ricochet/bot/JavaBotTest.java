package io.ricochet.bot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.testing.RealServer;
import io.ricochet.client.testing.ServerProcess;
import java.io.File;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.List;
import java.util.concurrent.TimeUnit;
import java.util.regex.Matcher;
import java.util.regex.Pattern;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.Timeout;
import org.junit.jupiter.api.extension.RegisterExtension;

/**
 * ricochet-java-bot as an operator runs it: {@code java -jar ricochet-java-bot.jar} (system
 * property {@code ricochet.java_bot_jar}) against the real server on loopback. It plays a match to
 * its time limit and prints one JSON line whose kills and deaths are the server's results; SIGTERM
 * prints the figures so far; a bad option exits 2.
 */
@Timeout(value = 90, unit = TimeUnit.SECONDS)
class JavaBotTest {
  private static final int TIME_LIMIT_S = 6;
  /** Sign-in (two registrations and logins), the match, its results: slack for a loaded machine. */
  private static final long PLAY_LIMIT_MS = (TIME_LIMIT_S + 40) * 1000L;
  private static final String FAST_ACCOUNTS =
      "[db]\npassword_hashing = \"minimum\"\nregistrations_per_hour_per_address = 1000\n";

  /**
   * One free-for-all match of the arena that starts running when two players are in and ends
   * {@link #TIME_LIMIT_S} later.
   */
  @RegisterExtension
  final RealServer server = RealServer.starting(() -> {
    String source = System.getProperty("ricochet.source_dir", ".");
    return new ServerProcess("count = 1\nmax_players = 16\nmaps = [\"" + source
            + "/server/maps/arena.toml\"]\nseed = 42\nwarmup_s = 0\nfrag_limit = 0\n"
            + "record = false\nmin_players = 2\ntime_limit_s = " + TIME_LIMIT_S + "\n",
        "", FAST_ACCOUNTS, 30_000);
  });

  /** A running bot process: its stdout and stderr go to files. */
  private static final class BotProcess {
    final Process process;
    final Path out;
    final Path err;

    BotProcess(String... args) throws Exception {
      out = Files.createTempFile("ricochet-java-bot", ".out");
      err = Files.createTempFile("ricochet-java-bot", ".err");
      List<String> command = new ArrayList<>();
      command.add(
          System.getProperty("java.home") + File.separator + "bin" + File.separator + "java");
      command.add("-jar");
      command.add(System.getProperty("ricochet.java_bot_jar"));
      command.addAll(Arrays.asList(args));
      process = new ProcessBuilder(command)
                    .redirectOutput(out.toFile())
                    .redirectError(err.toFile())
                    .start();
    }

    int exit(long limitMs) throws Exception {
      if (!process.waitFor(limitMs, TimeUnit.MILLISECONDS)) {
        process.destroyForcibly();
        throw new AssertionError("the bot did not exit within " + limitMs + " ms: " + err());
      }
      return process.exitValue();
    }

    String out() throws Exception {
      return new String(Files.readAllBytes(out), StandardCharsets.UTF_8);
    }

    String err() throws Exception {
      return new String(Files.readAllBytes(err), StandardCharsets.UTF_8);
    }

    void cleanUp() throws Exception {
      process.destroyForcibly();
      Files.deleteIfExists(out);
      Files.deleteIfExists(err);
    }
  }

  private static String[] args(ServerProcess server, String... more) {
    List<String> all = new ArrayList<>(Arrays.asList("--host", "127.0.0.1", "--control-port",
        Integer.toString(server.controlPort()), "--pin-sha256", server.fingerprint()));
    all.addAll(Arrays.asList(more));
    return all.toArray(new String[0]);
  }

  @Test
  void twoBotsPlayAMatchToItsTimeLimitAndPrintTheServersResults() throws Exception {
    BotProcess bot = new BotProcess(args(server.get(), "--bots", "2", "--name", "jb", "--skill",
        "0.9", "--matches", "1", "--duration-s", Long.toString(PLAY_LIMIT_MS / 1000)));
    try {
      assertEquals(0, bot.exit(PLAY_LIMIT_MS + 20_000), bot.err());
      String json = bot.out();
      assertEquals(1, json.split("\n").length, "one line: " + json);
      assertTrue(json.startsWith("{\"bots\":2,\"done\":2,\"total\":{"), json);
      List<String> perBot = perBot(json);
      assertEquals(2, perBot.size(), json);
      double killsSeen = 0;
      for (int k = 0; k < 2; ++k) {
        String each = perBot.get(k);
        assertTrue(each.startsWith("{\"name\":\"jb-" + (k + 1) + "\",\"state\":\"done\","
                       + "\"error\":\"\",\"metrics\":{"),
            each);
        assertEquals(1, number(each, "matches"), each);
        // What it counted from the Kill events is what the server's MatchResults say.
        assertEquals(number(each, "result_kills"), number(each, "kills"), each);
        assertEquals(number(each, "result_deaths"), number(each, "deaths"), each);
        killsSeen += number(each, "kills");
        // It played the match: snapshots at about 60 Hz, both ways of traffic, a round trip.
        assertTrue(number(each, "snapshots") > 40 * (TIME_LIMIT_S - 1), each);
        assertTrue(number(each, "snapshots_per_s") > 40, each);
        assertTrue(number(each, "bytes_in") > 0 && number(each, "bytes_out") > 0, each);
        assertTrue(number(each, "rtt_samples") >= TIME_LIMIT_S - 2, each);
        assertTrue(number(each, "rtt_ms_p50") > 0 && number(each, "rtt_ms_p50") < 500, each);
        assertTrue(number(each, "first_snapshot_ms") > 0, each);
        // Predicting on a clean link: ricochet-bot's bound there (bot_match_test.cpp) is 0.25 m
        // (two ticks of a repeated input); the library measures 1.4-1.7 mm (PredictionPlayTest).
        assertTrue(number(each, "prediction_samples") > 100, each);
        assertTrue(number(each, "prediction_error_m_p99") < 0.25, each);
      }
      String total = json.substring(0, json.indexOf(",\"per_bot\":"));
      assertEquals(killsSeen, number(total, "kills"), total);
      assertEquals(2, number(total, "matches"), total);
    } finally {
      bot.cleanUp();
    }
  }

  @Test
  void sigtermStopsItAndPrintsTheFiguresSoFar() throws Exception {
    // The match needs two players: the one bot waits in it, getting snapshots, until SIGTERM.
    BotProcess bot = new BotProcess(args(server.get(), "--name", "stopped", "--log-level", "info"));
    try {
      long deadline = System.nanoTime() + TimeUnit.MILLISECONDS.toNanos(PLAY_LIMIT_MS);
      while (!bot.err().contains("JOINING -> PLAYING") && System.nanoTime() < deadline) {
        assertTrue(bot.process.isAlive(), bot.err());
        Thread.sleep(50);
      }
      assertTrue(bot.err().contains("JOINING -> PLAYING"), bot.err());
      Thread.sleep(1000); // about 60 snapshots
      bot.process.destroy(); // SIGTERM
      assertEquals(0, bot.exit(20_000), bot.err());
      List<String> perBot = perBot(bot.out());
      assertEquals(1, perBot.size(), bot.out());
      String each = perBot.get(0);
      assertTrue(each.contains("\"state\":\"done\",\"error\":\"\""), each);
      assertTrue(number(each, "snapshots") > 0, each);
      assertEquals(0, number(each, "matches"), each);
      assertTrue(bot.err().contains("PLAYING -> DONE (stopped by a signal)"), bot.err());
    } finally {
      bot.cleanUp();
    }
  }

  @Test
  void aBadOptionExitsTwoSayingWhatIsWrong() throws Exception {
    BotProcess bot = new BotProcess("--pin-sha256", server.get().fingerprint(), "--bots", "65");
    try {
      assertEquals(2, bot.exit(20_000));
      assertEquals("", bot.out());
      assertTrue(bot.err().contains("--bots must be 1..64, got 65"), bot.err());
    } finally {
      bot.cleanUp();
    }
  }

  /** The per_bot objects of a report line. */
  static List<String> perBot(String json) {
    List<String> objects = new ArrayList<>();
    int at = json.indexOf("\"per_bot\":[");
    if (at < 0) return objects;
    String[] parts = json.substring(at).split("(?=\\{\"name\":)");
    for (int i = 1; i < parts.length; ++i) objects.add(parts[i]);
    return objects;
  }

  /** The number after {@code "key":} in {@code json} (the first); fails when there is none. */
  static double number(String json, String key) {
    Matcher match = Pattern.compile("\"" + key + "\":(-?[0-9.]+)").matcher(json);
    assertTrue(match.find(), key + " in " + json);
    return Double.parseDouble(match.group(1));
  }
}
