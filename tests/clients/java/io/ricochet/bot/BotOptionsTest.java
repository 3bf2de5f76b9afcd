package io.ricochet.bot;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertThrows;
import static org.junit.jupiter.api.Assertions.assertTrue;

import org.junit.jupiter.api.Test;

/** ricochet-java-bot's command line: ricochet-bot's names, the client's aliases, clear refusals. */
class BotOptionsTest {
  private static final String PIN =
      "AB:CD:EF:01:23:45:67:89:AB:CD:EF:01:23:45:67:89:AB:CD:EF:01:23:45:67:89:AB:CD:EF:01:23:45:67:89";

  @Test
  void takesRicochetBotsNamesAndTheClientsAliases() throws Exception {
    BotOptions cpp = BotOptions.parse(new String[] {"--host", "127.0.0.1", "--port", "4000",
        "--fingerprint", PIN, "--bots", "3", "--match", "7", "--duration-s", "2.5", "--name",
        "mixed", "--skill", "0.9", "--seed", "5", "--matches", "0", "--spacing-ms", "0"});
    BotOptions java = BotOptions.parse(new String[] {"--control-port", "4000", "--pin-sha256", PIN,
        "--bots", "3", "--match-id", "7", "--seconds", "2.5", "--name", "mixed"});
    for (BotOptions options : new BotOptions[] {cpp, java}) {
      assertEquals(4000, options.port);
      assertEquals(PIN, options.fingerprint);
      assertEquals(7, options.matchId);
      assertEquals(2.5, options.durationS);
      assertEquals("mixed-3", options.nameOf(3));
    }
    assertEquals(0.9, cpp.skill);
    assertEquals(5, cpp.seed);
    assertEquals(0, cpp.matches);
    assertEquals(1, java.matches, "by default it stops after one match");
    assertEquals("jbot", BotOptions.parse(new String[] {"--trust-file", "x"}).nameOf(1));
  }

  @Test
  void findMatchTakesAModeAndAnOptionalMap() throws Exception {
    BotOptions any = BotOptions.parse(new String[] {"--fingerprint", PIN, "--find-match", "tdm"});
    assertEquals("tdm", any.findMode);
    assertEquals("", any.findMap);
    BotOptions on =
        BotOptions.parse(new String[] {"--fingerprint", PIN, "--find-match", "ffa:foundry.v2"});
    assertEquals("ffa", on.findMode);
    assertEquals("foundry.v2", on.findMap);
    assertEquals("", BotOptions.parse(new String[] {"--fingerprint", PIN}).findMode);
    assertRefused("--find-match must be MODE[:MAP]", "--fingerprint", PIN, "--find-match", ":x");
    assertRefused("--find-match must be MODE[:MAP]", "--fingerprint", PIN, "--find-match", "TDM");
    assertRefused(
        "--find-match must be MODE[:MAP]", "--fingerprint", PIN, "--find-match", "tdm:a b");
    assertRefused("give one of --match (--match-id) and --find-match", "--fingerprint", PIN,
        "--find-match", "tdm", "--match", "3");
  }

  @Test
  void refusesWhatItCannotRunNamingTheOptionAndTheValue() {
    assertRefused("--bots must be 1..64, got 0", "--fingerprint", PIN, "--bots", "0");
    assertRefused("--skill must be 0..1, got 1.5", "--fingerprint", PIN, "--skill", "1.5");
    assertRefused("--port must be an integer 1..65535, got x", "--fingerprint", PIN, "--port", "x");
    assertRefused("unknown option --colour", "--fingerprint", PIN, "--colour", "red");
    assertRefused("--seconds needs a value", "--fingerprint", PIN, "--seconds");
    assertRefused("give one of --fingerprint", "--host", "127.0.0.1");
    assertRefused("give one of --fingerprint", "--fingerprint", PIN, "--trust-file", "f");
    assertRefused("--fingerprint must be 32 hex pairs", "--fingerprint", "AB:CD");
    assertRefused("names of 3..24", "--fingerprint", PIN, "--name", "a b");
    assertRefused("names of 3..24", "--fingerprint", PIN, "--name", "abcdefghijklmnopqrstuv",
        "--bots", "10"); // abcdefghijklmnopqrstuv-10 is 25 characters
    assertRefused(
        "--duration-s must be 0..86400, got -1", "--fingerprint", PIN, "--duration-s", "-1");
  }

  private static void assertRefused(String expected, String... args) {
    BotOptions.UsageException refused =
        assertThrows(BotOptions.UsageException.class, () -> BotOptions.parse(args));
    assertTrue(refused.getMessage().contains(expected),
        "expected \"" + expected + "\" in \"" + refused.getMessage() + "\"");
  }
}
