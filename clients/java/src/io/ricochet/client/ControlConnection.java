package io.ricochet.client;

import io.ricochet.client.core.control.ControlCloseReason;
import io.ricochet.client.core.control.ControlEvent;
import io.ricochet.client.core.control.ControlSession;
import io.ricochet.client.core.control.ControlState;
import io.ricochet.client.core.control.RequestResult;
import io.ricochet.wire.ControlProto.ClientMessage;
import io.ricochet.wire.ControlProto.ErrorCode;
import io.ricochet.wire.ControlProto.MatchResults;
import io.ricochet.wire.ControlProto.ServerMessage;
import java.io.IOException;
import java.io.OutputStream;
import java.net.Socket;
import java.util.ArrayDeque;
import java.util.ArrayList;
import java.util.HashMap;
import java.util.List;
import java.util.Map;

/**
 * One TLS control connection and its {@link ControlSession}, the I/O under {@link RicochetClient}.
 * Two threads of its own: "ricochet-control-read" connects (TLS and pin, before anything is
 * sent), then blocks reading and feeds the session; "ricochet-control-write" writes what the
 * session queues and runs its timers (request timeouts, keep-alive pings), because a blocking
 * {@code SSLSocket} cannot be woken to write. The session is only touched under this object's
 * lock. Callbacks ({@link ReplyHandler}, {@link Callbacks}) run on those threads with the lock
 * held and must only hand work to another executor. Once over (closed, lost, refused), it stays
 * over: the client makes a new one.
 */
final class ControlConnection {
  /** Gets the answer to one request. */
  interface ReplyHandler {
    /**
     * The reply (its body answers the request, or is an Error) arrived on {@code from} at {@code
     * nowMs}.
     */
    void onReply(ControlConnection from, ServerMessage message, long nowMs);

    /** No reply will come. */
    void onFailure(RicochetException failure);
  }

  /** Gets what the server sends unasked, and the end. */
  interface Callbacks {
    void onMatchResults(MatchResults results);

    void onDisconnected(Disconnect disconnect);
  }

  private static final class Submission {
    final ClientMessage message;
    final ReplyHandler handler;

    Submission(ClientMessage message, ReplyHandler handler) {
      this.message = message;
      this.handler = handler;
    }
  }

  private final ControlTransport transport;
  private final long requestTimeoutMs;
  private final long keepAliveMs;
  private final Callbacks callbacks;
  private final Socket tcp = new Socket();
  private final Thread reader;
  private final Thread writer;
  private final ArrayDeque<Submission> submitted = new ArrayDeque<>();
  private final Map<Long, ReplyHandler> handlers = new HashMap<>();
  private ControlTransport.Streams streams; // once TLS is up and pinned
  private ControlSession session; // once connected
  private boolean over;
  private Disconnect disconnect; // how it ended, once over after TLS was up

  ControlConnection(
      ControlTransport transport, long requestTimeoutMs, long keepAliveMs, Callbacks callbacks) {
    this.transport = transport;
    this.requestTimeoutMs = requestTimeoutMs;
    this.keepAliveMs = keepAliveMs;
    this.callbacks = callbacks;
    this.reader = new Thread(this::readLoop, "ricochet-control-read");
    this.writer = new Thread(this::writeLoop, "ricochet-control-write");
    reader.setDaemon(true);
    writer.setDaemon(true);
  }

  /** Starts connecting; requests submitted meanwhile are sent once TLS is up and pinned. */
  void start() {
    reader.start();
  }

  /**
   * Queues {@code message}; {@code handler} gets its reply or why none will come. Once TLS is up
   * the session checks it at once, against the state the replies so far have set, so requests
   * made one after the other are checked and sent in that order; before, it waits for the
   * connection.
   */
  synchronized void submit(ClientMessage message, ReplyHandler handler) {
    if (over) {
      handler.onFailure(new RicochetException(
          RicochetException.Kind.DISCONNECTED, null, null, "the connection is closed"));
      return;
    }
    submitted.addLast(new Submission(message, handler));
    if (session != null) sendSubmitted(nowMs());
    notifyAll();
  }

  /** Whether it is over (a new request needs a new connection). */
  synchronized boolean isOver() {
    return over;
  }

  /** How it ended once over, when TLS had come up; null before, or when it never connected. */
  synchronized Disconnect disconnect() {
    return disconnect;
  }

  /** Whether it is over and its threads have ended. */
  boolean finished() {
    return isOver() && !reader.isAlive() && !writer.isAlive();
  }

  /** The session's state; CLOSED before TLS is up and once over. */
  synchronized ControlState state() {
    return session == null ? ControlState.CLOSED : session.state();
  }

  /** Closes it (pending requests fail with CLOSED) and waits for its threads to end. */
  void close() throws InterruptedException {
    synchronized (this) {
      if (session != null) {
        session.close();
        dispatchEvents();
      } else if (!over) {
        end(new RicochetException(RicochetException.Kind.CLOSED, null, null, "client closed"));
      }
    }
    ControlTransport.closeQuietly(tcp);
    join(reader);
    join(writer);
  }

  /** Cuts the TCP connection as a lost network would (tests). */
  void dropForTest() {
    ControlTransport.closeQuietly(tcp);
  }

  private static void join(Thread thread) throws InterruptedException {
    if (thread.getState() != Thread.State.NEW) thread.join();
  }

  private static long nowMs() {
    return System.nanoTime() / 1_000_000;
  }

  private void readLoop() {
    ControlTransport.Streams opened;
    try {
      opened = transport.open(tcp);
    } catch (RicochetException e) {
      synchronized (this) {
        end(e);
      }
      return;
    } catch (RuntimeException e) {
      // A provider may throw unchecked exceptions from a handshake; none escapes this thread.
      synchronized (this) {
        end(new RicochetException(RicochetException.Kind.CONNECT_FAILED, e.toString(), e));
      }
      ControlTransport.closeQuietly(tcp);
      return;
    }
    synchronized (this) {
      if (over) {
        ControlTransport.closeQuietly(tcp);
        return;
      }
      streams = opened;
      session = new ControlSession(nowMs(), requestTimeoutMs, keepAliveMs);
      writer.start();
      notifyAll();
    }
    byte[] buffer = new byte[16 * 1024];
    while (true) {
      int read;
      String failure = null;
      try {
        read = opened.in.read(buffer);
      } catch (IOException | RuntimeException e) {
        read = -1;
        failure = "reading failed: " + e;
      }
      synchronized (this) {
        if (read < 0) {
          session.connectionLost(failure != null ? failure : "the server closed the connection");
        } else {
          session.receive(buffer, 0, read);
        }
        dispatchEvents();
        notifyAll();
        if (over) break;
      }
    }
    ControlTransport.closeQuietly(tcp);
  }

  private void writeLoop() {
    OutputStream out = streams.out;
    while (true) {
      byte[] bytes;
      synchronized (this) {
        while (true) {
          if (over) return;
          long now = nowMs();
          sendSubmitted(now);
          session.update(now);
          bytes = session.pollTransmit();
          dispatchEvents();
          if (over) return;
          if (bytes != null) break;
          long waitMs = Math.max(1, session.deadlineMs() - now);
          try {
            wait(Math.min(waitMs, 60_000));
          } catch (InterruptedException e) {
            Thread.currentThread().interrupt();
            session.close();
            dispatchEvents();
            return;
          }
        }
      }
      try {
        out.write(bytes);
        out.flush();
      } catch (IOException | RuntimeException e) {
        synchronized (this) {
          session.connectionLost("writing failed: " + e);
          dispatchEvents();
        }
        return;
      }
    }
  }

  /** Hands every submitted request to the session (lock held). */
  private void sendSubmitted(long now) {
    Submission submission;
    while ((submission = submitted.pollFirst()) != null) {
      RequestResult result = session.request(submission.message, now);
      if (result.queued()) {
        handlers.put(result.requestId(), submission.handler);
      } else {
        submission.handler.onFailure(
            new RicochetException(RicochetException.Kind.REFUSED_LOCALLY, null, result.refusal(),
                "refused before sending: " + result.refusal().counterName() + " (the connection is "
                    + session.state().counterName() + ")"));
      }
    }
  }

  /** Delivers the session's events (lock held). */
  private void dispatchEvents() {
    ControlEvent event;
    while ((event = session.pollEvent()) != null) {
      if (event instanceof ControlEvent.Reply) {
        ControlEvent.Reply reply = (ControlEvent.Reply) event;
        ReplyHandler handler = handlers.remove(reply.requestId());
        if (handler != null) handler.onReply(this, reply.message(), nowMs());
      } else if (event instanceof ControlEvent.MatchResultsArrived) {
        callbacks.onMatchResults(((ControlEvent.MatchResultsArrived) event).results());
      } else if (event instanceof ControlEvent.Closed) {
        ControlEvent.Closed closed = (ControlEvent.Closed) event;
        ErrorCode code = closed.serverError() == null ? null : closed.serverError().getCode();
        boolean requested = closed.reason() == ControlCloseReason.REQUESTED;
        end(new RicochetException(
            requested ? RicochetException.Kind.CLOSED : RicochetException.Kind.DISCONNECTED, code,
            null, closed.detail()));
        disconnect = new Disconnect(closed.reason(), code, closed.detail());
        callbacks.onDisconnected(disconnect);
      }
    }
  }

  /** Marks it over and fails everything still waiting with {@code failure} (lock held). */
  private void end(RicochetException failure) {
    over = true;
    List<ReplyHandler> waiting = new ArrayList<>(handlers.values());
    handlers.clear();
    for (Submission submission : submitted) waiting.add(submission.handler);
    submitted.clear();
    for (ReplyHandler handler : waiting) handler.onFailure(failure);
    ControlTransport.closeQuietly(tcp);
    notifyAll();
  }
}
