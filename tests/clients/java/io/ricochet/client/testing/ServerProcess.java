package io.ricochet.client.testing;

import java.io.File;
import java.io.IOException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.ArrayList;
import java.util.Comparator;
import java.util.List;
import java.util.concurrent.TimeUnit;
import java.util.regex.Matcher;
import java.util.regex.Pattern;
import java.util.stream.Stream;

/**
 * The real {@code ricochet-server} (system property {@code ricochet.server_binary}) as a child
 * process for end-to-end tests, as tests/integration/server_process.h runs it: a temporary data
 * directory, a configuration on 127.0.0.1 with every port 0 (the kernel picks free ones), its log
 * in a file, password threads at nice 0. The bound ports and the certificate fingerprint come from
 * the ports file the server writes once it listens, checked against its start-up log line. {@link
 * #close()} stops it (SIGTERM, then kill) and removes the directory.
 */
public final class ServerProcess implements AutoCloseable {
  private static final Pattern PORTS_FILE =
      Pattern.compile("^\\{\"control_port\":(\\d+),\"game_port\":(\\d+),\"admin_port\":(\\d+),"
          + "\"fingerprint\":\"([0-9A-F:]{95})\",\"pid\":(\\d+)\\}\\n$");
  private static final Pattern LOG_FINGERPRINT =
      Pattern.compile("fingerprint \\(pin it in clients\\): ([0-9A-F:]{95})");

  private final Path dir;
  private final Path log;
  private final Process process;
  private int controlPort;
  private int gamePort;
  private int adminPort;
  private String fingerprint;

  /**
   * Starts a server whose [matches] table is {@code matchesToml}, with {@code controlToml} more
   * keys of its [control] table and {@code moreToml} after them (whole tables: "[db]\n..."), and
   * waits until it listens, at most {@code startLimitMs}. Throws when it does not.
   */
  public ServerProcess(String matchesToml, String controlToml, String moreToml, long startLimitMs)
      throws IOException, InterruptedException {
    String binary = System.getProperty("ricochet.server_binary");
    if (binary == null) throw new IllegalStateException("ricochet.server_binary is not set");
    dir = Files.createTempDirectory("ricochet-java-e2e");
    log = dir.resolve("server.log");
    Path config = dir.resolve("server.toml");
    Path ports = dir.resolve("ports.json");
    String toml = "[server]\ndata_dir = \"" + dir.resolve("data") + "\"\nports_file = \"" + ports
        + "\"\nthreads = 2\nshutdown_grace_s = 2\n"
        + "[control]\nbind = \"127.0.0.1\"\nport = 0\n" + controlToml + "\n"
        + "[game]\nbind = \"127.0.0.1\"\nport = 0\n"
        + "[admin]\nbind = \"127.0.0.1\"\nport = 0\n"
        + "[matches]\n" + matchesToml + "\n" + moreToml + "\n";
    Files.write(config, toml.getBytes(StandardCharsets.UTF_8));
    List<String> command = new ArrayList<>();
    command.add(binary);
    command.add("--config");
    command.add(config.toString());
    command.add("--password-thread-nice");
    command.add("0");
    ProcessBuilder builder = new ProcessBuilder(command);
    builder.redirectErrorStream(true);
    builder.redirectOutput(ProcessBuilder.Redirect.appendTo(log.toFile()));
    process = builder.start();
    long deadline = System.nanoTime() + TimeUnit.MILLISECONDS.toNanos(startLimitMs);
    while (true) {
      if (readPorts(ports)) return;
      if (!process.isAlive() || System.nanoTime() > deadline) {
        close();
        throw new IllegalStateException(
            "ricochet-server did not start within " + startLimitMs + " ms: " + log());
      }
      Thread.sleep(20);
    }
  }

  /** A server with one open match of the sample arena, 16 seats, nobody needed to start. */
  public static ServerProcess arena(String moreToml) throws IOException, InterruptedException {
    return arena("", "", moreToml);
  }

  /**
   * As {@link #arena(String)}, with {@code matchesToml} more keys of [matches] and {@code
   * controlToml} more keys of [control].
   */
  public static ServerProcess arena(String matchesToml, String controlToml, String moreToml)
      throws IOException, InterruptedException {
    String source = System.getProperty("ricochet.source_dir", ".");
    return new ServerProcess("count = 1\nmax_players = 16\nmaps = [\"" + source
            + "/server/maps/arena.toml\"]\nseed = 42\nwarmup_s = 0\nfrag_limit = 0\n"
            + "record = false\nmin_players = 1\ntime_limit_s = 600\n" + matchesToml,
        controlToml, moreToml, 30_000);
  }

  private boolean readPorts(Path ports) throws IOException {
    if (!Files.exists(ports)) return false;
    String file = new String(Files.readAllBytes(ports), StandardCharsets.UTF_8);
    Matcher fields = PORTS_FILE.matcher(file);
    if (!fields.matches()) return false;
    Matcher logged = LOG_FINGERPRINT.matcher(log());
    if (!logged.find()) return false;
    if (!logged.group(1).equals(fields.group(4))) {
      throw new IllegalStateException(
          "the ports file " + file + " disagrees with the log " + log());
    }
    controlPort = Integer.parseInt(fields.group(1));
    gamePort = Integer.parseInt(fields.group(2));
    adminPort = Integer.parseInt(fields.group(3));
    fingerprint = fields.group(4);
    return true;
  }

  /** The control channel's TCP port on 127.0.0.1. */
  public int controlPort() {
    return controlPort;
  }

  /** The game channel's UDP port on 127.0.0.1. */
  public int gamePort() {
    return gamePort;
  }

  /**
   * Bans {@code username} through the admin HTTP port ({@code POST /accounts/NAME/ban},
   * server/OPERATIONS.md); its HTTP status.
   */
  public int ban(String username) throws IOException {
    java.net.HttpURLConnection http =
        (java.net.HttpURLConnection) new java.net
            .URL("http://127.0.0.1:" + adminPort + "/accounts/" + username + "/ban")
            .openConnection();
    http.setRequestMethod("POST");
    http.setConnectTimeout(10_000);
    http.setReadTimeout(10_000);
    try {
      return http.getResponseCode();
    } finally {
      http.disconnect();
    }
  }

  /** The certificate's SHA-256, 32 uppercase hex pairs with colons, as the server logs it. */
  public String fingerprint() {
    return fingerprint;
  }

  /**
   * The server's data directory: its database {@code ricochet.db}, and {@code recordings/} when
   * the matches are recorded without a recordings_dir. Removed by {@link #close()}.
   */
  public Path dataDir() {
    return dir.resolve("data");
  }

  /** The server's log so far. */
  public String log() {
    try {
      return new String(Files.readAllBytes(log), StandardCharsets.UTF_8);
    } catch (IOException e) {
      return "(no log: " + e + ")";
    }
  }

  /** Sends SIGTERM (a graceful stop: connections get SHUTTING_DOWN); does not wait. */
  public void terminate() {
    process.destroy();
  }

  /** Waits for the exit at most {@code limitMs}; its code, or null when still running. */
  public Integer waitExit(long limitMs) throws InterruptedException {
    return process.waitFor(limitMs, TimeUnit.MILLISECONDS) ? process.exitValue() : null;
  }

  /** Stops it (SIGTERM, then SIGKILL after 10 s) and deletes its directory. */
  @Override
  public void close() throws IOException {
    process.destroy();
    try {
      if (!process.waitFor(10, TimeUnit.SECONDS)) {
        process.destroyForcibly();
        process.waitFor(10, TimeUnit.SECONDS);
      }
    } catch (InterruptedException e) {
      process.destroyForcibly();
      Thread.currentThread().interrupt();
    }
    try (Stream<Path> paths = Files.walk(dir)) {
      paths.sorted(Comparator.reverseOrder()).map(Path::toFile).forEach(File::delete);
    }
  }
}
