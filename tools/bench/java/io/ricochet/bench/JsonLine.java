package io.ricochet.bench;

import java.io.FileOutputStream;
import java.io.IOException;
import java.io.OutputStreamWriter;
import java.io.Writer;
import java.nio.charset.StandardCharsets;
import java.util.Locale;

/**
 * One result as one JSON line, its fields in the order added, as the C++ benches write them
 * (tools/bench/harness.h JsonObject and result_line): first "bench", numbers in fixed notation
 * with a given count of decimals. Printed to stdout and appended to a results file when one is
 * given.
 */
final class JsonLine {
  private final StringBuilder fields = new StringBuilder();

  /** A line whose first field is "bench": {@code bench}. */
  JsonLine(String bench) {
    text("bench", bench);
  }

  JsonLine text(String key, String value) {
    StringBuilder escaped = new StringBuilder();
    for (int i = 0; i < value.length(); ++i) {
      char c = value.charAt(i);
      if (c == '"' || c == '\\') {
        escaped.append('\\').append(c);
      } else if (c < 0x20) {
        escaped.append(String.format(Locale.ROOT, "\\u%04x", (int) c));
      } else {
        escaped.append(c);
      }
    }
    return raw(key, "\"" + escaped + "\"");
  }

  JsonLine integer(String key, long value) {
    return raw(key, Long.toString(value));
  }

  /** Fixed notation with {@code decimals} digits after the point (printf "%.Nf"). */
  JsonLine number(String key, double value, int decimals) {
    if (Double.isNaN(value) || Double.isInfinite(value)) return raw(key, "null");
    return raw(key, String.format(Locale.ROOT, "%." + decimals + "f", value));
  }

  JsonLine flag(String key, boolean value) {
    return raw(key, value ? "true" : "false");
  }

  /** The line, braces included, no newline. */
  @Override
  public String toString() {
    return "{" + fields + "}";
  }

  /** Prints the line and, when {@code path} is not null, appends it to that file. */
  void write(String path) throws IOException {
    System.out.println(this);
    if (path == null) return;
    try (Writer out =
             new OutputStreamWriter(new FileOutputStream(path, true), StandardCharsets.UTF_8)) {
      out.write(toString());
      out.write('\n');
    }
  }

  private JsonLine raw(String key, String value) {
    if (fields.length() > 0) fields.append(',');
    fields.append('"').append(key).append("\":").append(value);
    return this;
  }
}
