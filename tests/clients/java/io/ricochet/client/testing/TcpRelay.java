package io.ricochet.client.testing;

import java.io.IOException;
import java.io.InputStream;
import java.io.OutputStream;
import java.net.InetAddress;
import java.net.InetSocketAddress;
import java.net.ServerSocket;
import java.net.Socket;
import java.util.ArrayList;
import java.util.List;

/**
 * A TCP relay on 127.0.0.1 (a free port) to a target port, for tests of lost connections: {@link
 * #cut()} closes every relayed connection on both sides, as a lost network does; while {@link
 * #refuse} is on, connections are accepted and closed at once (a network that is still down).
 * Counts the connections it accepted. Threads of its own ("relay-"), all ended by {@link #close()}.
 */
public final class TcpRelay implements AutoCloseable {
  private final int targetPort;
  private final ServerSocket listener;
  private final Thread acceptor;
  private final List<Socket> open = new ArrayList<>();
  private final List<Thread> pumps = new ArrayList<>();
  private int accepted;
  private boolean refusing;
  private boolean closed;

  /** Starts relaying 127.0.0.1:{@link #port()} to 127.0.0.1:{@code targetPort}. */
  public TcpRelay(int targetPort) throws IOException {
    this.targetPort = targetPort;
    listener = new ServerSocket(0, 50, InetAddress.getLoopbackAddress());
    acceptor = new Thread(this::acceptLoop, "relay-accept");
    acceptor.setDaemon(true);
    acceptor.start();
  }

  /** The port clients connect to. */
  public int port() {
    return listener.getLocalPort();
  }

  /** Connections accepted so far (relayed or refused). */
  public synchronized int accepted() {
    return accepted;
  }

  /** Closes every relayed connection, both sides. */
  public synchronized void cut() {
    for (Socket socket : open) closeQuietly(socket);
    open.clear();
  }

  /** While on, every new connection is closed as soon as it is accepted. */
  public synchronized void refuse(boolean on) {
    refusing = on;
  }

  @Override
  public void close() {
    List<Thread> threads;
    synchronized (this) {
      closed = true;
      cut();
      threads = new ArrayList<>(pumps);
    }
    try {
      listener.close();
    } catch (IOException ignored) {
      // closing
    }
    try {
      acceptor.join(10_000);
      for (Thread thread : threads) thread.join(10_000);
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
    }
  }

  private void acceptLoop() {
    while (true) {
      Socket client;
      try {
        client = listener.accept();
      } catch (IOException e) {
        return; // closed
      }
      Socket server = null;
      synchronized (this) {
        ++accepted;
        if (closed || refusing) {
          closeQuietly(client);
          continue;
        }
      }
      try {
        server = new Socket();
        server.connect(new InetSocketAddress(InetAddress.getLoopbackAddress(), targetPort), 10_000);
      } catch (IOException e) {
        closeQuietly(client);
        closeQuietly(server);
        continue;
      }
      synchronized (this) {
        if (closed) {
          closeQuietly(client);
          closeQuietly(server);
          continue;
        }
        open.add(client);
        open.add(server);
        pumps.add(pump(client, server, "relay-up"));
        pumps.add(pump(server, client, "relay-down"));
      }
    }
  }

  private Thread pump(Socket from, Socket to, String name) {
    Thread thread = new Thread(() -> {
      byte[] buffer = new byte[16 * 1024];
      try {
        InputStream in = from.getInputStream();
        OutputStream out = to.getOutputStream();
        int read;
        while ((read = in.read(buffer)) >= 0) {
          out.write(buffer, 0, read);
          out.flush();
        }
      } catch (IOException e) {
        // cut, or the other side closed
      }
      closeQuietly(from);
      closeQuietly(to);
    }, name);
    thread.setDaemon(true);
    thread.start();
    return thread;
  }

  private static void closeQuietly(Socket socket) {
    if (socket == null) return;
    try {
      socket.close();
    } catch (IOException ignored) {
      // closing
    }
  }
}
