package io.ricochet.client;

import static io.ricochet.client.ClientTesting.await;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.core.snapshot.EntityFlags;
import io.ricochet.client.testing.RealServer;
import io.ricochet.client.testing.ServerProcess;
import io.ricochet.wire.ControlProto.MatchResults;
import io.ricochet.wire.ControlProto.PlayerMatchResult;
import io.ricochet.wire.GameProto.GameEvent;
import io.ricochet.wire.GameProto.MatchEndReason;
import io.ricochet.wire.GameProto.MatchPhase;
import java.io.File;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.HashMap;
import java.util.List;
import java.util.Map;
import java.util.Random;
import java.util.TreeMap;
import java.util.concurrent.ConcurrentHashMap;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicReference;
import java.util.regex.Matcher;
import java.util.regex.Pattern;
import org.junit.jupiter.api.BeforeAll;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.Timeout;
import org.junit.jupiter.api.extension.RegisterExtension;

/**
 * A Java client and a {@code ricochet-bot} (the C++ client, a child process) in one recorded match
 * on the real server, played to its time limit. At every tick both received, the positions each
 * decoded for both players agree within the 1 mm grid (the bot writes what it decoded with {@code
 * --dump-states}); and the client's {@link RicochetClient.Listener#onMatchResults} carries this
 * player's kills, deaths and score as the server's recording replays them ({@code ricochet-replay
 * --json}), and the kills the client saw in the Kill events.
 */
@Timeout(value = 150, unit = TimeUnit.SECONDS)
class ClientAndBotMatchTest {
  private static final int TIME_LIMIT_S = 10;
  private static final long WAIT_MS = ClientTesting.WAIT_MS;
  /** Half the quantisation step: two decoders of one snapshot agree to the bit, or fail this. */
  private static final double GRID_M = 0.0006;

  /** The match starts running when both are in, and ends {@link #TIME_LIMIT_S} later. */
  @RegisterExtension
  static final RealServer server = RealServer.starting(() -> {
    String source = System.getProperty("ricochet.source_dir", ".");
    return new ServerProcess("count = 1\nmax_players = 16\nmaps = [\"" + source
            + "/server/maps/arena.toml\"]\nseed = 42\nwarmup_s = 0\nfrag_limit = 0\n"
            + "record = true\nmin_players = 2\ntime_limit_s = " + TIME_LIMIT_S + "\n",
        "", ClientTesting.FAST_ACCOUNTS, WAIT_MS);
  });

  /** Tick to entity to x, y, z: every player of every snapshot the Java client decoded. */
  private static final Map<Long, Map<Long, float[]>> clientSaw = new ConcurrentHashMap<>();
  /** The same, as the bot decoded it (its --dump-states file). */
  private static Map<Long, Map<Long, float[]>> botSaw;
  private static MatchResults results;
  private static Session session;
  private static String replayJson;
  private static String botJson;
  private static int killsSeen;
  private static int deathsSeen;

  /** What the client sees: every player's decoded position, and the Kill events that count. */
  private static final class Watcher implements GameListener {
    final CountDownLatch firstSnapshot = new CountDownLatch(1);
    volatile long ownEntity;
    private MatchPhase phase = MatchPhase.MATCH_PHASE_UNSPECIFIED;

    @Override
    public void onSnapshot(GameSnapshot snapshot) {
      Map<Long, float[]> players = new HashMap<>();
      for (int i = 0; i < snapshot.count(); ++i) {
        if (EntityFlags.kind(snapshot.flags(i)) != EntityFlags.KIND_PLAYER) continue;
        players.put(snapshot.id(i),
            new float[] {
                snapshot.positionM(i, 0), snapshot.positionM(i, 1), snapshot.positionM(i, 2)});
      }
      clientSaw.put(snapshot.tick(), players);
      ownEntity = snapshot.yourEntityId();
      firstSnapshot.countDown();
    }

    @Override
    public void onEvent(GameEvent event) {
      if (event.getEventCase() == GameEvent.EventCase.MATCH_STATE) {
        phase = event.getMatchState().getPhase();
      } else if (event.getEventCase() == GameEvent.EventCase.KILL
          && phase == MatchPhase.MATCH_PHASE_RUNNING && ownEntity != 0) {
        // Counted as the bots count them: in the running phase, where the match counts them.
        if (event.getKill().getVictimEntityId() == ownEntity) {
          ++deathsSeen;
        } else if (event.getKill().getKillerEntityId() == ownEntity) {
          ++killsSeen;
        }
      }
    }
  }

  @BeforeAll
  static void playOneMatchBesideTheBot() throws Exception {
    ServerProcess running = server.get();
    Path dir = Files.createTempDirectory("ricochet-client-and-bot");
    Path states = dir.resolve("bot-states.csv");
    List<String> command = new ArrayList<>(Arrays.asList(System.getProperty("ricochet.bot_binary"),
        "--host", "127.0.0.1", "--port", Integer.toString(running.controlPort()), "--fingerprint",
        running.fingerprint(), "--name", "cbot", "--password", "password-of-cbot", "--skill", "0.9",
        "--matches", "1", "--dump-states", states.toString(), "--duration-s", "90"));
    Process bot = new ProcessBuilder(command)
                      .redirectOutput(dir.resolve("bot.out").toFile())
                      .redirectError(dir.resolve("bot.err").toFile())
                      .start();
    try {
      AtomicReference<MatchResults> resultsCame = new AtomicReference<>();
      CountDownLatch ended = new CountDownLatch(1);
      RicochetClient client = ClientTesting.pinned(running)
                                  .listener(new RicochetClient.Listener() {
                                    @Override
                                    public void onMatchResults(MatchResults arrived) {
                                      resultsCame.set(arrived);
                                      ended.countDown();
                                    }
                                  })
                                  .build();
      Watcher watcher = new Watcher();
      try {
        await(client.register("jclient", "password-jclient"));
        session = await(client.login("jclient", "password-jclient"));
        long matchId = await(client.listMatches()).get(0).matchId();
        GameConnection game = await(client.joinMatch(matchId, watcher));
        assertTrue(watcher.firstSnapshot.await(WAIT_MS, TimeUnit.MILLISECONDS), "no snapshot");
        // Anything, changing every 100 ms (firing now and then), until the results come.
        Random random = new Random(3);
        long deadline = System.nanoTime() + TimeUnit.SECONDS.toNanos(TIME_LIMIT_S + 60);
        while (!ended.await(100, TimeUnit.MILLISECONDS) && System.nanoTime() < deadline) {
          game.setInput(random.nextFloat() * 2 - 1, random.nextFloat() * 2 - 1,
              (float) (random.nextFloat() * 2 * Math.PI), 0f,
              random.nextInt(4) == 0 ? GameConnection.BUTTON_FIRE : 0, 0);
        }
        results = resultsCame.get();
        assertNotNull(results, "no MatchResults within " + (TIME_LIMIT_S + 60) + " s");
        game.close();
      } finally {
        client.close();
      }
      assertTrue(bot.waitFor(WAIT_MS, TimeUnit.MILLISECONDS), "the bot did not exit");
      botJson = new String(Files.readAllBytes(dir.resolve("bot.out")), StandardCharsets.UTF_8);
      assertEquals(0, bot.exitValue(), botJson + read(dir.resolve("bot.err")));
      running.terminate();
      assertEquals(Integer.valueOf(0), running.waitExit(WAIT_MS), running.log());
      botSaw = readStates(states);
      replayJson = replay(running.dataDir().resolve("recordings"), dir);
    } finally {
      bot.destroyForcibly();
      for (File file : dir.toFile().listFiles()) Files.delete(file.toPath());
      Files.delete(dir);
    }
  }

  @Test
  void bothDecodeTheSamePositionsOfBothPlayersAtEveryTickBothReceived() {
    int compared = 0;
    for (Map.Entry<Long, Map<Long, float[]>> tick : new TreeMap<>(clientSaw).entrySet()) {
      Map<Long, float[]> fromBot = botSaw.get(tick.getKey());
      if (fromBot == null) continue; // a tick the bot did not receive (or before it came)
      Map<Long, float[]> fromClient = tick.getValue();
      assertEquals(fromClient.keySet(), fromBot.keySet(), "players at tick " + tick.getKey());
      for (Map.Entry<Long, float[]> player : fromClient.entrySet()) {
        float[] bot = fromBot.get(player.getKey());
        for (int a = 0; a < 3; ++a) {
          assertEquals(player.getValue()[a], bot[a], GRID_M,
              "tick " + tick.getKey() + " entity " + player.getKey() + " axis " + a);
        }
      }
      if (fromClient.size() == 2) ++compared;
    }
    // Both in the match for its whole running time, at 60 snapshots a second: most ticks compare.
    assertTrue(compared > 40 * TIME_LIMIT_S, "ticks compared with both players: " + compared);
  }

  @Test
  void onMatchResultsCarriesThisPlayersKillsDeathsAndScoreAsTheRecordingReplays() {
    assertFalse(results.getAborted());
    assertEquals(MatchEndReason.MATCH_END_REASON_TIME_LIMIT, results.getEndReason());
    assertEquals(2, results.getPlayersCount(), results.toString());
    PlayerMatchResult mine = null;
    for (PlayerMatchResult player : results.getPlayersList()) {
      if (player.getAccountId() == session.accountId()) mine = player;
    }
    assertNotNull(mine, "no result for account " + session.accountId() + ": " + results);
    assertEquals(session.username(), mine.getUsername());
    assertEquals(replayScore(session.accountId(), "kills"), mine.getKills(), replayJson);
    assertEquals(replayScore(session.accountId(), "deaths"), mine.getDeaths(), replayJson);
    assertEquals(replayScore(session.accountId(), "score"), mine.getScore(), replayJson);
    assertEquals(killsSeen, mine.getKills(), "the Kill events the client saw");
    assertEquals(deathsSeen, mine.getDeaths(), "the Kill events the client saw");
    // The bot's own count (its JSON line) is the other player's result.
    for (PlayerMatchResult player : results.getPlayersList()) {
      if (player.getAccountId() == session.accountId()) continue;
      assertEquals("cbot", player.getUsername());
      assertEquals(player.getKills(), number(botJson, "kills"), botJson);
      assertEquals(player.getDeaths(), number(botJson, "deaths"), botJson);
    }
    System.out.println("[ figures  ] " + mine.getUsername() + " kills " + mine.getKills()
        + " deaths " + mine.getDeaths() + " score " + mine.getScore() + "; bot " + botJson);
  }

  /** The number after {@code "key":} in the replay's score object of {@code account}. */
  private static long replayScore(long account, String key) {
    int at = replayJson.indexOf("{\"account\":" + account + ",");
    assertTrue(at >= 0, "account " + account + " in " + replayJson);
    return number(replayJson.substring(at), key);
  }

  private static long number(String json, String key) {
    Matcher match = Pattern.compile("\"" + key + "\":(-?[0-9]+)").matcher(json);
    assertTrue(match.find(), key + " in " + json);
    return Long.parseLong(match.group(1));
  }

  /** ricochet-bot --dump-states: "tick,entity,x,y,z" lines. */
  private static Map<Long, Map<Long, float[]>> readStates(Path file) throws Exception {
    List<String> lines = Files.readAllLines(file, StandardCharsets.UTF_8);
    assertEquals("tick,entity,x,y,z", lines.get(0));
    Map<Long, Map<Long, float[]>> states = new HashMap<>();
    for (String line : lines.subList(1, lines.size())) {
      String[] fields = line.split(",");
      states.computeIfAbsent(Long.parseLong(fields[0]), tick -> new HashMap<>())
          .put(Long.parseLong(fields[1]),
              new float[] {Float.parseFloat(fields[2]), Float.parseFloat(fields[3]),
                  Float.parseFloat(fields[4])});
    }
    return states;
  }

  /** ricochet-replay --json of the one recording in {@code recordings}; its output. */
  private static String replay(Path recordings, Path scratch) throws Exception {
    File[] files = recordings.toFile().listFiles((where, name) -> name.endsWith(".rcr"));
    assertNotNull(files, "no recordings in " + recordings);
    assertEquals(1, files.length, Arrays.toString(files));
    Path out = scratch.resolve("replay.json");
    Process replay = new ProcessBuilder(
        System.getProperty("ricochet.replay_binary"), "--json", files[0].toString())
                         .redirectErrorStream(true)
                         .redirectOutput(out.toFile())
                         .start();
    assertTrue(replay.waitFor(60, TimeUnit.SECONDS), "the replay did not end");
    String json = read(out);
    assertEquals(0, replay.exitValue(), json);
    return json;
  }

  private static String read(Path file) throws Exception {
    return new String(Files.readAllBytes(file), StandardCharsets.UTF_8);
  }
}
