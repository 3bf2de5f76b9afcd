package io.ricochet.client.core.control;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.core.FrameReader;
import io.ricochet.client.core.Frames;
import io.ricochet.wire.ControlProto.ChatRequest;
import io.ricochet.wire.ControlProto.ClientMessage;
import io.ricochet.wire.ControlProto.CreateMatchReply;
import io.ricochet.wire.ControlProto.CreateMatchRequest;
import io.ricochet.wire.ControlProto.Error;
import io.ricochet.wire.ControlProto.ErrorCode;
import io.ricochet.wire.ControlProto.JoinMatchReply;
import io.ricochet.wire.ControlProto.JoinMatchRequest;
import io.ricochet.wire.ControlProto.LeaveMatchReply;
import io.ricochet.wire.ControlProto.LeaveMatchRequest;
import io.ricochet.wire.ControlProto.ListMatchesReply;
import io.ricochet.wire.ControlProto.ListMatchesRequest;
import io.ricochet.wire.ControlProto.LoginRequest;
import io.ricochet.wire.ControlProto.LogoutReply;
import io.ricochet.wire.ControlProto.LogoutRequest;
import io.ricochet.wire.ControlProto.MatchResults;
import io.ricochet.wire.ControlProto.Pong;
import io.ricochet.wire.ControlProto.ResumeRequest;
import io.ricochet.wire.ControlProto.ServerMessage;
import io.ricochet.wire.ControlProto.SessionReply;
import java.util.ArrayList;
import java.util.List;
import java.util.Random;
import org.junit.jupiter.api.Test;

/** The control session with fake time: numbering, states, matching, timeouts and refusals. */
class ControlSessionTest {
  private static final ClientMessage LOGIN =
      ClientMessage.newBuilder()
          .setLogin(LoginRequest.newBuilder().setUsername("alice").setPassword("password1"))
          .build();
  private static final ClientMessage LIST =
      ClientMessage.newBuilder().setListMatches(ListMatchesRequest.getDefaultInstance()).build();
  private static final ClientMessage CREATE =
      ClientMessage.newBuilder()
          .setCreateMatch(CreateMatchRequest.newBuilder().setName("m").setMaxPlayers(2))
          .build();
  private static final ClientMessage JOIN =
      ClientMessage.newBuilder().setJoinMatch(JoinMatchRequest.newBuilder().setMatchId(7)).build();
  private static final ClientMessage LEAVE =
      ClientMessage.newBuilder().setLeaveMatch(LeaveMatchRequest.getDefaultInstance()).build();
  private static final ClientMessage CHAT =
      ClientMessage.newBuilder().setChat(ChatRequest.newBuilder().setText("hi")).build();
  private static final ClientMessage LOGOUT =
      ClientMessage.newBuilder().setLogout(LogoutRequest.getDefaultInstance()).build();
  private static final ClientMessage RESUME =
      ClientMessage.newBuilder()
          .setResume(ResumeRequest.newBuilder().setSessionToken(repeat('a', 64)))
          .build();

  private static String repeat(char c, int times) {
    StringBuilder out = new StringBuilder();
    for (int i = 0; i < times; ++i) out.append(c);
    return out.toString();
  }

  /** The client messages in {@code bytes}, which must be whole frames. */
  private static List<ClientMessage> sent(byte[] bytes) throws Exception {
    List<ClientMessage> out = new ArrayList<>();
    if (bytes == null) return out;
    FrameReader reader = new FrameReader();
    reader.feed(bytes);
    while (reader.next() == FrameReader.Status.FRAME) {
      out.add(ClientMessage.parseFrom(reader.payload()));
    }
    assertEquals(0, reader.buffered());
    return out;
  }

  private static void deliver(ControlSession session, ServerMessage message) {
    byte[] frame = Frames.frame(message);
    session.receive(frame, 0, frame.length);
  }

  private static ServerMessage reply(long requestId, ServerMessage.Builder body) {
    return body.setRequestId((int) requestId).build();
  }

  private static ServerMessage.Builder session() {
    return ServerMessage.newBuilder().setSession(
        SessionReply.newBuilder().setAccountId(3).setUsername("alice"));
  }

  private static ServerMessage.Builder error(ErrorCode code) {
    return ServerMessage.newBuilder().setError(
        Error.newBuilder().setCode(code).setMessage("because"));
  }

  private static ControlEvent.Closed closedEvent(ControlSession session) {
    ControlEvent event;
    ControlEvent.Closed closed = null;
    while ((event = session.pollEvent()) != null) {
      if (event instanceof ControlEvent.Closed) closed = (ControlEvent.Closed) event;
    }
    assertNotNull(closed, "a Closed event");
    assertEquals(ControlState.CLOSED, session.state());
    return closed;
  }

  /** A session signed in (its login answered), at time 0. */
  private static ControlSession signedIn() {
    ControlSession session = new ControlSession(0);
    RequestResult login = session.request(LOGIN, 0);
    deliver(session, reply(login.requestId(), session()));
    assertInstanceOf(ControlEvent.Reply.class, session.pollEvent());
    session.pollTransmit();
    assertEquals(ControlState.AUTHENTICATED, session.state());
    return session;
  }

  @Test
  void requestIdsCountFromOneAndWrapPastTheLargestToOne() throws Exception {
    ControlSession fresh = new ControlSession(0);
    assertEquals(1, fresh.request(LOGIN, 0).requestId());
    assertEquals(2, fresh.request(LOGIN, 0).requestId());
    List<ClientMessage> frames = sent(fresh.pollTransmit());
    assertEquals(2, frames.size());
    assertEquals(1, frames.get(0).getRequestId());
    assertEquals(2, frames.get(1).getRequestId());

    ControlSession late = new ControlSession(0, 0, 0, 0xFFFFFFFE);
    assertEquals(0xFFFFFFFFL, late.request(LOGIN, 0).requestId());
    assertEquals(1, late.request(LOGIN, 0).requestId()); // never 0: that is the server's own
    frames = sent(late.pollTransmit());
    assertEquals(0xFFFFFFFFL, frames.get(0).getRequestId() & 0xFFFFFFFFL);
    assertEquals(1, frames.get(1).getRequestId());
    // The reply to the request numbered 2^32-1 is matched like any other.
    deliver(late, reply(0xFFFFFFFFL, error(ErrorCode.WRONG_CREDENTIALS)));
    ControlEvent.Reply answer = (ControlEvent.Reply) late.pollEvent();
    assertEquals(0xFFFFFFFFL, answer.requestId());
    assertTrue(answer.isError());
  }

  @Test
  void whatTheStateDoesNotAllowIsRefusedLocallyCountedAndNeverSent() {
    ControlSession session = new ControlSession(0);
    for (ClientMessage early : new ClientMessage[] {LIST, CREATE, JOIN, LEAVE, CHAT, LOGOUT}) {
      RequestResult result = session.request(early, 0);
      assertFalse(result.queued(), early.getBodyCase().name());
      assertEquals(RequestRefusal.WRONG_STATE, result.refusal());
    }
    assertEquals(6, session.counters().refusedRequests(RequestRefusal.WRONG_STATE));
    assertEquals(
        RequestRefusal.NO_BODY, session.request(ClientMessage.getDefaultInstance(), 0).refusal());
    StringBuilder huge = new StringBuilder();
    for (int i = 0; i < 70_000; ++i) huge.append('x');
    ControlSession in = signedIn();
    deliver(in,
        reply(in.request(JOIN, 0).requestId(),
            ServerMessage.newBuilder().setJoinMatch(JoinMatchReply.newBuilder().setMatchId(7))));
    assertEquals(ControlState.IN_MATCH, in.state());
    ClientMessage tooLarge = ClientMessage.newBuilder()
                                 .setChat(ChatRequest.newBuilder().setText(huge.toString()))
                                 .build();
    assertEquals(RequestRefusal.TOO_LARGE, in.request(tooLarge, 0).refusal());
    assertEquals(1, in.counters().refusedRequests(RequestRefusal.TOO_LARGE));
    assertNull(session.pollTransmit(), "nothing refused was queued");
    assertEquals(0, session.counters().framesOut());
    // A list_matches waits for the login's reply: the state is the replies'.
    assertTrue(session.request(LOGIN, 0).queued());
    assertEquals(RequestRefusal.WRONG_STATE, session.request(LIST, 0).refusal());
    session.close();
    assertEquals(RequestRefusal.CLOSED, session.request(LOGIN, 0).refusal());
    assertEquals(1, session.counters().refusedRequests(RequestRefusal.CLOSED));
  }

  @Test
  void repliesInAnyOrderAreMatchedToTheirRequests() {
    ControlSession session = signedIn();
    long list = session.request(LIST, 10).requestId();
    long create = session.request(CREATE, 10).requestId();
    assertEquals(2, session.pending());
    deliver(session,
        reply(create,
            ServerMessage.newBuilder().setCreateMatch(CreateMatchReply.getDefaultInstance())));
    deliver(session,
        reply(list,
            ServerMessage.newBuilder().setListMatches(ListMatchesReply.getDefaultInstance())));
    ControlEvent.Reply first = (ControlEvent.Reply) session.pollEvent();
    ControlEvent.Reply second = (ControlEvent.Reply) session.pollEvent();
    assertEquals(create, first.requestId());
    assertEquals(RequestKind.CREATE_MATCH, first.kind());
    assertEquals(list, second.requestId());
    assertEquals(RequestKind.LIST_MATCHES, second.kind());
    assertEquals(0, session.pending());
    assertNull(session.pollEvent());
  }

  /** A resumed connection back in its match (PROTOCOL.md, resume): in the match at once. */
  @Test
  void aResumeBackInTheMatchIsInTheMatch() throws Exception {
    ControlSession resumed = new ControlSession(0);
    deliver(resumed,
        reply(resumed.request(RESUME, 0).requestId(),
            ServerMessage.newBuilder().setSession(
                SessionReply.newBuilder().setAccountId(3).setUsername("alice").setMatchId(7))));
    assertEquals(ControlState.IN_MATCH, resumed.state());
    RequestResult chat = resumed.request(CHAT, 0);
    assertTrue(chat.queued(), chat.toString());
    assertEquals(2, sent(resumed.pollTransmit()).size(), "the resume, then the chat");
    deliver(resumed,
        reply(resumed.request(LEAVE, 0).requestId(),
            ServerMessage.newBuilder().setLeaveMatch(LeaveMatchReply.getDefaultInstance())));
    assertEquals(ControlState.AUTHENTICATED, resumed.state());

    // No match_id: only signed in, so leave is refused locally.
    ControlSession signedInOnly = new ControlSession(0);
    deliver(signedInOnly, reply(signedInOnly.request(RESUME, 0).requestId(), session()));
    assertEquals(ControlState.AUTHENTICATED, signedInOnly.state());
    assertEquals(RequestRefusal.WRONG_STATE, signedInOnly.request(LEAVE, 0).refusal());

    // A match_id answering a login means nothing.
    ControlSession loggedIn = new ControlSession(0);
    deliver(loggedIn,
        reply(loggedIn.request(LOGIN, 0).requestId(),
            ServerMessage.newBuilder().setSession(
                SessionReply.newBuilder().setAccountId(3).setUsername("alice").setMatchId(7))));
    assertEquals(ControlState.AUTHENTICATED, loggedIn.state());
  }

  @Test
  void theStatesFollowTheReplies() {
    ControlSession session = signedIn();
    deliver(session,
        reply(session.request(JOIN, 0).requestId(),
            ServerMessage.newBuilder().setJoinMatch(JoinMatchReply.newBuilder().setMatchId(7))));
    assertEquals(ControlState.IN_MATCH, session.state());
    deliver(session,
        reply(session.request(LEAVE, 0).requestId(),
            ServerMessage.newBuilder().setLeaveMatch(LeaveMatchReply.getDefaultInstance())));
    assertEquals(ControlState.AUTHENTICATED, session.state());
    // A failed join leaves the state as it was.
    deliver(session, reply(session.request(JOIN, 0).requestId(), error(ErrorCode.MATCH_FULL)));
    assertEquals(ControlState.AUTHENTICATED, session.state());
    deliver(session,
        reply(session.request(JOIN, 0).requestId(),
            ServerMessage.newBuilder().setJoinMatch(JoinMatchReply.newBuilder().setMatchId(7))));
    // NOT_IN_MATCH to a leave: the match had already let go of the seat.
    deliver(session, reply(session.request(LEAVE, 0).requestId(), error(ErrorCode.NOT_IN_MATCH)));
    assertEquals(ControlState.AUTHENTICATED, session.state());
    deliver(session,
        reply(session.request(JOIN, 0).requestId(),
            ServerMessage.newBuilder().setJoinMatch(JoinMatchReply.newBuilder().setMatchId(7))));
    // MatchResults (request_id 0) ends the match.
    deliver(session,
        ServerMessage.newBuilder()
            .setMatchResults(MatchResults.newBuilder().setMatchId(7))
            .build());
    assertEquals(ControlState.AUTHENTICATED, session.state());
    ControlEvent event;
    ControlEvent last = null;
    while ((event = session.pollEvent()) != null) last = event;
    assertEquals(7, ((ControlEvent.MatchResultsArrived) last).results().getMatchId());
    deliver(session,
        reply(session.request(LOGOUT, 0).requestId(),
            ServerMessage.newBuilder().setLogout(LogoutReply.getDefaultInstance())));
    assertEquals(ControlState.UNAUTHENTICATED, session.state());
    // A failed login leaves it unauthenticated.
    deliver(
        session, reply(session.request(LOGIN, 0).requestId(), error(ErrorCode.WRONG_CREDENTIALS)));
    assertEquals(ControlState.UNAUTHENTICATED, session.state());
  }

  @Test
  void aReplyToNoPendingRequestClosesTheSessionCounted() {
    ControlSession session = signedIn();
    session.request(LIST, 0);
    deliver(session,
        reply(
            99, ServerMessage.newBuilder().setListMatches(ListMatchesReply.getDefaultInstance())));
    assertEquals(ControlCloseReason.UNKNOWN_REQUEST, closedEvent(session).reason());
    assertEquals(1, session.counters().closes(ControlCloseReason.UNKNOWN_REQUEST));
    assertEquals(0, session.pending());
  }

  @Test
  void aSecondReplyToTheSameRequestIsRefused() {
    ControlSession session = signedIn();
    long list = session.request(LIST, 0).requestId();
    ServerMessage answer = reply(
        list, ServerMessage.newBuilder().setListMatches(ListMatchesReply.getDefaultInstance()));
    deliver(session, answer);
    assertInstanceOf(ControlEvent.Reply.class, session.pollEvent());
    deliver(session, answer);
    assertEquals(ControlCloseReason.UNKNOWN_REQUEST, closedEvent(session).reason());
  }

  @Test
  void aReplyOfTheWrongKindClosesTheSessionCounted() {
    ControlSession session = signedIn();
    long list = session.request(LIST, 0).requestId();
    deliver(session,
        reply(list, ServerMessage.newBuilder().setLogout(LogoutReply.getDefaultInstance())));
    assertEquals(ControlCloseReason.WRONG_REPLY, closedEvent(session).reason());
    assertEquals(1, session.counters().closes(ControlCloseReason.WRONG_REPLY));
  }

  @Test
  void onlyMatchResultsAndAClosingErrorComeUnasked() {
    ControlSession session = signedIn();
    deliver(session, ServerMessage.newBuilder().setPong(Pong.getDefaultInstance()).build());
    assertEquals(ControlCloseReason.UNEXPECTED_MESSAGE, closedEvent(session).reason());

    ControlSession other = signedIn();
    deliver(other, error(ErrorCode.SHUTTING_DOWN).build());
    ControlEvent.Closed closed = closedEvent(other);
    assertEquals(ControlCloseReason.SERVER_ERROR, closed.reason());
    assertEquals(ErrorCode.SHUTTING_DOWN, closed.serverError().getCode());
    assertFalse(closed.reason().refusesServer());
  }

  @Test
  void aRequestWithNoReplyInTimeClosesTheSession() {
    ControlSession session = new ControlSession(1_000, 60_000, 0);
    session.request(LOGIN, 1_000);
    assertEquals(61_000, session.deadlineMs());
    session.update(60_999);
    assertEquals(ControlState.UNAUTHENTICATED, session.state());
    session.update(61_000);
    assertEquals(ControlCloseReason.REQUEST_TIMEOUT, closedEvent(session).reason());
    assertEquals(Long.MAX_VALUE, session.deadlineMs());
  }

  @Test
  void aQuietSessionPingsAndConsumesThePong() throws Exception {
    ControlSession session = new ControlSession(0, 60_000, 30_000);
    assertEquals(30_000, session.deadlineMs());
    session.update(29_999);
    assertNull(session.pollTransmit());
    session.update(30_000);
    List<ClientMessage> frames = sent(session.pollTransmit());
    assertEquals(1, frames.size());
    assertTrue(frames.get(0).hasPing());
    assertEquals(30_000_000L, frames.get(0).getPing().getClientTimeUs());
    assertEquals(1, session.counters().keepAlives());
    deliver(session,
        reply(frames.get(0).getRequestId(),
            ServerMessage.newBuilder().setPong(Pong.getDefaultInstance())));
    assertNull(session.pollEvent(), "its own pong is no event");
    assertEquals(0, session.pending());
    // The next one is due 30 s after the last frame sent, not before.
    session.request(LOGIN, 40_000);
    session.pollTransmit();
    session.update(69_999);
    assertNull(session.pollTransmit());
    session.update(70_000);
    assertTrue(sent(session.pollTransmit()).get(0).hasPing());
  }

  @Test
  void framesSplitAnywhereAreReassembled() {
    ControlSession session = new ControlSession(0);
    long login = session.request(LOGIN, 0).requestId();
    byte[] frame = Frames.frame(reply(login, session()));
    for (int i = 0; i < frame.length; ++i) session.receive(frame, i, 1);
    assertInstanceOf(ControlEvent.Reply.class, session.pollEvent());
    assertEquals(ControlState.AUTHENTICATED, session.state());
    assertEquals(frame.length, session.counters().bytesIn());
    assertEquals(1, session.counters().framesIn());
  }

  @Test
  void brokenFramesCloseTheSessionWithTheirReason() {
    byte[][] inputs = {
        {0x00, 0x01, 0x00, 0x01}, // 65537 bytes declared
        {0, 0, 0, 0}, {0, 0, 0, 2, (byte) 0xFF, (byte) 0xFF}, // not protobuf
        {0, 0, 0, 2, 0x08, 0x05}, // request_id 5, no body
    };
    ControlCloseReason[] reasons = {
        ControlCloseReason.FRAME_OVERSIZE,
        ControlCloseReason.FRAME_EMPTY,
        ControlCloseReason.MALFORMED,
        ControlCloseReason.MISSING_BODY,
    };
    for (int i = 0; i < inputs.length; ++i) {
      ControlSession session = new ControlSession(0);
      session.receive(inputs[i], 0, inputs[i].length);
      ControlEvent.Closed closed = closedEvent(session);
      assertEquals(reasons[i], closed.reason());
      assertTrue(closed.reason().refusesServer());
      assertEquals(1, session.counters().closes(reasons[i]));
    }
  }

  @Test
  void garbageNeverThrowsAndClosesAtMostOnce() {
    Random random = new Random(30);
    for (int round = 0; round < 2_000; ++round) {
      ControlSession session = signedIn();
      session.request(LIST, 0);
      session.request(JOIN, 0);
      byte[] bytes = new byte[random.nextInt(64)];
      random.nextBytes(bytes);
      if (bytes.length >= 4 && random.nextBoolean()) {
        bytes[0] = 0; // a plausible length, so the payload is parsed
        bytes[1] = 0;
        bytes[2] = 0;
        bytes[3] = (byte) (bytes.length - 4);
      }
      session.receive(bytes, 0, bytes.length);
      session.update(1);
      long closes = 0;
      for (ControlCloseReason reason : ControlCloseReason.values()) {
        closes += session.counters().closes(reason);
      }
      assertTrue(closes <= 1);
      if (session.state() == ControlState.CLOSED) {
        assertEquals(1, closes);
        assertEquals(0, session.pending());
        assertNull(session.pollTransmit());
      }
    }
  }

  @Test
  void closeDropsWhatIsQueuedAndPending() {
    ControlSession session = signedIn();
    session.request(LIST, 0);
    session.close();
    assertNull(session.pollTransmit());
    assertEquals(0, session.pending());
    assertEquals(ControlCloseReason.REQUESTED, closedEvent(session).reason());
    session.connectionLost("later");
    assertEquals(0, session.counters().closes(ControlCloseReason.CONNECTION_LOST));
    byte[] frame = Frames.frame(reply(1, session()));
    session.receive(frame, 0, frame.length);
    assertNull(session.pollEvent(), "nothing after Closed");
  }
}
