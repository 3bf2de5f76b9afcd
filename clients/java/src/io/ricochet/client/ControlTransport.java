package io.ricochet.client;

import java.io.IOException;
import java.io.InputStream;
import java.io.OutputStream;
import java.net.Socket;

/**
 * Opens the byte stream a {@link ControlConnection} speaks the control channel over, on its I/O
 * thread: {@link TlsConnector} (TLS 1.3 and the certificate check) in the library; a plain socket
 * in tests that play the server themselves.
 */
interface ControlTransport {
  /** The plaintext streams of one connection. */
  final class Streams {
    final InputStream in;
    final OutputStream out;

    Streams(InputStream in, OutputStream out) {
      this.in = in;
      this.out = out;
    }
  }

  /**
   * Connects {@code tcp} (unconnected; closing it from another thread aborts the attempt) and
   * returns its streams once nothing more needs checking before the first request is written.
   */
  Streams open(Socket tcp) throws RicochetException;

  /** Closes {@code socket}, ignoring failures (closing is the last thing done with it). */
  static void closeQuietly(Socket socket) {
    try {
      socket.close();
    } catch (IOException ignored) {
      // closing: nothing more to do
    }
  }
}
