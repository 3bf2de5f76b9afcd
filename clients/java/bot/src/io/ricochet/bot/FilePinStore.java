package io.ricochet.bot;

import io.ricochet.client.PinStore;
import java.io.IOException;
import java.io.UncheckedIOException;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Path;
import java.util.List;

/**
 * Trust on first use in a file, as ricochet-bot's --trust-file: the first connection writes the
 * server certificate's pin (one line), later ones must match it. One file for one server.
 */
final class FilePinStore implements PinStore {
  private final Path file;

  FilePinStore(Path file) {
    this.file = file;
  }

  @Override
  public synchronized String load(String hostPort) {
    if (!Files.exists(file)) return null;
    try {
      List<String> lines = Files.readAllLines(file, StandardCharsets.UTF_8);
      return lines.isEmpty() || lines.get(0).trim().isEmpty() ? null : lines.get(0).trim();
    } catch (IOException e) {
      throw new UncheckedIOException("cannot read " + file, e);
    }
  }

  @Override
  public synchronized void save(String hostPort, String pinSha256) {
    if (load(hostPort) != null) return; // another bot of this process saved it first
    try {
      Files.write(file, (pinSha256 + "\n").getBytes(StandardCharsets.UTF_8));
    } catch (IOException e) {
      throw new UncheckedIOException("cannot write " + file, e);
    }
  }
}
