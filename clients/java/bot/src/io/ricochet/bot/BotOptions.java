package io.ricochet.bot;

import java.util.Locale;

/**
 * The command line of ricochet-java-bot, with ricochet-bot's option names where they mean the same
 * (tools/bot/README.md) and the Java client's names as aliases ({@code --control-port}, {@code
 * --pin-sha256}, {@code --match-id}, {@code --seconds}). {@link #parse} refuses anything else with
 * a message that names the option, its range and the value given.
 */
final class BotOptions {
  /** A command line that cannot be run; the message says why (exit code 2). */
  static final class UsageException extends Exception {
    private static final long serialVersionUID = 1L;

    UsageException(String message) {
      super(message);
    }
  }

  static final String USAGE = "usage: java -jar ricochet-java-bot.jar [options]\n"
      + "  --host ADDRESS            the server (default 127.0.0.1)\n"
      + "  --port, --control-port P  its control channel's TCP port (default 7777)\n"
      + "  --fingerprint, --pin-sha256 H  pin the certificate's SHA-256 (AA:BB:..., as logged)\n"
      + "  --trust-file FILE         or trust on first use: the pin is kept in FILE\n"
      + "  --name NAME               account name (default jbot; with --bots N: NAME-1..NAME-N)\n"
      + "  --password PASSWORD       account password, registered if new (default ricochet-bot)\n"
      + "  --match, --match-id ID    the match to join; 0: the first with room (default 0)\n"
      + "  --find-match MODE[:MAP]   ask the fleet for a seat instead (PROTOCOL.md, Placement):\n"
      + "                            follow the assignment to the server it names and join there\n"
      + "  --bots N                  bots in this process, 1..64 (default 1)\n"
      + "  --spacing-ms MS           ms between two bots' starts, 0..60000 (default 20)\n"
      + "  --skill S                 aim skill 0..1 (1: no aim error; default 0.5)\n"
      + "  --seed N                  the behaviour's seed; bot k uses seed + k - 1 (default 1)\n"
      + "  --matches N               stop after this many match results; 0: no limit (default 1)\n"
      + "  --duration-s, --seconds S stop after this long; 0: no limit (default 0)\n"
      + "  --log-level LEVEL         info (every transition) or warn (default), on stderr\n"
      + "  --help                    this text\n"
      + "At exit (the matches played, the time up, SIGINT or SIGTERM) it prints one JSON line of\n"
      + "figures, per bot and in total; exit code 0, 1 when a bot failed, 2 for a bad option.\n";

  String host = "127.0.0.1";
  int port = 7777;
  String fingerprint = "";
  String trustFile = "";
  String name = "jbot";
  String password = "ricochet-bot";
  long matchId;
  String findMode = ""; // --find-match: empty, or the mode to find a seat of
  String findMap = ""; // and its map (empty: any)
  int bots = 1;
  int spacingMs = 20;
  double skill = 0.5;
  long seed = 1;
  int matches = 1;
  double durationS;
  boolean verbose;
  boolean help;

  /** The options of {@code args}; throws UsageException naming the first wrong one. */
  static BotOptions parse(String[] args) throws UsageException {
    BotOptions options = new BotOptions();
    for (int i = 0; i < args.length; ++i) {
      String option = args[i];
      if (option.equals("--help") || option.equals("-h")) {
        options.help = true;
        continue;
      }
      if (i + 1 >= args.length) {
        throw new UsageException(
            option.startsWith("--") ? option + " needs a value" : "unknown argument " + option);
      }
      String value = args[++i];
      switch (option) {
        case "--host":
          options.host = value;
          break;
        case "--port":
        case "--control-port":
          options.port = (int) integer(option, value, 1, 65535);
          break;
        case "--fingerprint":
        case "--pin-sha256":
          options.fingerprint = value;
          break;
        case "--trust-file":
          options.trustFile = value;
          break;
        case "--name":
          options.name = value;
          break;
        case "--password":
          options.password = value;
          break;
        case "--match":
        case "--match-id":
          options.matchId = integer(option, value, 0, 0xFFFFFFFFL);
          break;
        case "--find-match": {
          int colon = value.indexOf(':');
          options.findMode = colon < 0 ? value : value.substring(0, colon);
          options.findMap = colon < 0 ? "" : value.substring(colon + 1);
          if (!options.findMode.matches("[a-z0-9_-]{1,32}")
              || !options.findMap.matches("[A-Za-z0-9_.-]{0,64}")) {
            throw new UsageException("--find-match must be MODE[:MAP] (MODE 1..32 of [a-z0-9_-], "
                + "MAP up to 64 of [A-Za-z0-9_.-]), got " + value);
          }
          break;
        }
        case "--bots":
          options.bots = (int) integer(option, value, 1, 64);
          break;
        case "--spacing-ms":
          options.spacingMs = (int) integer(option, value, 0, 60000);
          break;
        case "--skill":
          options.skill = real(option, value, 0, 1);
          break;
        case "--seed":
          options.seed = integer(option, value, 0, Long.MAX_VALUE);
          break;
        case "--matches":
          options.matches = (int) integer(option, value, 0, 1000);
          break;
        case "--duration-s":
        case "--seconds":
          options.durationS = real(option, value, 0, 86400);
          break;
        case "--log-level":
          if (!value.equals("info") && !value.equals("warn")) {
            throw new UsageException("--log-level must be info or warn, got " + value);
          }
          options.verbose = value.equals("info");
          break;
        default:
          throw new UsageException("unknown option " + option);
      }
    }
    if (options.help) return options;
    if (options.fingerprint.isEmpty() == options.trustFile.isEmpty()) {
      throw new UsageException("give one of --fingerprint (--pin-sha256) and --trust-file");
    }
    if (!options.fingerprint.isEmpty()
        && !options.fingerprint.replace(":", "").matches("[0-9A-Fa-f]{64}")) {
      throw new UsageException(
          "--fingerprint must be 32 hex pairs (AA:BB:...), got " + options.fingerprint);
    }
    String widest = options.bots > 1 ? options.name + "-" + options.bots : options.name;
    if (!widest.matches("[A-Za-z0-9_.-]{3,24}")) {
      throw new UsageException("--name must make names of 3..24 of [A-Za-z0-9_.-], got " + widest);
    }
    if (options.password.length() < 8) {
      throw new UsageException("--password must be at least 8 characters");
    }
    if (options.host.isEmpty()) throw new UsageException("--host is empty");
    if (!options.findMode.isEmpty() && options.matchId != 0) {
      throw new UsageException("give one of --match (--match-id) and --find-match");
    }
    return options;
  }

  /** Bot {@code k}'s (1..bots) account name. */
  String nameOf(int k) {
    return bots > 1 ? name + "-" + k : name;
  }

  private static long integer(String option, String value, long min, long max)
      throws UsageException {
    long parsed;
    try {
      parsed = Long.parseLong(value);
    } catch (NumberFormatException e) {
      throw new UsageException(
          option + " must be an integer " + min + ".." + max + ", got " + value);
    }
    if (parsed < min || parsed > max) {
      throw new UsageException(option + " must be " + min + ".." + max + ", got " + value);
    }
    return parsed;
  }

  private static double real(String option, String value, double min, double max)
      throws UsageException {
    double parsed;
    try {
      parsed = Double.parseDouble(value);
    } catch (NumberFormatException e) {
      parsed = Double.NaN;
    }
    if (!(parsed >= min && parsed <= max)) {
      throw new UsageException(String.format(
          Locale.ROOT, "%s must be %s..%s, got %s", option, trim(min), trim(max), value));
    }
    return parsed;
  }

  private static String trim(double value) {
    return value == Math.rint(value) ? Long.toString((long) value) : Double.toString(value);
  }
}
