package io.ricochet.client.testing;

import java.io.BufferedReader;
import java.io.IOException;
import java.io.InputStreamReader;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.nio.file.Paths;
import java.util.ArrayList;
import java.util.Collections;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;

/**
 * Reads tests/vectors/NAME.txt, the cross-language vectors ricochet-vectors writes
 * (tools/vectors/vector_file.h has the format): records of a kind and key=value fields.
 */
public final class Vectors {
  private Vectors() {}

  /** One line: its kind and fields in order. */
  public static final class Record {
    public final String kind;
    public final int line;
    private final Map<String, String> fields;

    Record(String kind, int line, Map<String, String> fields) {
      this.kind = kind;
      this.line = line;
      this.fields = fields;
    }

    public String word(String key) {
      String value = fields.get(key);
      if (value == null) throw new IllegalArgumentException("line " + line + " has no " + key);
      return value;
    }

    public long number(String key) {
      return Long.parseLong(word(key));
    }

    public byte[] bytes(String key) {
      return Hex.decode(word(key));
    }

    public boolean has(String key) {
      return fields.containsKey(key);
    }

    @Override
    public String toString() {
      return kind + " (line " + line + ") " + fields.keySet();
    }
  }

  /** The directory of the vectors (the system property ricochet.vectors_dir, set by ctest). */
  public static Path directory() {
    String dir = System.getProperty("ricochet.vectors_dir");
    if (dir == null)
      throw new IllegalStateException("run with -Dricochet.vectors_dir=tests/vectors");
    return Paths.get(dir);
  }

  /** Every record of tests/vectors/{set}.txt, in order. */
  public static List<Record> read(String set) throws IOException {
    Path path = directory().resolve(set + ".txt");
    List<Record> records = new ArrayList<>();
    try (BufferedReader reader = new BufferedReader(
             new InputStreamReader(Files.newInputStream(path), StandardCharsets.UTF_8))) {
      String text;
      int line = 0;
      while ((text = reader.readLine()) != null) {
        ++line;
        if (text.isEmpty() || text.startsWith("#")) continue;
        String[] parts = text.split(" ");
        Map<String, String> fields = new LinkedHashMap<>();
        for (int i = 1; i < parts.length; ++i) {
          int eq = parts[i].indexOf('=');
          if (eq <= 0) throw new IOException(path + ":" + line + ": field without '='");
          fields.put(parts[i].substring(0, eq), parts[i].substring(eq + 1));
        }
        records.add(new Record(parts[0], line, Collections.unmodifiableMap(fields)));
      }
    }
    if (records.isEmpty()) throw new IOException(path + " has no records");
    return records;
  }
}
