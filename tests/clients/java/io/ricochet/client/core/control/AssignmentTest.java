package io.ricochet.client.core.control;

import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertInstanceOf;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import com.google.protobuf.ByteString;
import io.ricochet.client.core.Frames;
import io.ricochet.wire.ControlProto.ClientMessage;
import io.ricochet.wire.ControlProto.Error;
import io.ricochet.wire.ControlProto.ErrorCode;
import io.ricochet.wire.ControlProto.FindMatchReply;
import io.ricochet.wire.ControlProto.FindMatchRequest;
import io.ricochet.wire.ControlProto.JoinMatchReply;
import io.ricochet.wire.ControlProto.JoinMatchRequest;
import io.ricochet.wire.ControlProto.LoginRequest;
import io.ricochet.wire.ControlProto.ServerMessage;
import io.ricochet.wire.ControlProto.SessionReply;
import org.junit.jupiter.api.Test;

/**
 * Placement in the sans-IO core with fake time (PROTOCOL.md, Placement): find_match and its
 * reply through the {@link ControlSession}, the {@link Assignment} made of it (what a client needs
 * to follow it, refused when it cannot be followed), its ticket's expiry, and the join with the
 * ticket.
 */
class AssignmentTest {
  private static final String FINGERPRINT =
      "4ca9e7a1b0c2d3e4f5061728394a5b6c7d8e9fa0b1c2d3e4f50617283940ab25";

  private static io.ricochet.wire.ControlProto.Assignment.Builder elsewhere() {
    byte[] ticket = new byte[Assignment.TICKET_BYTES];
    for (int i = 0; i < ticket.length; ++i) ticket[i] = (byte) (0xa0 + i);
    return io.ricochet.wire.ControlProto.Assignment.newBuilder()
        .setConnection("game-2.example.net:7787")
        .setGamePort(7788)
        .setCertificateSha256(FINGERPRINT)
        .setMatchId(3)
        .setMode("tdm")
        .setMap("foundry")
        .setTicket(ByteString.copyFrom(ticket))
        .setTicketExpiresInMs(30_000);
  }

  private static void deliver(ControlSession session, ServerMessage message) {
    byte[] frame = Frames.frame(message);
    session.receive(frame, 0, frame.length);
  }

  private static ControlEvent.Reply replyTo(ControlSession session, long requestId) {
    ControlEvent event = session.pollEvent();
    assertInstanceOf(ControlEvent.Reply.class, event);
    ControlEvent.Reply reply = (ControlEvent.Reply) event;
    assertEquals(requestId, reply.requestId());
    return reply;
  }

  @Test
  void anAssignmentElsewhereGivesWhatAClientNeedsToFollowItAndExpiresOnTheCallersClock() {
    Assignment.Result result = Assignment.of(elsewhere().build(), 1_000);
    Assignment assignment = result.assignment();
    assertNotNull(assignment, result.detail());
    assertNull(result.refusal());
    assertEquals("game-2.example.net", assignment.host());
    assertEquals(7787, assignment.controlPort());
    assertEquals(7788, assignment.gamePort());
    assertEquals(FINGERPRINT, assignment.certificateSha256());
    assertEquals(3, assignment.matchId());
    assertEquals("tdm", assignment.mode());
    assertEquals("foundry", assignment.map());
    assertEquals(Assignment.TICKET_BYTES, assignment.ticket().length);
    assertEquals((byte) 0xa0, assignment.ticket()[0]);
    assignment.ticket()[0] = 0; // a copy
    assertEquals((byte) 0xa0, assignment.ticket()[0]);
    assertFalse(assignment.onThisServer());
    assertEquals("game-2.example.net:7787", assignment.connection());
    // 30 s from the reply, on the clock the caller passed in.
    assertEquals(30_000, assignment.ticketExpiresInMs());
    assertEquals(31_000, assignment.expiresAtMs());
    assertFalse(assignment.expiredAt(1_000));
    assertFalse(assignment.expiredAt(30_999));
    assertTrue(assignment.expiredAt(31_000));

    // Uppercase fingerprints are the server's to avoid, ours to accept; unsigned fields stay so.
    Assignment big = Assignment
                         .of(elsewhere()
                                 .setCertificateSha256(FINGERPRINT.toUpperCase())
                                 .setMatchId(0xFFFFFFFF)
                                 .setTicketExpiresInMs(0xFFFFFFFF)
                                 .build(),
                             0)
                         .assignment();
    assertEquals(FINGERPRINT, big.certificateSha256());
    assertEquals(0xFFFFFFFFL, big.matchId());
    assertEquals(0xFFFFFFFFL, big.expiresAtMs());
  }

  @Test
  void ipv6ComesInBracketsAndAnAssignmentOnThisServerWithANewMatchIsFollowedInPlace() {
    Assignment here = Assignment
                          .of(elsewhere()
                                  .setConnection("[::1]:7777")
                                  .setMatchId(0)
                                  .setMap("")
                                  .setOnThisServer(true)
                                  .build(),
                              5)
                          .assignment();
    assertEquals("::1", here.host());
    assertEquals(7777, here.controlPort());
    assertEquals("[::1]:7777", here.connection());
    assertTrue(here.onThisServer());
    assertEquals(0, here.matchId(), "a new match is made when the ticket is used");
    assertEquals("", here.map());
  }

  @Test
  void anAssignmentThatCannotBeFollowedIsRefusedWithItsReasonNeverAnException() {
    Object[][] cases = {
        {elsewhere().clearConnection(), AssignmentRefusal.CONNECTION},
        {elsewhere().setConnection("host-only"), AssignmentRefusal.CONNECTION},
        {elsewhere().setConnection(":7777"), AssignmentRefusal.CONNECTION},
        {elsewhere().setConnection("host:0"), AssignmentRefusal.CONNECTION},
        {elsewhere().setConnection("host:65536"), AssignmentRefusal.CONNECTION},
        {elsewhere().setConnection("host:+777"), AssignmentRefusal.CONNECTION},
        {elsewhere().setConnection("host:"), AssignmentRefusal.CONNECTION},
        {elsewhere().setConnection("::1:7777"), AssignmentRefusal.CONNECTION},
        {elsewhere().setConnection("[]:7777"), AssignmentRefusal.CONNECTION},
        {elsewhere().setConnection("[host]:7777"), AssignmentRefusal.CONNECTION},
        {elsewhere().setGamePort(0), AssignmentRefusal.GAME_PORT},
        {elsewhere().setGamePort(65536), AssignmentRefusal.GAME_PORT},
        {elsewhere().setCertificateSha256(FINGERPRINT.substring(1)), AssignmentRefusal.CERTIFICATE},
        {elsewhere().setCertificateSha256(FINGERPRINT.replace('a', 'g')),
            AssignmentRefusal.CERTIFICATE},
        {elsewhere().setTicket(ByteString.copyFrom(new byte[31])), AssignmentRefusal.TICKET},
        {elsewhere().clearTicket(), AssignmentRefusal.TICKET},
        {elsewhere().clearMode(), AssignmentRefusal.MODE},
    };
    for (Object[] each : cases) {
      io.ricochet.wire.ControlProto.Assignment wire =
          ((io.ricochet.wire.ControlProto.Assignment.Builder) each[0]).build();
      Assignment.Result result = Assignment.of(wire, 0);
      assertNull(result.assignment(), wire.toString());
      assertEquals(each[1], result.refusal(), wire.toString());
      assertTrue(
          result.detail().contains(((AssignmentRefusal) each[1]).counterName()), result.detail());
    }
  }

  @Test
  void findMatchLeavesTheStateAndTheTicketJoinsOnTheServerItNames() {
    // On A: signed in, find_match (allowed signed in only), the assignment elsewhere.
    ControlSession a = new ControlSession(0);
    ClientMessage find = ClientMessage.newBuilder()
                             .setFindMatch(FindMatchRequest.newBuilder().setMode("tdm"))
                             .build();
    assertEquals(RequestRefusal.WRONG_STATE, a.request(find, 0).refusal());
    long login =
        a.request(
             ClientMessage.newBuilder()
                 .setLogin(LoginRequest.newBuilder().setUsername("alice").setPassword("password1"))
                 .build(),
             0)
            .requestId();
    deliver(a,
        ServerMessage.newBuilder()
            .setRequestId((int) login)
            .setSession(SessionReply.newBuilder().setAccountId(7).setSessionToken("ab"))
            .build());
    replyTo(a, login);
    long found = a.request(find, 100).requestId();
    // The request times out like any other, on fake time: not before 60 s after it was sent.
    a.update(60_099);
    assertEquals(ControlState.AUTHENTICATED, a.state());
    deliver(a,
        ServerMessage.newBuilder()
            .setRequestId((int) found)
            .setFindMatch(FindMatchReply.newBuilder().setAssignment(elsewhere()))
            .build());
    ControlEvent.Reply reply = replyTo(a, found);
    assertEquals(RequestKind.FIND_MATCH, reply.kind());
    assertEquals(ControlState.AUTHENTICATED, a.state(), "an assignment seats nobody yet");
    Assignment assignment =
        Assignment.of(reply.message().getFindMatch().getAssignment(), 60_100).assignment();
    assertEquals(90_100, assignment.expiresAtMs());

    // Each placement error answers its request and keeps the connection as it was.
    for (ErrorCode code : new ErrorCode[] {ErrorCode.NO_SERVER_AVAILABLE,
             ErrorCode.UNKNOWN_MODE_OR_MAP, ErrorCode.FIND_MATCH_RATE_LIMITED}) {
      long again = a.request(find, 60_200).requestId();
      deliver(a,
          ServerMessage.newBuilder()
              .setRequestId((int) again)
              .setError(Error.newBuilder().setCode(code).setMessage("because"))
              .build());
      ControlEvent.Reply refused = replyTo(a, again);
      assertTrue(refused.isError());
      assertEquals(code, refused.message().getError().getCode());
      assertEquals(ControlState.AUTHENTICATED, a.state(), code.name());
    }

    // On B, once resumed: a join with the ticket; the ticket's errors keep it signed in.
    ControlSession b = new ControlSession(60_300);
    long resumed =
        b.request(
             ClientMessage.newBuilder()
                 .setResume(
                     io.ricochet.wire.ControlProto.ResumeRequest.newBuilder().setSessionToken("ab"))
                 .build(),
             60_300)
            .requestId();
    deliver(b,
        ServerMessage.newBuilder()
            .setRequestId((int) resumed)
            .setSession(SessionReply.newBuilder().setAccountId(7))
            .build());
    replyTo(b, resumed);
    ClientMessage join = ClientMessage.newBuilder()
                             .setJoinMatch(JoinMatchRequest.newBuilder().setTicket(
                                 ByteString.copyFrom(assignment.ticket())))
                             .build();
    for (ErrorCode code : new ErrorCode[] {ErrorCode.UNKNOWN_TICKET, ErrorCode.EXPIRED_TICKET}) {
      long refused = b.request(join, 60_400).requestId();
      deliver(b,
          ServerMessage.newBuilder()
              .setRequestId((int) refused)
              .setError(Error.newBuilder().setCode(code))
              .build());
      assertEquals(code, replyTo(b, refused).message().getError().getCode());
      assertEquals(ControlState.AUTHENTICATED, b.state(), code.name());
    }
    assertFalse(assignment.expiredAt(60_500));
    long joined = b.request(join, 60_500).requestId();
    deliver(b,
        ServerMessage.newBuilder()
            .setRequestId((int) joined)
            .setJoinMatch(JoinMatchReply.newBuilder().setMatchId(3).setUdpPort(7788))
            .build());
    assertEquals(RequestKind.JOIN_MATCH, replyTo(b, joined).kind());
    assertEquals(ControlState.IN_MATCH, b.state());
    // In the match, find_match is still allowed (PROTOCOL.md's table).
    assertTrue(b.request(find, 60_600).queued());
  }
}
