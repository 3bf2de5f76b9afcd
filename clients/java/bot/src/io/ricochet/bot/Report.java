package io.ricochet.bot;

import java.util.List;

/**
 * The JSON line ricochet-java-bot prints at exit, shaped as ricochet-bot's: {@code {"bots":N,
 * "done":D,"total":{...},"per_bot":[{"name":..,"state":..,"error":..,"metrics":{...}}]}}. In
 * {@code total} counts add up, the round trip's percentiles are over every bot's samples, and the
 * prediction error's p99 and max, and first_snapshot_ms, are the largest of the bots'.
 */
final class Report {
  private Report() {}

  /** The line for {@code bots} (call on the loop). */
  static String json(List<JavaBot> bots) {
    BotFigures total = new BotFigures();
    StringBuilder perBot = new StringBuilder();
    int done = 0;
    for (JavaBot bot : bots) {
      BotFigures figures = bot.figures();
      total.merge(figures);
      if (bot.state() == JavaBot.State.DONE) ++done;
      if (perBot.length() > 0) perBot.append(',');
      perBot.append("{\"name\":").append(string(bot.name()));
      perBot.append(",\"state\":\"").append(bot.state().name().toLowerCase(java.util.Locale.ROOT));
      perBot.append("\",\"error\":").append(string(bot.error()));
      perBot.append(",\"metrics\":").append(figures.toJson()).append('}');
    }
    return "{\"bots\":" + bots.size() + ",\"done\":" + done + ",\"total\":" + total.toJson()
        + ",\"per_bot\":[" + perBot + "]}";
  }

  /** {@code text} as a JSON string: quotes, backslashes and control characters escaped. */
  static String string(String text) {
    StringBuilder out = new StringBuilder("\"");
    for (int i = 0; i < text.length(); ++i) {
      char c = text.charAt(i);
      if (c == '"' || c == '\\') {
        out.append('\\').append(c);
      } else if (c < 0x20) {
        out.append(String.format("\\u%04x", (int) c));
      } else {
        out.append(c);
      }
    }
    return out.append('"').toString();
  }
}
