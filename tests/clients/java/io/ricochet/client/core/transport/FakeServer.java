package io.ricochet.client.core.transport;

import java.util.Arrays;

/**
 * The server end as far as the unit tests need it: the session keys of a grant, a challenge, and
 * keep-alives, payloads and disconnects sealed with the next server sequence; it opens what the
 * client sends. Not a server: no tokens, no checks beyond the tag.
 */
final class FakeServer {
  static final byte[] TOKEN = filled(Packets.CONNECT_TOKEN_BYTES, 7);
  static final byte[] CLIENT_TO_SERVER = filled(Packets.KEY_BYTES, 1);
  static final byte[] SERVER_TO_CLIENT = filled(Packets.KEY_BYTES, 2);

  private final PacketAead seal = new PacketAead(SERVER_TO_CLIENT, Packets.PROTOCOL_ID);
  private final PacketAead open = new PacketAead(CLIENT_TO_SERVER, Packets.PROTOCOL_ID);
  long nextSequence;
  long nextHandshakeSequence = Packets.HANDSHAKE_SEQUENCE_BIT;
  /** The type and body of the last packet {@link #open} opened. */
  PacketType openedType;
  byte[] openedBody;
  long openedSequence;

  static ConnectGrant grant(int timeoutS) {
    return new ConnectGrant(TOKEN, CLIENT_TO_SERVER, SERVER_TO_CLIENT, timeoutS);
  }

  static byte[] filled(int length, int value) {
    byte[] out = new byte[length];
    for (int i = 0; i < length; ++i) out[i] = (byte) (value + i);
    return out;
  }

  byte[] challenge() {
    return sealed(
        PacketType.CHALLENGE, nextHandshakeSequence++, filled(Packets.CHALLENGE_BODY_BYTES, 40));
  }

  byte[] denied(DisconnectReason reason) {
    return sealed(PacketType.CONNECTION_DENIED, nextHandshakeSequence++,
        new byte[] {(byte) reason.wireValue()});
  }

  byte[] keepAlive() {
    return sealed(PacketType.KEEP_ALIVE, nextSequence++, new byte[Packets.ACK_HEADER_BYTES]);
  }

  /** A keep-alive acking the client's {@code ack} and the 32 before it per {@code ackBits}. */
  byte[] keepAlive(int ack, int ackBits) {
    byte[] body = new byte[Packets.ACK_HEADER_BYTES];
    Packets.putU16(body, 0, ack);
    Packets.putU32(body, 2, ackBits);
    return sealed(PacketType.KEEP_ALIVE, nextSequence++, body);
  }

  byte[] disconnect(DisconnectReason reason) {
    byte[] body = new byte[Packets.ACK_HEADER_BYTES + 1];
    body[Packets.ACK_HEADER_BYTES] = (byte) reason.wireValue();
    return sealed(PacketType.DISCONNECT, nextSequence++, body);
  }

  /** A payload with reliable messages {@code ids[i]} = {@code messages[i]} and unreliable bytes. */
  byte[] payload(int[] ids, byte[][] messages, byte[] unreliable) {
    int length = Packets.PAYLOAD_FIXED_BYTES + unreliable.length;
    for (byte[] message : messages)
      length += Packets.RELIABLE_MESSAGE_HEADER_BYTES + message.length;
    byte[] body = new byte[length];
    body[Packets.ACK_HEADER_BYTES] = (byte) messages.length;
    int at = Packets.PAYLOAD_FIXED_BYTES;
    for (int i = 0; i < messages.length; ++i) {
      Packets.putU16(body, at, ids[i]);
      Packets.putU16(body, at + 2, messages[i].length);
      System.arraycopy(messages[i], 0, body, at + 4, messages[i].length);
      at += 4 + messages[i].length;
    }
    System.arraycopy(unreliable, 0, body, at, unreliable.length);
    return sealed(PacketType.PAYLOAD, nextSequence++, body);
  }

  byte[] sealed(PacketType type, long sequence, byte[] body) {
    byte[] packet = new byte[Packets.MAX_DATAGRAM_BYTES];
    packet[0] = (byte) type.wireValue();
    Packets.putU64(packet, 1, sequence);
    System.arraycopy(body, 0, packet, Packets.HEADER_BYTES, body.length);
    return Arrays.copyOf(packet, seal.seal(packet, Packets.HEADER_BYTES + body.length));
  }

  /** Opens a client datagram (not the request); false when its tag fails. */
  boolean open(byte[] datagram, int length) {
    byte[] body = new byte[Packets.MAX_DATAGRAM_BYTES];
    int bytes = open.open(datagram, length, body);
    if (bytes < 0) return false;
    openedType = PacketType.values()[datagram[0]];
    openedSequence = Packets.getU64(datagram, 1);
    openedBody = Arrays.copyOf(body, bytes);
    return true;
  }

  /** Takes the client through the handshake at {@code nowUs}; its outbox is empty after. */
  static void connect(GameClient client, FakeServer server, long nowUs) {
    client.outbox().clear();
    deliver(client, server.challenge(), nowUs);
    client.outbox().clear(); // the response
    deliver(client, server.keepAlive(), nowUs);
    if (client.state() != ConnectionState.CONNECTED) throw new AssertionError(client.state());
  }

  static void deliver(GameClient client, byte[] datagram, long nowUs) {
    client.receive(datagram, datagram.length, nowUs);
  }
}
