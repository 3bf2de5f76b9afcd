package io.ricochet.client.testing;

import java.io.IOException;
import java.net.InetSocketAddress;
import java.net.SocketAddress;
import java.nio.ByteBuffer;
import java.nio.channels.DatagramChannel;
import java.nio.channels.SelectionKey;
import java.nio.channels.Selector;
import java.util.PriorityQueue;
import java.util.Random;
import java.util.concurrent.TimeUnit;
import java.util.concurrent.atomic.AtomicLong;

/**
 * A bad network link between one game client and the server's UDP game port, on 127.0.0.1 only,
 * as the C++ bot's link simulator (tools/bot/include/ricochet/bot/link_simulator.h) puts on each
 * direction: every datagram is lost with probability {@code loss}, otherwise delivered after
 * {@code latencyMs} ± up to {@code jitterMs} (uniform), so later ones may overtake it; seeded.
 * The client sends to {@link #port()} instead of the server's port; the relay forwards from its
 * own socket, so the server sees the relay as the client. One daemon thread; {@link #close()}
 * ends it. Real time (it carries real sockets), test code only.
 */
public final class BadLinkRelay implements AutoCloseable {
  /** One direction's figures. */
  public static final class Counters {
    /** Datagrams that entered the link. */
    public final AtomicLong sent = new AtomicLong();
    /** Datagrams lost. */
    public final AtomicLong dropped = new AtomicLong();
    /** Datagrams delivered after their delay. */
    public final AtomicLong delivered = new AtomicLong();

    @Override
    public String toString() {
      return "sent " + sent + " dropped " + dropped + " delivered " + delivered;
    }
  }

  private static final class InFlight {
    final long dueNs;
    final long order;
    final boolean toServer;
    final byte[] bytes;

    InFlight(long dueNs, long order, boolean toServer, byte[] bytes) {
      this.dueNs = dueNs;
      this.order = order;
      this.toServer = toServer;
      this.bytes = bytes;
    }
  }

  /** Client to server. */
  public final Counters up = new Counters();
  /** Server to client. */
  public final Counters down = new Counters();

  private final double loss;
  private final double latencyMs;
  private final double jitterMs;
  private final Random random;
  private final DatagramChannel front; // the client's side
  private final DatagramChannel back; // connected to the server
  private final Selector selector;
  private final PriorityQueue<InFlight> queue = new PriorityQueue<>(256,
      (a, b)
          -> a.dueNs != b.dueNs ? Long.compare(a.dueNs, b.dueNs) : Long.compare(a.order, b.order));
  private final Thread thread;
  private volatile boolean running = true;
  private volatile Throwable failure;
  private SocketAddress client;
  private long sends;

  /**
   * A relay to the game port {@code serverPort} on 127.0.0.1: {@code loss} 0..1 each way, each
   * datagram delayed {@code latencyMs} ± {@code jitterMs} (ms), randomness from {@code seed}.
   */
  public BadLinkRelay(int serverPort, double loss, double latencyMs, double jitterMs, long seed)
      throws IOException {
    this.loss = loss;
    this.latencyMs = latencyMs;
    this.jitterMs = jitterMs;
    this.random = new Random(seed);
    selector = Selector.open();
    front = DatagramChannel.open();
    front.bind(new InetSocketAddress("127.0.0.1", 0));
    front.configureBlocking(false);
    front.register(selector, SelectionKey.OP_READ);
    back = DatagramChannel.open();
    back.bind(new InetSocketAddress("127.0.0.1", 0));
    back.connect(new InetSocketAddress("127.0.0.1", serverPort));
    back.configureBlocking(false);
    back.register(selector, SelectionKey.OP_READ);
    thread = new Thread(this::run, "bad-link-relay");
    thread.setDaemon(true);
    thread.start();
  }

  /** The port on 127.0.0.1 the client sends its game datagrams to. */
  public int port() throws IOException {
    return ((InetSocketAddress) front.getLocalAddress()).getPort();
  }

  /** Null while the relay works; otherwise what stopped it. */
  public Throwable failure() {
    return failure;
  }

  @Override
  public void close() throws IOException {
    running = false;
    selector.wakeup();
    try {
      thread.join(TimeUnit.SECONDS.toMillis(5));
    } catch (InterruptedException e) {
      Thread.currentThread().interrupt();
    }
    selector.close();
    front.close();
    back.close();
  }

  private void run() {
    ByteBuffer buffer = ByteBuffer.allocate(65536);
    try {
      while (running) {
        long now = System.nanoTime();
        InFlight next = queue.peek();
        long waitMs = next == null ? 50 : TimeUnit.NANOSECONDS.toMillis(next.dueNs - now);
        if (waitMs > 0) {
          selector.select(Math.min(waitMs, 50));
        } else {
          selector.selectNow();
        }
        selector.selectedKeys().clear();
        receive(buffer);
        deliverDue(buffer);
      }
    } catch (IOException | RuntimeException e) {
      failure = e;
    }
  }

  private void receive(ByteBuffer buffer) throws IOException {
    while (true) {
      buffer.clear();
      SocketAddress from = front.receive(buffer);
      if (from == null) break;
      client = from;
      enter(buffer, true, up);
    }
    while (true) {
      buffer.clear();
      if (back.receive(buffer) == null) break;
      enter(buffer, false, down);
    }
  }

  private void enter(ByteBuffer buffer, boolean toServer, Counters counters) {
    counters.sent.incrementAndGet();
    if (random.nextDouble() < loss) {
      counters.dropped.incrementAndGet();
      return;
    }
    double delayMs = latencyMs + (2 * random.nextDouble() - 1) * jitterMs;
    buffer.flip();
    byte[] bytes = new byte[buffer.remaining()];
    buffer.get(bytes);
    long due = System.nanoTime() + (long) (delayMs * 1e6);
    queue.add(new InFlight(due, sends++, toServer, bytes));
  }

  private void deliverDue(ByteBuffer buffer) throws IOException {
    long now = System.nanoTime();
    while (!queue.isEmpty() && queue.peek().dueNs <= now) {
      InFlight due = queue.poll();
      buffer.clear();
      buffer.put(due.bytes);
      buffer.flip();
      if (due.toServer) {
        back.write(buffer);
        up.delivered.incrementAndGet();
      } else if (client != null) {
        front.send(buffer, client);
        down.delivered.incrementAndGet();
      }
    }
  }
}
