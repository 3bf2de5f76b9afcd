package io.ricochet.client;

import static io.ricochet.client.ClientTesting.await;
import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.testing.BadLinkRelay;
import io.ricochet.client.testing.ServerProcess;
import io.ricochet.client.testing.Vectors;
import java.util.List;
import java.util.Locale;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.Timeout;

/**
 * Prediction behind a bad mobile link, against the real server on loopback: the client's game
 * datagrams pass a {@link BadLinkRelay} with 20 % loss each way and 150 ± 50 ms one way (the
 * issue's link, the same figures as the C++ bot's bad-link test in
 * tests/integration/bot_match_test.cpp), seeded. The player runs, turns, strafes and jumps for 12
 * s in the arena map (floor, walls, boxes, a ramp mesh). It must still play (snapshots keep
 * arriving, the server keeps applying its inputs, the player moves) and its prediction error p99
 * must stay under {@link #BAD_LINK_P99_BOUND_M}.
 *
 * <p>The bound. The Java prediction computes exactly what the match computes for the same inputs
 * at the same ticks (MovementVectorsTest: every tick bit for bit), so what the link adds is only
 * the server's jitter buffer changing which input it applies at which tick: an input that arrives
 * after its tick makes the server repeat the one before, the burst after it makes the server skip
 * one (PROTOCOL.md, the jitter buffer; counted as inputs off tick). Each repeat or skip shifts the
 * player along its path by one tick, at most max_speed · dt = 7 m/s / 60 Hz = 0.117 m, and at most
 * one happens per server tick. An acknowledged input's error counts the shifts since the snapshot
 * its prediction was last replayed from, so at most 0.117 m per tick between the two snapshots
 * the client applied. Snapshots (60 Hz) are lost 20 % of the time, and ±50 ms of jitter against
 * 16.7 ms between them makes about as many arrive after a newer one (refused as stale): about
 * half are applied, so a gap of k ticks has probability ~0.5^(k-1) and its 99th percentile is 1 +
 * ln(0.01)/ln(0.5) ≈ 8 ticks: 8 · 0.117 m = 0.94 m, so 1.0 m (the C++ bot's bound, from the
 * same argument). The test checks the premise too: at least {@link #MIN_APPLIED_FRACTION} of the
 * snapshots sent are applied, and the error is measured on at least 200 inputs.
 */
@Timeout(value = 90, unit = TimeUnit.SECONDS)
class PredictionBadLinkTest {
  private static final double BAD_LINK_P99_BOUND_M = 1.0;
  private static final double LOSS = 0.2;
  private static final double LATENCY_MS = 150;
  private static final double JITTER_MS = 50;
  private static final long SEED = 30;
  private static final int PHASES = 48; // of 250 ms: 12 s of play
  private static final double MIN_APPLIED_FRACTION = 0.35;
  private static final long WAIT_MS = ClientTesting.WAIT_MS;

  /** What the listener saw. */
  private static final class Recorder implements GameListener {
    final CountDownLatch firstPrediction = new CountDownLatch(1);
    final List<GameStats> stats = new CopyOnWriteArrayList<>();
    volatile int snapshots;
    volatile long lastInputSequence;
    volatile long firstTick = -1;
    volatile long lastTick;
    volatile double travelledM;
    private float[] previous;

    @Override
    public void onSnapshot(GameSnapshot snapshot) {
      ++snapshots;
      if (firstTick < 0) firstTick = snapshot.tick();
      lastTick = snapshot.tick();
      lastInputSequence = snapshot.lastInputSequence();
      int own = snapshot.indexOf(snapshot.yourEntityId());
      if (own >= 0) {
        float[] now = {
            snapshot.positionM(own, 0), snapshot.positionM(own, 1), snapshot.positionM(own, 2)};
        if (previous != null) {
          double sum = 0;
          for (int a = 0; a < 3; ++a) sum += (now[a] - previous[a]) * (now[a] - previous[a]);
          travelledM += Math.sqrt(sum);
        }
        previous = now;
      }
      if (snapshot.predicting()) firstPrediction.countDown();
    }

    @Override
    public void onStats(GameStats figures) {
      stats.add(figures);
    }
  }

  @Test
  void aPlayerBehindABadLinkStillPlaysWithABoundedPredictionError() throws Exception {
    String source = System.getProperty("ricochet.source_dir", ".");
    String matches = "count = 1\nmax_players = 4\nmaps = [\"" + source
        + "/server/maps/arena.toml\"]\nseed = 3\nwarmup_s = 0\nfrag_limit = 0\n"
        + "min_players = 1\ntime_limit_s = 120\n";
    Recorder recorder = new Recorder();
    BadLinkRelay relay;
    try (ServerProcess server =
             new ServerProcess(matches, "", ClientTesting.FAST_ACCOUNTS, WAIT_MS)) {
      relay = new BadLinkRelay(server.gamePort(), LOSS, LATENCY_MS, JITTER_MS, SEED);
      RicochetClient client = ClientTesting.signedIn(server, "java_bad_link");
      try {
        long matchId = await(client.listMatches()).get(0).matchId();
        JoinTicket direct = await(client.joinMatch(matchId));
        // The join reply's world is the one the movement vectors were made with.
        Vectors.Record world = Vectors.read("movement_arena").get(0);
        assertArrayEquals(world.bytes("bytes"), direct.collisionWorldBytes(),
            "the server's collision world of arena differs from tests/vectors/movement_arena.txt");
        // The same ticket, sent to the relay's port instead of the server's.
        String[] why = new String[1];
        JoinTicket viaRelay =
            JoinTicket.of("127.0.0.1", direct.reply().toBuilder().setUdpPort(relay.port()).build(),
                direct.receivedAtMs(), why);
        assertNotNull(viaRelay, why[0]);
        GameConnection game = await(client.connectGame(viaRelay, recorder));
        assertTrue(recorder.firstPrediction.await(WAIT_MS, TimeUnit.MILLISECONDS),
            "never predicted: " + game.stats());
        long firstInput = recorder.lastInputSequence;
        play(game);
        Thread.sleep(1500); // the last inputs' acknowledgements, and one more stats period
        game.close();
        assertTrue(recorder.lastInputSequence - firstInput > 0.5 * PHASES * 0.25 * 60,
            "the server applied inputs " + firstInput + ".." + recorder.lastInputSequence);
      } finally {
        client.close();
        relay.close();
      }
    }
    assertNull(relay.failure(), "the relay failed");
    assertTrue(relay.up.dropped.get() > 0 && relay.down.dropped.get() > 0,
        "up: " + relay.up + ", down: " + relay.down);
    report(recorder, relay);
  }

  /** Run, turn while running, strafe, jump, stop: 48 phases of 250 ms (paced, not waited on). */
  private static void play(GameConnection game) throws InterruptedException {
    float yaw = 0;
    for (int phase = 0; phase < PHASES; ++phase) {
      switch (phase % 8) {
        case 0:
          game.setInput(0f, 1f, yaw, 0f, 0, 0);
          break;
        case 1:
          yaw += 0.8f;
          game.setInput(0f, 1f, yaw, 0f, GameConnection.BUTTON_JUMP, 0);
          break;
        case 2:
          game.setInput(1f, 0.5f, yaw, 0f, 0, 0);
          break;
        case 3:
          yaw -= 1.6f;
          game.setInput(0f, 1f, yaw, 0f, 0, 0);
          break;
        case 4:
          game.setInput(-1f, 1f, yaw, 0f, GameConnection.BUTTON_JUMP, 0);
          break;
        case 5:
          yaw += 2.5f;
          game.setInput(0f, 1f, yaw, 0f, 0, 0);
          break;
        case 6:
          game.setInput(0.3f, -1f, yaw, 0f, 0, 0);
          break;
        default:
          game.setInput(0f, 0f, yaw, 0f, 0, 0);
          break;
      }
      Thread.sleep(250);
    }
  }

  private static void report(Recorder recorder, BadLinkRelay relay) {
    assertTrue(recorder.stats.size() >= 5, "stats periods: " + recorder.stats.size());
    GameStats last = recorder.stats.get(recorder.stats.size() - 1);
    int samples = 0;
    long offTick = 0;
    double worstMax = 0;
    StringBuilder periods = new StringBuilder();
    for (GameStats period : recorder.stats) {
      assertTrue(period.predicting(), "not predicting: " + period);
      assertNull(period.collisionWorldRefusal());
      samples += period.predictionErrorSamples();
      offTick += period.inputsOffTick();
      worstMax = Math.max(worstMax, period.predictionErrorMaxM());
      periods.append(String.format(Locale.ROOT,
          " [n=%d p50=%.4f p99=%.4f max=%.4f off-tick=%d snapshots/s=%.1f]",
          period.predictionErrorSamples(), period.predictionErrorP50M(),
          period.predictionErrorP99M(), period.predictionErrorMaxM(), period.inputsOffTick(),
          period.snapshotsPerSecond()));
    }
    long ticks = recorder.lastTick - recorder.firstTick;
    double applied = ticks > 0 ? (double) recorder.snapshots / ticks : 0;
    String summary = String.format(Locale.ROOT,
        "bad link: prediction error p99 %.4f m over the play (bound %.1f m), largest period max "
            + "%.4f m, %d samples, %d inputs off tick, %d resets; %d snapshots applied over %d "
            + "ticks (%.2f); travelled %.1f m; relay up: %s; down: %s",
        last.predictionErrorRecentP99M(), BAD_LINK_P99_BOUND_M, worstMax, samples, offTick,
        last.predictionResets(), recorder.snapshots, ticks, applied, recorder.travelledM, relay.up,
        relay.down);
    System.out.println(summary);
    System.out.println("per stats period:" + periods);
    // It still plays: snapshots keep coming, the player moves, its inputs reach the server.
    assertTrue(applied >= MIN_APPLIED_FRACTION, summary);
    assertTrue(recorder.travelledM > 20, summary);
    assertTrue(samples > 200, summary);
    assertTrue(offTick > 0, "a link this bad puts some inputs off tick: " + summary);
    // The first seed is a reset; a second would be a gap over 3 m, far past the bound.
    assertTrue(last.predictionResets() <= 2, summary);
    assertTrue(last.predictionErrorRecentP99M() < BAD_LINK_P99_BOUND_M, summary);
  }
}
