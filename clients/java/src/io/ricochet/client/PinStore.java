package io.ricochet.client;

/**
 * Where trust on first use keeps the certificate pins the app has seen, by "host:port" (the app
 * supplies it: SharedPreferences, a file ...). The first connection to a server with no pin saves
 * the SHA-256 of its certificate; every later one must match it. Called on the connection's I/O
 * thread, once per connection.
 */
public interface PinStore {
  /** The saved pin of {@code hostPort} ("host:port"), or null when it has none. */
  String load(String hostPort);

  /**
   * Saves {@code pinSha256} (32 uppercase hex pairs with colons) for {@code hostPort}, the first
   * time it is seen.
   */
  void save(String hostPort, String pinSha256);
}
