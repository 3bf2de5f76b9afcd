package io.ricochet.bench;

import java.util.HashMap;
import java.util.Map;

/** "--name value" command-line options; an unknown option or a missing value is an error. */
final class Args {
  private final Map<String, String> values = new HashMap<>();

  /** Reads {@code args}; {@code known} lists the option names allowed (without "--"). */
  Args(String[] args, String... known) {
    for (int i = 0; i < args.length; i += 2) {
      String name = args[i].startsWith("--") ? args[i].substring(2) : null;
      boolean allowed = false;
      for (String each : known) allowed |= each.equals(name);
      if (!allowed || i + 1 >= args.length) {
        throw new IllegalArgumentException("unknown option or missing value: " + args[i]
            + " (options: --" + String.join(" --", known) + ")");
      }
      values.put(name, args[i + 1]);
    }
  }

  String text(String name, String fallback) {
    String value = values.get(name);
    return value != null ? value : fallback;
  }

  String required(String name) {
    String value = values.get(name);
    if (value == null) throw new IllegalArgumentException("--" + name + " is required");
    return value;
  }

  /** An integer option within [min, max]. */
  int integer(String name, int fallback, int min, int max) {
    String value = values.get(name);
    int parsed = value == null ? fallback : Integer.parseInt(value);
    if (parsed < min || parsed > max) {
      throw new IllegalArgumentException("--" + name + " must be " + min + ".." + max);
    }
    return parsed;
  }
}
