package io.ricochet.client.core.transport;

import io.ricochet.wire.GameProto.ClientPayload;
import java.io.IOException;
import java.net.DatagramPacket;
import java.net.DatagramSocket;
import java.net.InetAddress;
import java.net.InetSocketAddress;
import java.net.SocketAddress;
import java.net.SocketTimeoutException;
import java.util.Arrays;

/**
 * {@link FakeServer} on a real UDP socket of 127.0.0.1 (a free port), for tests of the I/O layer
 * above the transport that need no real server: it answers the handshake and sends what the test
 * says, sealed with the grant's keys, to the address the client's request came from. Every receive
 * is bounded by a timeout. Public for the tests of io.ricochet.client.
 */
public final class FakeGameServer implements AutoCloseable {
  private final FakeServer server = new FakeServer();
  private final DatagramSocket socket;
  private final byte[] buffer = new byte[2048];
  private SocketAddress client;

  /** Binds 127.0.0.1 on a free port. */
  public FakeGameServer() throws IOException {
    socket = new DatagramSocket(new InetSocketAddress(InetAddress.getLoopbackAddress(), 0));
  }

  /** The 128-byte token, the two keys: what a join reply carries for this server. */
  public static byte[] token() {
    return FakeServer.TOKEN.clone();
  }

  /** The key of the client's packets. */
  public static byte[] clientToServerKey() {
    return FakeServer.CLIENT_TO_SERVER.clone();
  }

  /** The key of the server's packets. */
  public static byte[] serverToClientKey() {
    return FakeServer.SERVER_TO_CLIENT.clone();
  }

  /** The UDP port. */
  public int port() {
    return socket.getLocalPort();
  }

  /**
   * Receives until a disconnect packet comes within {@code timeoutMs}; its reason, or null when
   * none came.
   */
  public DisconnectReason awaitDisconnect(long timeoutMs) throws IOException {
    long deadline = System.currentTimeMillis() + timeoutMs;
    while (System.currentTimeMillis() < deadline) {
      if (receive(deadline - System.currentTimeMillis()) == PacketType.DISCONNECT) {
        return DisconnectReason.fromWire(server.openedBody[Packets.ACK_HEADER_BYTES] & 0xFF);
      }
    }
    return null;
  }

  /**
   * The next datagram's type within {@code timeoutMs}, or null when none came; a datagram that
   * does not open is skipped.
   */
  private PacketType receive(long timeoutMs) throws IOException {
    long deadline = System.nanoTime() + timeoutMs * 1_000_000L;
    while (true) {
      long leftMs = (deadline - System.nanoTime()) / 1_000_000L;
      if (leftMs <= 0) return null;
      socket.setSoTimeout((int) Math.max(1, leftMs));
      DatagramPacket packet = new DatagramPacket(buffer, buffer.length);
      try {
        socket.receive(packet);
      } catch (SocketTimeoutException e) {
        return null;
      }
      client = packet.getSocketAddress();
      if (packet.getLength() == Packets.CONNECTION_REQUEST_BYTES && buffer[0] == 0) {
        return PacketType.CONNECTION_REQUEST;
      }
      if (server.open(buffer, packet.getLength())) {
        return server.openedType;
      }
    }
  }

  /**
   * Receives until the handshake is done (request → challenge, response → keep-alive), within
   * {@code timeoutMs}; false when it is not.
   */
  public boolean handshake(long timeoutMs) throws IOException {
    long deadline = System.currentTimeMillis() + timeoutMs;
    while (System.currentTimeMillis() < deadline) {
      PacketType type = receive(deadline - System.currentTimeMillis());
      if (type == PacketType.CONNECTION_REQUEST) {
        send(server.challenge());
      } else if (type == PacketType.RESPONSE) {
        send(server.keepAlive());
        return true;
      }
    }
    return false;
  }

  /** The next ClientPayload the client sends within {@code timeoutMs}, or null. */
  public ClientPayload nextClientPayload(long timeoutMs) throws IOException {
    long deadline = System.currentTimeMillis() + timeoutMs;
    while (System.currentTimeMillis() < deadline) {
      if (receive(deadline - System.currentTimeMillis()) != PacketType.PAYLOAD) continue;
      byte[] body = server.openedBody;
      int at = Packets.PAYLOAD_FIXED_BYTES;
      for (int i = 0; i < (body[Packets.ACK_HEADER_BYTES] & 0xFF); ++i) {
        at += Packets.RELIABLE_MESSAGE_HEADER_BYTES + Packets.getU16(body, at + 2);
      }
      return ClientPayload.parseFrom(Arrays.copyOfRange(body, at, body.length));
    }
    return null;
  }

  /** A payload with reliable messages {@code ids[i]} = {@code messages[i]} and unreliable bytes. */
  public void sendPayload(int[] ids, byte[][] messages, byte[] unreliable) throws IOException {
    send(server.payload(ids, messages, unreliable));
  }

  /** A disconnect packet with {@code reason}. */
  public void sendDisconnect(DisconnectReason reason) throws IOException {
    send(server.disconnect(reason));
  }

  private void send(byte[] datagram) throws IOException {
    socket.send(new DatagramPacket(datagram, datagram.length, client));
  }

  @Override
  public void close() {
    socket.close();
  }
}
