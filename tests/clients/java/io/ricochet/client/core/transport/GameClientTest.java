package io.ricochet.client.core.transport;

import static org.junit.jupiter.api.Assertions.assertArrayEquals;
import static org.junit.jupiter.api.Assertions.assertEquals;
import static org.junit.jupiter.api.Assertions.assertFalse;
import static org.junit.jupiter.api.Assertions.assertNull;
import static org.junit.jupiter.api.Assertions.assertTrue;

import java.util.Arrays;
import java.util.Collections;
import java.util.Random;
import org.junit.jupiter.api.Test;

/** GameClient against a FakeServer, with fake time in microseconds. */
class GameClientTest {
  private static final long START_US = 5_000_000;
  private static final long MS = 1_000;

  private final RecordingListener listener = new RecordingListener();
  private final FakeServer server = new FakeServer();

  private GameClient connectedClient(int timeoutS) {
    GameClient client = new GameClient(FakeServer.grant(timeoutS), listener, START_US);
    FakeServer.connect(client, server, START_US);
    listener.clear();
    return client;
  }

  /** Counts the outbox's datagrams of {@code type} and clears it. */
  private int sent(GameClient client, PacketType type) {
    int count = 0;
    Outbox outbox = client.outbox();
    for (int i = 0; i < outbox.size(); ++i) {
      if (outbox.datagram(i)[0] == type.wireValue()) ++count;
    }
    outbox.clear();
    return count;
  }

  @Test
  void sendsTheRequestAtOnceThenEvery100MsUntilTheHandshakeTimesOut() {
    GameClient client = new GameClient(FakeServer.grant(2), listener, START_US);
    assertEquals(1, client.outbox().size());
    assertEquals(Packets.CONNECTION_REQUEST_BYTES, client.outbox().length(0));
    byte[] request = Arrays.copyOf(client.outbox().datagram(0), client.outbox().length(0));
    assertArrayEquals(FakeServer.TOKEN, Arrays.copyOfRange(request, 27, 27 + 128));
    for (int i = 27 + 128; i < request.length; ++i) assertEquals(0, request[i]);
    client.outbox().clear();
    int requests = 0;
    for (long t = START_US + MS; t < START_US + 2_000 * MS; t += MS) {
      client.update(t);
      requests += sent(client, PacketType.CONNECTION_REQUEST);
    }
    assertEquals(19, requests); // at 100, 200 ... 1900 ms
    assertEquals(ConnectionState.SENDING_REQUEST, client.state());
    client.update(START_US + 2_000 * MS);
    assertEquals(ConnectionState.DISCONNECTED, client.state());
    assertEquals(DisconnectReason.HANDSHAKE_TIMED_OUT, client.disconnectReason());
    assertEquals(Collections.singletonList("disconnected handshake_timed_out"), listener.events);
    assertEquals(0, client.outbox().size()); // gives up without a word
  }

  @Test
  void answersTheChallengeAndConnectsOnTheFirstKeepAlive() {
    GameClient client = new GameClient(FakeServer.grant(5), listener, START_US);
    client.outbox().clear();
    FakeServer.deliver(client, server.challenge(), START_US + 30 * MS);
    assertEquals(ConnectionState.SENDING_RESPONSE, client.state());
    assertEquals(1, client.outbox().size());
    assertTrue(server.open(client.outbox().datagram(0), client.outbox().length(0)));
    assertEquals(PacketType.RESPONSE, server.openedType);
    assertEquals(0, server.openedSequence); // the response is the client's sequence 0
    assertArrayEquals(FakeServer.filled(Packets.CHALLENGE_BODY_BYTES, 40), server.openedBody);
    client.outbox().clear();
    FakeServer.deliver(client, server.challenge(), START_US + 40 * MS); // a duplicate: ignored
    assertEquals(0, client.outbox().size());
    client.update(START_US + 129 * MS);
    assertEquals(0, client.outbox().size());
    client.update(START_US + 130 * MS);
    assertEquals(1, sent(client, PacketType.RESPONSE));
    FakeServer.deliver(client, server.keepAlive(), START_US + 150 * MS);
    assertEquals(ConnectionState.CONNECTED, client.state());
    assertEquals(Collections.singletonList("connected"), listener.events);
    assertEquals(1, client.counters().connectionsTotal());
    assertEquals(Arrays.asList("sending_request -> sending_request",
                     "sending_request -> sending_response", "sending_response -> connected"),
        listener.transitions);
  }

  @Test
  void aDeniedPacketEndsTheHandshakeWithItsReason() {
    GameClient client = new GameClient(FakeServer.grant(5), listener, START_US);
    FakeServer.deliver(client, server.denied(DisconnectReason.HOST_FULL), START_US + MS);
    assertEquals(DisconnectReason.HOST_FULL, client.disconnectReason());
    assertEquals(1, client.counters().disconnects(DisconnectReason.HOST_FULL));
  }

  @Test
  void keepAlivesGoOutAt10HzOverTenSecondsWhileNothingElseIsSent() {
    GameClient client = connectedClient(60);
    int keepAlives = 0;
    for (long t = START_US + MS; t <= START_US + 10_000 * MS; t += MS) {
      client.update(t);
      keepAlives += sent(client, PacketType.KEEP_ALIVE);
      if (t % (1_000 * MS) == 0) FakeServer.deliver(client, server.keepAlive(), t); // stay alive
    }
    assertEquals(100, keepAlives);
    assertEquals(ConnectionState.CONNECTED, client.state());
  }

  @Test
  void payloadsSentEveryTickLeaveNoRoomForKeepAlives() {
    GameClient client = connectedClient(60);
    byte[] input = {1, 2, 3};
    int keepAlives = 0;
    int payloads = 0;
    for (long t = START_US + MS; t <= START_US + 2_000 * MS; t += MS) {
      if (t % (16 * MS) == 0) assertTrue(client.sendPayload(input, 0, input.length, t));
      client.update(t);
      Outbox outbox = client.outbox();
      for (int i = 0; i < outbox.size(); ++i) {
        if (outbox.datagram(i)[0] == PacketType.KEEP_ALIVE.wireValue()) ++keepAlives;
        if (outbox.datagram(i)[0] == PacketType.PAYLOAD.wireValue()) ++payloads;
      }
      outbox.clear();
    }
    assertEquals(0, keepAlives);
    assertEquals(125, payloads); // 2000 / 16
  }

  @Test
  void timesOutAtTimeoutSecondsOfSilenceAndNotBefore() {
    GameClient client = connectedClient(3);
    long lastHeard = START_US + 500 * MS;
    FakeServer.deliver(client, server.keepAlive(), lastHeard);
    for (long t = lastHeard; t < lastHeard + 3_000 * MS; t += 10 * MS) {
      client.update(t);
      client.outbox().clear();
      assertEquals(ConnectionState.CONNECTED, client.state(), "at " + t);
    }
    client.update(lastHeard + 3_000 * MS - 1);
    assertEquals(ConnectionState.CONNECTED, client.state());
    client.outbox().clear();
    client.update(lastHeard + 3_000 * MS);
    assertEquals(DisconnectReason.TIMED_OUT, client.disconnectReason());
    assertEquals(Collections.singletonList("disconnected timed_out"), listener.events);
    assertEquals(0, client.outbox().size()); // nothing is sent on a timeout
  }

  @Test
  void forgedPacketsDoNotKeepTheConnectionAlive() {
    GameClient client = connectedClient(1);
    byte[] forged = server.keepAlive();
    forged[forged.length - 1] ^= 1;
    for (long t = START_US; t < START_US + 1_000 * MS; t += 10 * MS) {
      FakeServer.deliver(client, forged, t);
      client.update(t);
    }
    client.update(START_US + 1_000 * MS);
    assertEquals(DisconnectReason.TIMED_OUT, client.disconnectReason());
    assertEquals(100, client.counters().dropped(DropReason.FORGED_MAC));
  }

  @Test
  void disconnectSendsThreeCopiesThenNothing() {
    GameClient client = connectedClient(5);
    client.disconnect(START_US + MS);
    assertEquals(3, client.outbox().size());
    for (int i = 0; i < 3; ++i) {
      assertTrue(server.open(client.outbox().datagram(i), client.outbox().length(i)));
      assertEquals(PacketType.DISCONNECT, server.openedType);
      assertEquals(DisconnectReason.REQUESTED.wireValue(), server.openedBody[6]);
    }
    client.outbox().clear();
    client.disconnect(START_US + 2 * MS);
    client.update(START_US + 1_000 * MS);
    assertFalse(client.sendPayload(new byte[1], 0, 1, START_US + 1_000 * MS));
    assertEquals(0, client.outbox().size());
    assertEquals(Collections.singletonList("disconnected requested"), listener.events);
  }

  @Test
  void disconnectBeforeConnectedSendsNothing() {
    GameClient client = new GameClient(FakeServer.grant(5), listener, START_US);
    client.outbox().clear();
    client.disconnect(START_US + MS);
    assertEquals(0, client.outbox().size());
    assertEquals(DisconnectReason.REQUESTED, client.disconnectReason());
  }

  @Test
  void theServersDisconnectEndsWithItsReason() {
    GameClient client = connectedClient(5);
    FakeServer.deliver(client, server.disconnect(DisconnectReason.REPLACED), START_US + MS);
    assertEquals(DisconnectReason.REPLACED, client.disconnectReason());
    FakeServer.deliver(client, server.disconnect(DisconnectReason.REPLACED), START_US + MS);
    assertEquals(1, client.counters().dropped(DropReason.WRONG_STATE));
    assertEquals(Collections.singletonList("disconnected replaced"), listener.events);
  }

  @Test
  void reliableEventsArriveInOrderExactlyOnceWhateverTheNetworkDoes() {
    GameClient client = connectedClient(5);
    byte[][] packets = new byte[6][];
    for (int i = 0; i < 6; ++i) {
      packets[i] = server.payload(new int[] {i}, new byte[][] {{(byte) i}}, new byte[0]);
    }
    long t = START_US;
    for (int i : new int[] {3, 1, 1, 5, 0, 4, 2, 2, 0}) FakeServer.deliver(client, packets[i], t);
    assertEquals(Arrays.asList("reliable 00", "reliable 01", "reliable 02", "reliable 03",
                     "reliable 04", "reliable 05"),
        listener.events);
    assertEquals(3, client.counters().dropped(DropReason.REPLAYED));
    // The same message resent in a new packet (its ack was lost) is delivered once.
    FakeServer.deliver(
        client, server.payload(new int[] {5, 6}, new byte[][] {{5}, {6}}, new byte[] {9}), t);
    assertEquals("reliable 06", listener.events.get(6));
    assertEquals("unreliable 09", listener.events.get(7));
    assertEquals(8, listener.events.size());
  }

  @Test
  void aReliableMessageTooFarAheadIsCountedAndTheRestOfThePacketUsed() {
    GameClient client = connectedClient(5);
    FakeServer.deliver(client,
        server.payload(new int[] {0, 300}, new byte[][] {{1}, {2}}, new byte[] {7}), START_US);
    assertEquals(Arrays.asList("reliable 01", "unreliable 07"), listener.events);
    assertEquals(1, client.counters().dropped(DropReason.RELIABLE_OUT_OF_WINDOW));
  }

  @Test
  void reliableMessagesAreResentEvery100MsUntilAckedThenNoMore() {
    GameClient client = connectedClient(60);
    byte[] hello = {'h', 'i'};
    assertTrue(client.sendReliable(hello, 0, hello.length, START_US));
    assertEquals(1, client.reliablePending());
    int carrying = 0;
    long lastSequence = -1;
    for (long t = START_US; t < START_US + 1_000 * MS; t += 10 * MS) {
      client.update(t);
      Outbox outbox = client.outbox();
      for (int i = 0; i < outbox.size(); ++i) {
        assertTrue(server.open(outbox.datagram(i), outbox.length(i)));
        if (server.openedType == PacketType.PAYLOAD && server.openedBody[6] == 1) {
          ++carrying;
          lastSequence = server.openedSequence;
        }
      }
      outbox.clear();
    }
    assertEquals(10, carrying); // at 0, 100 ... 900 ms: never acked
    assertEquals(9, client.counters().reliableResends());
    FakeServer.deliver(
        client, server.keepAlive((int) lastSequence & 0xFFFF, 0), START_US + 1_000 * MS);
    assertEquals(0, client.reliablePending());
    assertTrue(client.rttUs() >= 0);
    for (long t = START_US + 1_000 * MS; t < START_US + 2_000 * MS; t += 10 * MS) {
      client.update(t);
      assertEquals(0, sent(client, PacketType.PAYLOAD));
    }
  }

  @Test
  void reliableMessagesRideAlongWithPayloadsAndTheAckMeasuresTheRoundTrip() {
    GameClient client = connectedClient(60);
    byte[] event = {42};
    client.sendReliable(event, 0, 1, START_US);
    byte[] input = {1, 2, 3, 4};
    assertTrue(client.sendPayload(input, 0, input.length, START_US));
    assertTrue(server.open(client.outbox().datagram(0), client.outbox().length(0)));
    byte[] body = server.openedBody;
    assertEquals(1, body[6]); // one reliable message
    assertEquals(0, Packets.getU16(body, 7)); // id 0
    assertEquals(1, Packets.getU16(body, 9)); // 1 byte
    assertEquals(42, body[11]);
    assertArrayEquals(input, Arrays.copyOfRange(body, 12, body.length));
    // The client acks the server's keep-alive of the handshake (sequence 0).
    assertEquals(0, Packets.getU16(body, 0));
    client.outbox().clear();
    FakeServer.deliver(
        client, server.keepAlive((int) server.openedSequence, 0), START_US + 40 * MS);
    assertEquals(40 * MS, client.rttUs());
    assertEquals(0, client.reliablePending());
  }

  @Test
  void tooManyUnackedReliableMessagesDisconnectWithReliableOverflow() {
    GameClient client = connectedClient(60);
    byte[] message = {1};
    for (int i = 0; i < GameClient.MAX_RELIABLE_QUEUED; ++i) {
      assertTrue(client.sendReliable(message, 0, 1, START_US));
    }
    assertFalse(client.sendReliable(message, 0, 1, START_US));
    assertEquals(DisconnectReason.RELIABLE_OVERFLOW, client.disconnectReason());
    assertEquals(3, sent(client, PacketType.DISCONNECT));
    assertFalse(client.sendReliable(new byte[0], 0, 0, START_US));
  }

  @Test
  void payloadsAndMessagesOutOfBoundsAreRefused() {
    GameClient client = new GameClient(FakeServer.grant(5), listener, START_US);
    assertFalse(client.sendPayload(new byte[1], 0, 1, START_US)); // not connected yet
    FakeServer.connect(client, server, START_US);
    byte[] big = new byte[2000];
    assertFalse(client.sendPayload(big, 0, Packets.MAX_UNRELIABLE_BYTES + 1, START_US));
    assertTrue(client.sendPayload(big, 0, Packets.MAX_UNRELIABLE_BYTES, START_US));
    assertEquals(Packets.MAX_DATAGRAM_BYTES, client.outbox().length(0));
    assertFalse(client.sendReliable(big, 0, Packets.MAX_RELIABLE_MESSAGE_BYTES + 1, START_US));
    assertFalse(client.sendReliable(big, 0, 0, START_US));
  }

  @Test
  void everyRefusedDatagramIsCountedByReasonAndNoneReachesTheApp() {
    GameClient client = connectedClient(5);
    byte[] good = server.keepAlive();
    byte[] flipped = server.keepAlive(); // a sequence not seen yet: the tag is what fails
    flipped[12] ^= 4;
    byte[] truncated = Arrays.copyOf(good, good.length - 1);
    byte[] unknownType = good.clone();
    unknownType[0] = 7;
    FakeServer.deliver(client, good, START_US);
    FakeServer.deliver(client, good, START_US);
    FakeServer.deliver(client, new byte[0], START_US);
    FakeServer.deliver(client, new byte[1201], START_US);
    FakeServer.deliver(client, flipped, START_US);
    FakeServer.deliver(client, truncated, START_US);
    FakeServer.deliver(client, unknownType, START_US);
    FakeServer.deliver(client, server.challenge(), START_US);
    FakeServer.deliver(
        client, server.sealed(PacketType.KEEP_ALIVE, server.nextSequence++, new byte[5]), START_US);
    TransportCounters counters = client.counters();
    assertEquals(1, counters.dropped(DropReason.REPLAYED));
    assertEquals(1, counters.dropped(DropReason.EMPTY));
    assertEquals(1, counters.dropped(DropReason.OVERSIZED));
    assertEquals(1, counters.dropped(DropReason.FORGED_MAC));
    assertEquals(2, counters.dropped(DropReason.TRUNCATED)); // short, and a 5-byte keep-alive
    assertEquals(1, counters.dropped(DropReason.MALFORMED));
    assertEquals(1, counters.dropped(DropReason.WRONG_STATE));
    assertEquals(8, counters.droppedTotal());
    assertEquals(2 + 9, counters.packetsIn()); // the handshake's challenge and keep-alive too
    assertEquals(8, listener.drops.size());
    assertTrue(listener.events.isEmpty());
    assertEquals(ConnectionState.CONNECTED, client.state());
  }

  @Test
  void garbageNeverThrowsInAnyState() {
    Random random = new Random(30);
    byte[] datagram = new byte[1400];
    for (int round = 0; round < 4; ++round) {
      FakeServer fresh = new FakeServer();
      GameClient client = new GameClient(FakeServer.grant(5), listener, START_US);
      if (round == 1) FakeServer.deliver(client, fresh.challenge(), START_US);
      if (round >= 2) FakeServer.connect(client, fresh, START_US);
      if (round == 3) client.disconnect(START_US);
      ConnectionState before = client.state();
      for (int i = 0; i < 20_000; ++i) {
        int length = random.nextInt(datagram.length + 1);
        random.nextBytes(datagram);
        if (length > 0) datagram[0] = (byte) random.nextInt(8); // mostly known types
        if (length > 8 && random.nextBoolean()) datagram[8] = (byte) 0x80; // handshake bit
        client.receive(datagram, length, START_US + i);
      }
      assertEquals(before, client.state());
      assertEquals(20_000, client.counters().droppedTotal());
    }
  }

  @Test
  void countsTheServersLossAndLatePackets() {
    GameClient client = connectedClient(5); // server sequence 0 accepted
    byte[] one = server.keepAlive();
    server.keepAlive(); // 2: lost
    byte[] three = server.keepAlive();
    FakeServer.deliver(client, three, START_US);
    FakeServer.deliver(client, one, START_US);
    assertEquals(4, client.serverPacketsSent());
    assertEquals(1, client.serverPacketsMissing());
    assertEquals(1, client.serverPacketsLate());
    assertNull(client.disconnectReason());
  }

  @Test
  void aConnectedClientsTrafficAllocatesNothingOnceWarm() {
    com.sun.management.ThreadMXBean threads =
        (com.sun.management.ThreadMXBean) java.lang.management.ManagementFactory.getThreadMXBean();
    long thread = Thread.currentThread().getId();
    GameClient client = new GameClient(FakeServer.grant(60), new GameClientListener() {}, START_US);
    FakeServer.connect(client, server, START_US);
    byte[][][] passes = new byte[10][1000][]; // fresh sequences for every pass
    for (byte[][] snapshots : passes) {
      for (int i = 0; i < snapshots.length; ++i) {
        snapshots[i] = server.payload(new int[0], new byte[0][], FakeServer.filled(300, i));
      }
    }
    byte[] input = FakeServer.filled(40, 3);
    long t = START_US;
    long allocated = -1;
    for (int pass = 0; pass < 10 && (pass < 3 || allocated != 0); ++pass) { // warm up, compile
      long before = threads.getThreadAllocatedBytes(thread);
      for (byte[] snapshot : passes[pass]) {
        t += 16 * MS;
        client.receive(snapshot, snapshot.length, t);
        client.sendPayload(input, 0, input.length, t);
        client.update(t);
        client.outbox().clear();
      }
      allocated = threads.getThreadAllocatedBytes(thread) - before;
      assertEquals(0, client.counters().droppedTotal());
      assertEquals(1 + 1000L * (pass + 1), client.serverPacketsSent());
    }
    assertEquals(0, allocated, "bytes allocated by 1000 ticks of a connected client once warm");
  }

  /** Drives two clients over the same script: one updated every ms, one only at nextUpdateUs. */
  @Test
  void updatingOnlyAtNextUpdateUsSendsWhatUpdatingEveryMillisecondSends() {
    FakeServer everyMsServer = new FakeServer();
    FakeServer sleepyServer = new FakeServer();
    RecordingListener everyMsEvents = new RecordingListener();
    RecordingListener sleepyEvents = new RecordingListener();
    GameClient everyMs = new GameClient(FakeServer.grant(2), everyMsEvents, START_US);
    GameClient sleepy = new GameClient(FakeServer.grant(2), sleepyEvents, START_US);
    java.util.List<String> everyMsSent = new java.util.ArrayList<>();
    java.util.List<String> sleepySent = new java.util.ArrayList<>();
    byte[] message = {5};
    int sleepyUpdates = 0;
    for (long t = START_US; t <= START_US + 6_000 * MS; t += MS) {
      long elapsedMs = (t - START_US) / MS;
      if (elapsedMs == 350) { // the challenge, then the first keep-alive
        FakeServer.deliver(everyMs, everyMsServer.challenge(), t);
        FakeServer.deliver(sleepy, sleepyServer.challenge(), t);
      }
      if (elapsedMs == 420 || (elapsedMs >= 1_000 && elapsedMs <= 2_500 && elapsedMs % 500 == 0)) {
        FakeServer.deliver(everyMs, everyMsServer.keepAlive(), t);
        FakeServer.deliver(sleepy, sleepyServer.keepAlive(), t);
      }
      if (elapsedMs == 700 || elapsedMs == 1_234) {
        everyMs.sendReliable(message, 0, 1, t);
        sleepy.sendReliable(message, 0, 1, t);
      }
      if (elapsedMs >= 900 && elapsedMs < 1_100 && elapsedMs % 16 == 0) {
        everyMs.sendPayload(message, 0, 1, t);
        sleepy.sendPayload(message, 0, 1, t);
      }
      everyMs.update(t);
      if (t >= sleepy.nextUpdateUs()) {
        sleepy.update(t);
        ++sleepyUpdates;
      }
      everyMsSent.addAll(RecordingListener.drain(everyMs.outbox()));
      sleepySent.addAll(RecordingListener.drain(sleepy.outbox()));
      assertEquals(everyMsSent, sleepySent, "at " + elapsedMs + " ms");
    }
    assertEquals(everyMsEvents.events, sleepyEvents.events);
    assertEquals(DisconnectReason.TIMED_OUT, sleepy.disconnectReason()); // at 2.5 s + 2 s
    assertEquals(Long.MAX_VALUE, sleepy.nextUpdateUs());
    assertTrue(sleepyUpdates < 80, sleepyUpdates + " updates");
    assertTrue(everyMsSent.size() > 40);
  }
}
