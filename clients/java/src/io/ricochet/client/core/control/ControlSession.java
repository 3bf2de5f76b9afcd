package io.ricochet.client.core.control;

import com.google.protobuf.InvalidProtocolBufferException;
import io.ricochet.client.core.FrameReader;
import io.ricochet.client.core.FrameRefusal;
import io.ricochet.client.core.Frames;
import io.ricochet.wire.ControlProto.ClientMessage;
import io.ricochet.wire.ControlProto.Error;
import io.ricochet.wire.ControlProto.ErrorCode;
import io.ricochet.wire.ControlProto.Ping;
import io.ricochet.wire.ControlProto.ServerMessage;
import java.io.ByteArrayOutputStream;
import java.util.ArrayDeque;
import java.util.Iterator;
import java.util.Locale;

/**
 * The client end of the control channel as a sans-IO state machine (PROTOCOL.md, Control channel,
 * The client end; the C++ twin is {@code proto/include/ricochet/proto/control_client.h}): the
 * server's bytes (TLS plaintext) and the time in; frames to write and {@link ControlEvent}s out.
 *
 * <p>It numbers requests from 1 (wrapping past 2^32-1 to 1), matches every reply to its pending
 * request by id in whatever order they come, follows the connection's {@link ControlState} from
 * the replies, refuses locally what the state does not allow ({@link RequestRefusal}, counted),
 * times requests out, sends keep-alive pings of its own and consumes their pongs, and checks the
 * server's bytes like any untrusted input: anything the protocol does not allow closes the session
 * with a counted {@link ControlCloseReason}, never an exception. The TLS connection and its pinning
 * are the caller's: one session per TLS connection, made once TLS is up. No sockets, no threads,
 * no clock (time is {@code nowMs}, any monotonic milliseconds). Not thread-safe.
 */
public final class ControlSession {
  /** The default request timeout: a login may wait behind many password hashes (ms). */
  public static final long DEFAULT_REQUEST_TIMEOUT_MS = 60_000;
  /** The default keep-alive: well inside the server's 120 s idle timeout (ms). */
  public static final long DEFAULT_KEEP_ALIVE_MS = 30_000;

  private static final class Pending {
    final long requestId;
    final RequestKind kind;
    final long sentAtMs;
    final boolean keepAlive; // this session's own ping: its Pong is no event

    Pending(long requestId, RequestKind kind, long sentAtMs, boolean keepAlive) {
      this.requestId = requestId;
      this.kind = kind;
      this.sentAtMs = sentAtMs;
      this.keepAlive = keepAlive;
    }
  }

  private final long requestTimeoutMs;
  private final long keepAliveMs;
  private final FrameReader reader = new FrameReader();
  private final ByteArrayOutputStream outbox = new ByteArrayOutputStream();
  private final ArrayDeque<Pending> pending = new ArrayDeque<>(); // in the order sent
  private final ArrayDeque<ControlEvent> events = new ArrayDeque<>();
  private final ControlCounters counters = new ControlCounters();
  private ControlState state = ControlState.UNAUTHENTICATED;
  private int lastRequestId; // unsigned 32-bit
  private long lastSentMs; // when a frame was last queued (keep-alive)

  /** A session with the default timeouts, made when TLS is up at {@code nowMs}. */
  public ControlSession(long nowMs) {
    this(nowMs, DEFAULT_REQUEST_TIMEOUT_MS, DEFAULT_KEEP_ALIVE_MS);
  }

  /**
   * A session made when TLS is up at {@code nowMs}. A request with no reply {@code
   * requestTimeoutMs} after it was queued closes it (0: never); a ping is queued when nothing was
   * sent for {@code keepAliveMs} (0: no keep-alive pings).
   */
  public ControlSession(long nowMs, long requestTimeoutMs, long keepAliveMs) {
    this(nowMs, requestTimeoutMs, keepAliveMs, 0);
  }

  /** For tests: as above, numbering from {@code lastRequestId + 1} (unsigned 32-bit). */
  ControlSession(long nowMs, long requestTimeoutMs, long keepAliveMs, int lastRequestId) {
    if (requestTimeoutMs < 0 || keepAliveMs < 0) {
      throw new IllegalArgumentException(
          "timeouts must be >= 0 ms: " + requestTimeoutMs + ", " + keepAliveMs);
    }
    this.requestTimeoutMs = requestTimeoutMs;
    this.keepAliveMs = keepAliveMs;
    this.lastRequestId = lastRequestId;
    this.lastSentMs = nowMs;
  }

  /**
   * Queues {@code message} (one of the requests, its body set) with the next request id (any
   * request_id in it is replaced), unless the current state does not allow its kind. The state is
   * the one replies have set: send list_matches after the login's reply, not with it.
   */
  public RequestResult request(ClientMessage message, long nowMs) {
    if (state == ControlState.CLOSED) return refuse(RequestRefusal.CLOSED);
    RequestKind kind = RequestKind.of(message);
    if (kind == null) return refuse(RequestRefusal.NO_BODY);
    if (!kind.allowedIn(state)) return refuse(RequestRefusal.WRONG_STATE);
    long requestId = queue(message, kind, nowMs, false);
    if (requestId == 0) return refuse(RequestRefusal.TOO_LARGE);
    return new RequestResult(requestId, null);
  }

  /**
   * Bytes received from the server, {@code bytes[offset, offset + length)}, split anywhere. Each
   * whole frame is handled at once: its reply or MatchResults becomes an event, or it closes the
   * session with the reason it was refused. Ignored once closed.
   */
  public void receive(byte[] bytes, int offset, int length) {
    if (state == ControlState.CLOSED) return;
    counters.bytesIn += length;
    reader.feed(bytes, offset, length);
    while (state != ControlState.CLOSED) {
      FrameReader.Status status = reader.next();
      if (status == FrameReader.Status.NEED_MORE) return;
      if (status == FrameReader.Status.REFUSED) {
        boolean oversize = reader.refusal() == FrameRefusal.OVERSIZE;
        end(oversize ? ControlCloseReason.FRAME_OVERSIZE : ControlCloseReason.FRAME_EMPTY,
            "the server sent a frame header declaring " + reader.refusedLength()
                + " bytes; a frame holds 1.." + FrameReader.MAX_PAYLOAD_BYTES,
            null);
        return;
      }
      ++counters.framesIn;
      byte[] payload = reader.payload();
      ServerMessage message;
      try {
        message = ServerMessage.parseFrom(payload);
      } catch (InvalidProtocolBufferException e) {
        end(ControlCloseReason.MALFORMED,
            "the server sent " + payload.length + " bytes that are not a ServerMessage", null);
        return;
      }
      if (message.getBodyCase() == ServerMessage.BodyCase.BODY_NOT_SET) {
        end(ControlCloseReason.MISSING_BODY,
            "the server sent a ServerMessage with no body (request_id "
                + unsigned(message.getRequestId()) + ")",
            null);
        return;
      }
      onMessage(message);
    }
  }

  /** Request timeouts and keep-alive pings; call it at {@link #deadlineMs()} (earlier is fine). */
  public void update(long nowMs) {
    if (state == ControlState.CLOSED) return;
    Pending oldest = pending.peekFirst();
    if (requestTimeoutMs > 0 && oldest != null && nowMs - oldest.sentAtMs >= requestTimeoutMs) {
      end(ControlCloseReason.REQUEST_TIMEOUT,
          requestName(oldest.requestId, oldest.kind) + " had no reply within " + requestTimeoutMs
              + " ms",
          null);
      return;
    }
    if (keepAliveMs > 0 && nowMs - lastSentMs >= keepAliveMs) {
      ClientMessage ping = ClientMessage.newBuilder()
                               .setPing(Ping.newBuilder().setClientTimeUs(nowMs * 1000))
                               .build();
      if (queue(ping, RequestKind.PING, nowMs, true) != 0) ++counters.keepAlives;
    }
  }

  /**
   * When {@link #update} has something to do next (ms, the clock of {@code nowMs}); {@link
   * Long#MAX_VALUE} when nothing is due (no timeouts configured, or closed).
   */
  public long deadlineMs() {
    if (state == ControlState.CLOSED) return Long.MAX_VALUE;
    long due = Long.MAX_VALUE;
    Pending oldest = pending.peekFirst();
    if (requestTimeoutMs > 0 && oldest != null) due = oldest.sentAtMs + requestTimeoutMs;
    if (keepAliveMs > 0) due = Math.min(due, lastSentMs + keepAliveMs);
    return due;
  }

  /** Every frame queued since the last call, back to back; null when nothing is queued. */
  public byte[] pollTransmit() {
    if (outbox.size() == 0) return null;
    byte[] bytes = outbox.toByteArray();
    outbox.reset();
    return bytes;
  }

  /** The next event, or null when there is none. */
  public ControlEvent pollEvent() {
    return events.pollFirst();
  }

  /** The stream ended or failed ({@code why}, for people); no-op once closed. */
  public void connectionLost(String why) {
    end(ControlCloseReason.CONNECTION_LOST, why, null);
  }

  /** The caller is done: drops what is queued and pending. No-op once closed. */
  public void close() {
    end(ControlCloseReason.REQUESTED, "closed by this client", null);
  }

  /** The connection's state as the replies have set it. */
  public ControlState state() {
    return state;
  }

  /** Requests sent and not answered yet, keep-alive pings included. */
  public int pending() {
    return pending.size();
  }

  /** What this session counted. */
  public ControlCounters counters() {
    return counters;
  }

  private RequestResult refuse(RequestRefusal refusal) {
    ++counters.refusedRequests[refusal.ordinal()];
    return new RequestResult(0, refusal);
  }

  /** Frames {@code message} with the next id; 0 when it does not fit a frame. */
  private long queue(ClientMessage message, RequestKind kind, long nowMs, boolean keepAlive) {
    int requestId = lastRequestId == -1 ? 1 : lastRequestId + 1;
    byte[] frame = Frames.frame(message.toBuilder().setRequestId(requestId).build());
    if (frame == null) return 0;
    lastRequestId = requestId;
    outbox.write(frame, 0, frame.length);
    ++counters.framesOut;
    counters.bytesOut += frame.length;
    lastSentMs = nowMs;
    pending.addLast(new Pending(unsigned(requestId), kind, nowMs, keepAlive));
    return unsigned(requestId);
  }

  private void onMessage(ServerMessage message) {
    if (message.getRequestId() != 0) {
      onReply(message);
      return;
    }
    switch (message.getBodyCase()) {
      case MATCH_RESULTS:
        if (state == ControlState.IN_MATCH) state = ControlState.AUTHENTICATED;
        events.addLast(new ControlEvent.MatchResultsArrived(message.getMatchResults()));
        return;
      case ERROR:
        end(ControlCloseReason.SERVER_ERROR,
            "the server closed the connection: " + describe(message.getError()),
            message.getError());
        return;
      default:
        end(ControlCloseReason.UNEXPECTED_MESSAGE,
            "the server sent a " + bodyName(message)
                + " with request_id 0; only match_results and a closing error come unasked",
            null);
    }
  }

  private void onReply(ServerMessage message) {
    long requestId = unsigned(message.getRequestId());
    Pending request = null;
    for (Iterator<Pending> it = pending.iterator(); it.hasNext();) {
      Pending candidate = it.next();
      if (candidate.requestId == requestId) {
        request = candidate;
        break;
      }
    }
    if (request == null) {
      end(ControlCloseReason.UNKNOWN_REQUEST,
          "the server answered request " + requestId + ", which is not pending (" + pending.size()
              + " are)",
          null);
      return;
    }
    if (!request.kind.answeredBy(message.getBodyCase())) {
      end(ControlCloseReason.WRONG_REPLY,
          "the server answered " + requestName(requestId, request.kind) + " with a "
              + bodyName(message),
          null);
      return;
    }
    pending.remove(request);
    switch (message.getBodyCase()) {
      case SESSION:
        // A resume back in the match its sign-in plays (PROTOCOL.md, resume): in the match again.
        state = request.kind == RequestKind.RESUME && message.getSession().getMatchId() != 0
            ? ControlState.IN_MATCH
            : ControlState.AUTHENTICATED;
        break;
      case JOIN_MATCH:
        state = ControlState.IN_MATCH;
        break;
      case LEAVE_MATCH:
        state = ControlState.AUTHENTICATED;
        break;
      case LOGOUT:
        state = ControlState.UNAUTHENTICATED;
        break;
      case ERROR:
        if (request.kind == RequestKind.LEAVE_MATCH
            && message.getError().getCode() == ErrorCode.NOT_IN_MATCH) {
          state = ControlState.AUTHENTICATED; // the match had already let go of the seat
        }
        break;
      default:
        break;
    }
    if (!request.keepAlive)
      events.addLast(new ControlEvent.Reply(requestId, request.kind, message));
  }

  private void end(ControlCloseReason reason, String detail, Error serverError) {
    if (state == ControlState.CLOSED) return;
    state = ControlState.CLOSED;
    ++counters.closes[reason.ordinal()];
    pending.clear();
    outbox.reset();
    events.addLast(new ControlEvent.Closed(reason, detail, serverError));
  }

  private static long unsigned(int value) {
    return value & 0xFFFFFFFFL;
  }

  private static String requestName(long requestId, RequestKind kind) {
    return "request " + requestId + " (" + kind.counterName() + ")";
  }

  private static String bodyName(ServerMessage message) {
    return message.getBodyCase().name().toLowerCase(Locale.ROOT);
  }

  private static String describe(Error error) {
    String code = error.getCode() == ErrorCode.UNRECOGNIZED ? "error code " + error.getCodeValue()
                                                            : error.getCode().name();
    return code + ": " + error.getMessage();
  }
}
