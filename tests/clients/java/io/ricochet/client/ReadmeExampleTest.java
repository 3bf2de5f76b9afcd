package io.ricochet.client;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.core.transport.DisconnectReason;
import io.ricochet.client.testing.RealServer;
import io.ricochet.client.testing.ServerProcess;
import java.io.ByteArrayOutputStream;
import java.io.PrintStream;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Paths;
import java.util.concurrent.CountDownLatch;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.Test;
import org.junit.jupiter.api.extension.RegisterExtension;

/**
 * The example of clients/java/README.md, run against the real server: the README shows the
 * lines between the markers below, character for character (checked here), so it compiles and
 * works.
 */
class ReadmeExampleTest {
  @RegisterExtension
  static final RealServer realServer = RealServer.arena(ClientTesting.FAST_ACCOUNTS);

  @Test
  void theReadmesExampleSignsInJoinsAndLogsSnapshots() throws Exception {
    ByteArrayOutputStream logged = new ByteArrayOutputStream();
    PrintStream log = new PrintStream(logged, true, "UTF-8");
    ServerProcess server = realServer.get();
    String host = "127.0.0.1";
    int controlPort = server.controlPort();
    String fingerprint = server.fingerprint();
    String username = "readme_player";
    String password = "correct horse battery";
    // README example begins
    RicochetClient client = RicochetClient.builder()
                                .host(host)
                                .controlPort(controlPort)
                                .pinSha256(fingerprint) // the server logs it
                                .build();
    client.register(username, password).get(30, TimeUnit.SECONDS); // once per account
    Session session = client.login(username, password).get(30, TimeUnit.SECONDS);
    MatchInfo match = client.listMatches().get(30, TimeUnit.SECONDS).get(0);
    CountDownLatch snapshots = new CountDownLatch(60);
    GameListener listener = new GameListener() { // called on the listener executor
      @Override
      public void onSnapshot(GameSnapshot s) {
        // s is valid during this call only: copy what you keep
        log.printf("tick %d: %d entities, me at (%.3f, %.3f, %.3f)%n", s.tick(), s.count(),
            s.predictedPositionM(0), s.predictedPositionM(1), s.predictedPositionM(2));
        snapshots.countDown();
      }

      @Override
      public void onDisconnected(DisconnectReason reason) {
        log.println("left the match: " + reason);
      }
    };
    GameConnection game = client.joinMatch(match.matchId(), listener).get(30, TimeUnit.SECONDS);
    game.setInput(0, 1, 0, 0, 0, 0); // run forward
    snapshots.await(30, TimeUnit.SECONDS);
    log.println(session.username() + ": " + game.stats());
    game.close();
    client.close();
    // README example ends
    assertEquals(0, snapshots.getCount(), "60 snapshots logged");
    String text = new String(logged.toByteArray(), StandardCharsets.UTF_8);
    assertTrue(text.contains("entities, me at ("), text);
    assertTrue(text.contains("readme_player: "), text);
  }

  @Test
  void theReadmeShowsExactlyTheseLines() throws Exception {
    String source = System.getProperty("ricochet.source_dir");
    String test = new String(Files.readAllBytes(Paths.get(source,
                                 "tests/clients/java/io/ricochet/client/ReadmeExampleTest.java")),
        StandardCharsets.UTF_8);
    String readme = new String(
        Files.readAllBytes(Paths.get(source, "clients/java/README.md")), StandardCharsets.UTF_8);
    String begin = "// README example begins\n";
    String end = "    // README example ends";
    String example = test.substring(test.indexOf(begin) + begin.length(), test.indexOf(end));
    StringBuilder unindented = new StringBuilder();
    for (String line : example.split("\n", -1)) {
      unindented.append(line.startsWith("    ") ? line.substring(4) : line).append('\n');
    }
    String shown = unindented.toString().replaceAll("\n+$", "\n");
    assertTrue(readme.contains("```java\n" + shown + "```\n"),
        "clients/java/README.md's example differs from ReadmeExampleTest's:\n" + shown);
  }
}
