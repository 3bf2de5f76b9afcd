package io.ricochet.client;

import static io.ricochet.client.ClientTesting.await;
import static io.ricochet.client.ClientTesting.failure;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertNotNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import io.ricochet.client.core.FrameReader;
import io.ricochet.client.core.Frames;
import io.ricochet.client.core.control.ControlCloseReason;
import io.ricochet.client.core.control.ControlState;
import io.ricochet.wire.ControlProto.ClientMessage;
import io.ricochet.wire.ControlProto.ErrorCode;
import io.ricochet.wire.ControlProto.ListMatchesReply;
import io.ricochet.wire.ControlProto.MatchResults;
import io.ricochet.wire.ControlProto.Pong;
import io.ricochet.wire.ControlProto.ServerMessage;
import io.ricochet.wire.ControlProto.SessionReply;
import java.io.IOException;
import java.io.InputStream;
import java.net.InetAddress;
import java.net.InetSocketAddress;
import java.net.ServerSocket;
import java.net.Socket;
import java.util.List;
import java.util.concurrent.ArrayBlockingQueue;
import java.util.concurrent.BlockingQueue;
import java.util.concurrent.CompletableFuture;
import java.util.concurrent.CopyOnWriteArrayList;
import java.util.concurrent.TimeUnit;
import org.junit.jupiter.api.AfterEach;
import org.junit.jupiter.api.BeforeEach;
import org.junit.jupiter.api.Test;

/**
 * The client's I/O layer against a server this test plays itself, over plain TCP on 127.0.0.1
 * (TLS replaced through the package's test seam): what the real server never does (results on
 * cue, garbage, silence) reaches the listener as the protocol says, and never as an exception.
 */
class ScriptedServerTest {
  private ServerSocket listening;
  private Socket peer;
  private InputStream fromClient;
  private final FrameReader frames = new FrameReader();
  private final List<Throwable> uncaught = new CopyOnWriteArrayList<>();
  private Thread.UncaughtExceptionHandler previousHandler;

  /** Records every disconnect and result, and the threads they came on. */
  private static final class Recorder implements RicochetClient.Listener {
    final BlockingQueue<Disconnect> disconnects = new ArrayBlockingQueue<>(4);
    final BlockingQueue<MatchResults> results = new ArrayBlockingQueue<>(4);
    final BlockingQueue<String> threads = new ArrayBlockingQueue<>(8);
    final BlockingQueue<Object> resumes = new ArrayBlockingQueue<>(4); // Session or failure

    @Override
    public void onResumed(Session session) {
      resumes.add(session);
    }

    @Override
    public void onResumeFailed(RicochetException failure) {
      resumes.add(failure);
    }

    @Override
    public void onMatchResults(MatchResults matchResults) {
      threads.add(Thread.currentThread().getName());
      results.add(matchResults);
    }

    @Override
    public void onDisconnected(Disconnect disconnect) {
      threads.add(Thread.currentThread().getName());
      disconnects.add(disconnect);
    }
  }

  @BeforeEach
  void listen() throws IOException {
    listening = new ServerSocket(0, 1, InetAddress.getLoopbackAddress());
    listening.setSoTimeout((int) ClientTesting.WAIT_MS);
    previousHandler = Thread.getDefaultUncaughtExceptionHandler();
    Thread.setDefaultUncaughtExceptionHandler((thread, error) -> uncaught.add(error));
  }

  @AfterEach
  void stop() throws IOException {
    Thread.setDefaultUncaughtExceptionHandler(previousHandler);
    if (peer != null) peer.close();
    listening.close();
    assertTrue(uncaught.isEmpty(), "exceptions escaped: " + uncaught);
  }

  private RicochetClient client(Recorder recorder, long requestTimeoutMs, long keepAliveMs) {
    return builder(recorder, requestTimeoutMs, keepAliveMs).build();
  }

  private RicochetClient.Builder builder(
      Recorder recorder, long requestTimeoutMs, long keepAliveMs) {
    InetSocketAddress address =
        new InetSocketAddress(listening.getInetAddress(), listening.getLocalPort());
    return RicochetClient.builder()
        .host("127.0.0.1")
        .controlPort(listening.getLocalPort())
        .listener(recorder)
        .requestTimeoutMs(requestTimeoutMs)
        .keepAliveMs(keepAliveMs)
        .transportForTest(tcp -> {
          try {
            tcp.connect(address, 10_000);
            return new ControlTransport.Streams(tcp.getInputStream(), tcp.getOutputStream());
          } catch (IOException e) {
            throw new RicochetException(RicochetException.Kind.CONNECT_FAILED, e.toString(), e);
          }
        });
  }

  /** Accepts the client's connection. */
  private void accept() throws IOException {
    peer = listening.accept();
    peer.setSoTimeout((int) ClientTesting.WAIT_MS);
    fromClient = peer.getInputStream();
  }

  /** The client's next message. */
  private ClientMessage next() throws IOException {
    byte[] buffer = new byte[4096];
    while (frames.next() != FrameReader.Status.FRAME) {
      int read = fromClient.read(buffer);
      if (read < 0) throw new IOException("the client closed");
      frames.feed(buffer, 0, read);
    }
    return ClientMessage.parseFrom(frames.payload());
  }

  private void send(byte[] bytes) throws IOException {
    peer.getOutputStream().write(bytes);
    peer.getOutputStream().flush();
  }

  private void send(ServerMessage message) throws IOException {
    send(Frames.frame(message));
  }

  /** Answers the client's login. */
  private void signIn() throws IOException {
    ClientMessage login = next();
    assertTrue(login.hasLogin(), login.toString());
    send(ServerMessage.newBuilder()
             .setRequestId(login.getRequestId())
             .setSession(SessionReply.newBuilder()
                             .setAccountId(5)
                             .setUsername("scripted")
                             .setSessionToken(TOKEN))
             .build());
  }

  private static final String TOKEN =
      "00112233445566778899aabbccddeeff00112233445566778899aabbccddeeff";

  /** Signs the client in, then drops its connection as a lost network would. */
  private CompletableFuture<List<MatchInfo>> signInAndLoseTheConnection(
      RicochetClient client, Recorder recorder) throws Exception {
    CompletableFuture<Session> login = client.login("scripted", "password-1");
    accept();
    signIn();
    await(login);
    peer.close();
    Disconnect lost = recorder.disconnects.poll(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS);
    assertNotNull(lost);
    assertEquals(ControlCloseReason.CONNECTION_LOST, lost.reason(), lost.toString());
    return client.listMatches(); // waits for the resume
  }

  /** Answers the client's next message, a resume with the session's token, with {@code body}. */
  private void answerResume(ServerMessage.Builder reply) throws IOException {
    ClientMessage resume = next();
    assertTrue(resume.hasResume(), resume.toString());
    assertEquals(TOKEN, resume.getResume().getSessionToken());
    send(reply.setRequestId(resume.getRequestId()).build());
  }

  private static ServerMessage.Builder error(ErrorCode code) {
    return ServerMessage.newBuilder().setError(
        io.ricochet.wire.ControlProto.Error.newBuilder().setCode(code).setMessage("scripted"));
  }

  @Test
  void aBusyServerIsAskedAgainOnTheSameConnectionThenTheWaitingCallGoesOut() throws Exception {
    Recorder recorder = new Recorder();
    try (RicochetClient client = builder(recorder, 60_000, 0).resumeBackoffMs(10, 40).build()) {
      CompletableFuture<List<MatchInfo>> waiting = signInAndLoseTheConnection(client, recorder);
      accept();
      answerResume(error(ErrorCode.SERVER_BUSY));
      assertTrue(recorder.resumes.isEmpty(), "a busy server is retried");
      answerResume(ServerMessage.newBuilder().setSession(
          SessionReply.newBuilder().setAccountId(5).setUsername("scripted")));
      Object resumed = recorder.resumes.poll(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS);
      assertTrue(resumed instanceof Session, "onResumed: " + resumed);
      assertEquals(TOKEN, ((Session) resumed).sessionToken());
      ClientMessage list = next();
      assertTrue(list.hasListMatches(), "the waiting call, after the resume: " + list);
      send(ServerMessage.newBuilder()
               .setRequestId(list.getRequestId())
               .setListMatches(ListMatchesReply.getDefaultInstance())
               .build());
      assertTrue(await(waiting).isEmpty());
    }
  }

  @Test
  void anExpiredSessionGivesUpAtOnceAndFailsTheWaitingCall() throws Exception {
    Recorder recorder = new Recorder();
    try (RicochetClient client = builder(recorder, 60_000, 0).resumeBackoffMs(10, 40).build()) {
      CompletableFuture<List<MatchInfo>> waiting = signInAndLoseTheConnection(client, recorder);
      accept();
      answerResume(error(ErrorCode.EXPIRED_SESSION));
      Object gaveUp = recorder.resumes.poll(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS);
      assertTrue(gaveUp instanceof RicochetException, "onResumeFailed: " + gaveUp);
      assertEquals(ErrorCode.EXPIRED_SESSION, ((RicochetException) gaveUp).errorCode());
      assertEquals(ErrorCode.EXPIRED_SESSION, failure(waiting).errorCode());
      // Not resuming any more: a call goes out at once, on the open unauthenticated connection.
      CompletableFuture<Session> login = client.login("scripted", "password-1");
      signIn();
      assertEquals(5, await(login).accountId());
    }
  }

  @Test
  void anAssignmentThatCannotBeFollowedFailsFindMatchAndTheConnectionStays() throws Exception {
    Recorder recorder = new Recorder();
    try (RicochetClient client = client(recorder, 60_000, 0)) {
      CompletableFuture<Session> login = client.login("scripted", "password-1");
      accept();
      signIn();
      await(login);
      CompletableFuture<io.ricochet.client.core.control.Assignment> found =
          client.findMatch("tdm", "");
      ClientMessage find = next();
      assertEquals("tdm", find.getFindMatch().getMode());
      send(
          ServerMessage.newBuilder()
              .setRequestId(find.getRequestId())
              .setFindMatch(io.ricochet.wire.ControlProto.FindMatchReply.newBuilder().setAssignment(
                  io.ricochet.wire.ControlProto.Assignment.newBuilder()
                      .setConnection("10.0.0.2:7787")
                      .setGamePort(7788)
                      .setCertificateSha256(TOKEN)
                      .setMode("tdm")
                      .setTicket(com.google.protobuf.ByteString.copyFrom(new byte[31]))))
              .build());
      RicochetException refused = failure(found);
      assertEquals(RicochetException.Kind.INVALID_REPLY, refused.kind());
      assertTrue(refused.getMessage().startsWith("find_match reply refused (ticket)"),
          refused.getMessage());
      assertEquals(ControlState.AUTHENTICATED, client.state(), "the connection stays");
    }
  }

  @Test
  void matchResultsReachTheListenerOnItsThread() throws Exception {
    Recorder recorder = new Recorder();
    try (RicochetClient client = client(recorder, 60_000, 0)) {
      CompletableFuture<Session> login = client.login("scripted", "password-1");
      accept();
      signIn();
      assertEquals(5, await(login).accountId());
      send(ServerMessage.newBuilder()
               .setMatchResults(MatchResults.newBuilder().setMatchId(12).setAborted(true))
               .build());
      MatchResults results = recorder.results.poll(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS);
      assertNotNull(results);
      assertEquals(12, results.getMatchId());
      assertEquals("ricochet-listener", recorder.threads.poll());
    }
  }

  @Test
  void garbageFromTheServerEndsTheConnectionWithItsReason() throws Exception {
    Recorder recorder = new Recorder();
    try (RicochetClient client = client(recorder, 60_000, 0)) {
      CompletableFuture<Session> login = client.login("scripted", "password-1");
      accept();
      next();
      send(new byte[] {0, 0, 0, 3, (byte) 0xFF, (byte) 0xFF, (byte) 0xFF});
      RicochetException failed = failure(login);
      assertEquals(RicochetException.Kind.DISCONNECTED, failed.kind());
      Disconnect disconnect =
          recorder.disconnects.poll(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS);
      assertNotNull(disconnect);
      assertEquals(ControlCloseReason.MALFORMED, disconnect.reason());
      assertEquals(-1, fromClient.read(), "the client closed the connection");
      // The next call opens a new connection.
      CompletableFuture<Session> again = client.login("scripted", "password-1");
      peer.close();
      accept();
      signIn();
      assertEquals(5, await(again).accountId());
    }
  }

  @Test
  void aReplyToNoRequestEndsTheConnection() throws Exception {
    Recorder recorder = new Recorder();
    try (RicochetClient client = client(recorder, 60_000, 0)) {
      CompletableFuture<Session> login = client.login("scripted", "password-1");
      accept();
      ClientMessage request = next();
      send(ServerMessage.newBuilder()
               .setRequestId(request.getRequestId() + 1)
               .setSession(SessionReply.getDefaultInstance())
               .build());
      assertEquals(RicochetException.Kind.DISCONNECTED, failure(login).kind());
      Disconnect disconnect =
          recorder.disconnects.poll(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS);
      assertEquals(ControlCloseReason.UNKNOWN_REQUEST, disconnect.reason());
    }
  }

  @Test
  void aRequestTheServerNeverAnswersTimesOut() throws Exception {
    Recorder recorder = new Recorder();
    try (RicochetClient client = client(recorder, 300, 0)) {
      CompletableFuture<Session> login = client.login("scripted", "password-1");
      accept();
      next(); // and no answer
      RicochetException failed = failure(login);
      assertEquals(RicochetException.Kind.DISCONNECTED, failed.kind());
      Disconnect disconnect =
          recorder.disconnects.poll(ClientTesting.WAIT_MS, TimeUnit.MILLISECONDS);
      assertEquals(ControlCloseReason.REQUEST_TIMEOUT, disconnect.reason());
    }
  }

  @Test
  void keepAlivePingsAreWrittenAtTheirRate() throws Exception {
    Recorder recorder = new Recorder();
    try (RicochetClient client = client(recorder, 60_000, 100)) {
      CompletableFuture<Session> login = client.login("scripted", "password-1");
      accept();
      signIn();
      await(login);
      long start = System.nanoTime();
      int pings = 0;
      while (pings < 10) {
        ClientMessage ping = next();
        assertTrue(ping.hasPing(), ping.toString());
        ++pings;
        send(ServerMessage.newBuilder()
                 .setRequestId(ping.getRequestId())
                 .setPong(Pong.newBuilder().setClientTimeUs(ping.getPing().getClientTimeUs()))
                 .build());
      }
      long elapsedMs = TimeUnit.NANOSECONDS.toMillis(System.nanoTime() - start);
      // Ten pings, one per 100 ms of silence: about a second, never faster.
      assertTrue(elapsedMs >= 850, "10 pings in " + elapsedMs + " ms");
      assertTrue(elapsedMs < 10_000, "10 pings in " + elapsedMs + " ms");
      assertTrue(recorder.disconnects.isEmpty(), "pongs are consumed, nothing else happens");
    }
  }
}
