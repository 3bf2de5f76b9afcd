package io.ricochet.client.core.transport;

/**
 * The client end of an established (or establishing) session, as the C++ {@code proto::Connection}:
 * the send sequence and key, the replay window and receive key, acks, the reliable channel, the
 * keep-alive and silence timers. Knows no states; {@link GameClient} does. Writes packets into the
 * caller's buffers and allocates nothing per packet (but a copy of each reliable message).
 */
final class Session {
  private final PacketAead sendAead;
  private final PacketAead receiveAead;
  private final long timeoutUs;
  private final long keepAliveUs;
  private final long reliableResendUs;
  private final ReplayWindow replay = new ReplayWindow();
  private final SentPacketWindow sent = new SentPacketWindow();
  private final ReliableSender sender;
  private final ReliableReceiver receiver = new ReliableReceiver();
  private final int[] carriedIds = new int[255];
  private int carriedCount;
  private long nextSequence;
  private long lastSentUs;
  private long lastReceivedUs;
  private int openedBytes;

  Session(ConnectGrant grant, long timeoutUs, long keepAliveUs, long reliableResendUs,
      int maxReliablePending, int maxReliableQueued, long nowUs) {
    sendAead = new PacketAead(grant.clientToServerKey(), grant.protocolId());
    receiveAead = new PacketAead(grant.serverToClientKey(), grant.protocolId());
    this.timeoutUs = timeoutUs;
    this.keepAliveUs = keepAliveUs;
    this.reliableResendUs = reliableResendUs;
    sender = new ReliableSender(maxReliablePending, maxReliableQueued);
    lastSentUs = nowUs;
    lastReceivedUs = nowUs;
  }

  /**
   * A session packet (header checked): the replay check, then decryption into {@code body}. On
   * success (null) the sequence counts as received, the silence timer restarts and the body is
   * {@code body[0, openedBytes())}.
   */
  DropReason open(byte[] datagram, int length, long sequence, byte[] body, long nowUs) {
    if (replay.alreadyReceived(sequence)) return DropReason.REPLAYED;
    int bytes = receiveAead.open(datagram, length, body);
    if (bytes < 0) return DropReason.FORGED_MAC;
    openedBytes = bytes;
    replay.markReceived(sequence);
    lastReceivedUs = nowUs;
    return null;
  }

  /** A challenge or denied packet (no replay window: bit 63 sequences); body length or -1. */
  int openHandshake(byte[] datagram, int length, byte[] body) {
    return receiveAead.open(datagram, length, body);
  }

  int openedBytes() {
    return openedBytes;
  }

  /** Seals {@code body[0, bodyBytes)} as a {@code type} packet into {@code out}; its length. */
  int seal(PacketType type, byte[] body, int bodyBytes, long nowUs, byte[] out) {
    System.arraycopy(body, 0, out, Packets.HEADER_BYTES, bodyBytes);
    return sealBody(type, Packets.HEADER_BYTES + bodyBytes, nowUs, out);
  }

  int makeKeepAlive(long nowUs, byte[] out) {
    writeAck(out, Packets.HEADER_BYTES);
    return sealBody(
        PacketType.KEEP_ALIVE, Packets.HEADER_BYTES + Packets.ACK_HEADER_BYTES, nowUs, out);
  }

  int makeDisconnect(DisconnectReason reason, long nowUs, byte[] out) {
    writeAck(out, Packets.HEADER_BYTES);
    out[Packets.HEADER_BYTES + Packets.ACK_HEADER_BYTES] = (byte) reason.wireValue();
    return sealBody(
        PacketType.DISCONNECT, Packets.HEADER_BYTES + Packets.ACK_HEADER_BYTES + 1, nowUs, out);
  }

  /**
   * A payload packet: the ack header, the reliable messages due that fit beside {@code
   * unreliable[offset, offset + length)} (at most {@link Packets#MAX_UNRELIABLE_BYTES}), then
   * those bytes; into {@code out}, its length returned.
   */
  int makePayload(byte[] unreliable, int offset, int length, long nowUs, byte[] out) {
    int body = Packets.HEADER_BYTES;
    writeAck(out, body);
    int budget = Packets.MAX_BODY_BYTES - Packets.PAYLOAD_FIXED_BYTES - length;
    carriedCount = sender.takeDue(
        nowUs, reliableResendUs, budget, out, body + Packets.PAYLOAD_FIXED_BYTES, carriedIds);
    out[body + Packets.ACK_HEADER_BYTES] = (byte) carriedCount;
    int end = body + Packets.PAYLOAD_FIXED_BYTES + sender.takenBytes();
    System.arraycopy(unreliable, offset, out, end, length);
    return sealBody(PacketType.PAYLOAD, end + length, nowUs, out);
  }

  /** The server's ack header: acknowledges the reliable messages its packets carried. */
  void onAck(int ack, int ackBits, long nowUs) {
    sent.onAck(ack, ackBits, nextSequence, nowUs, sender);
  }

  ReliableReceiver.Outcome receiveReliable(int id, byte[] bytes, int offset, int length) {
    return receiver.receive(id, bytes, offset, length);
  }

  /** The next reliable message in order, or null. */
  byte[] popReliable() {
    return receiver.pop();
  }

  boolean queueReliable(byte[] message, int offset, int length) {
    return sender.push(message, offset, length);
  }

  boolean reliableDue(long nowUs) {
    return sender.hasDue(nowUs, reliableResendUs);
  }

  /** The earliest time at which a reliable resend, a keep-alive or the timeout is due. */
  long nextDueUs() {
    long next = Math.min(lastSentUs + keepAliveUs, lastReceivedUs + timeoutUs);
    return Math.min(next, sender.nextDueUs(reliableResendUs));
  }

  boolean keepAliveDue(long nowUs) {
    return nowUs - lastSentUs >= keepAliveUs;
  }

  boolean timedOut(long nowUs) {
    return nowUs - lastReceivedUs >= timeoutUs;
  }

  long reliableResends() {
    return sender.resends();
  }

  int reliablePending() {
    return sender.pending();
  }

  long rttUs() {
    return sent.rttUs();
  }

  ReplayWindow received() {
    return replay;
  }

  private void writeAck(byte[] out, int at) {
    Packets.putU16(out, at, replay.ack());
    Packets.putU32(out, at + 2, replay.ackBits());
  }

  /** Writes the header of the next sequence over {@code out[0, 9)} and seals the body after it. */
  private int sealBody(PacketType type, int length, long nowUs, byte[] out) {
    long sequence = nextSequence++;
    sent.onSent(sequence, nowUs, carriedIds, carriedCount);
    carriedCount = 0;
    lastSentUs = nowUs;
    out[0] = (byte) type.wireValue();
    Packets.putU64(out, 1, sequence);
    return sendAead.seal(out, length);
  }
}
