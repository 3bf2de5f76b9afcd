package io.ricochet.client.core.transport;

/**
 * What one {@link GameClient} counted (PROTOCOL.md Game channel transport §13; the names of the C++
 * {@code proto::TransportCounters}): packets and bytes each way, every dropped datagram by reason,
 * disconnects by reason, handshakes completed, reliable resends. Read by the app's stats and tests;
 * written only by the client.
 */
public final class TransportCounters {
  private final long[] drops = new long[DropReason.values().length];
  private final long[] disconnects = new long[DisconnectReason.values().length];
  private long packetsIn;
  private long packetsOut;
  private long bytesIn;
  private long bytesOut;
  private long connectionsTotal;
  private long reliableResends;

  /** Datagrams received, refused ones included. */
  public long packetsIn() {
    return packetsIn;
  }

  /** Datagrams sent. */
  public long packetsOut() {
    return packetsOut;
  }

  /** Bytes of the datagrams received (UDP payload bytes). */
  public long bytesIn() {
    return bytesIn;
  }

  /** Bytes of the datagrams sent (UDP payload bytes). */
  public long bytesOut() {
    return bytesOut;
  }

  /** Datagrams dropped for {@code reason}. */
  public long dropped(DropReason reason) {
    return drops[reason.ordinal()];
  }

  /** Datagrams dropped for any reason. */
  public long droppedTotal() {
    long total = 0;
    for (long n : drops) total += n;
    return total;
  }

  /** Connections that ended for {@code reason} (0 or 1 for one client). */
  public long disconnects(DisconnectReason reason) {
    return disconnects[reason.ordinal()];
  }

  /** Handshakes completed. */
  public long connectionsTotal() {
    return connectionsTotal;
  }

  /** Reliable messages sent again for want of an ack. */
  public long reliableResends() {
    return reliableResends;
  }

  void countIn(int bytes) {
    ++packetsIn;
    bytesIn += bytes;
  }

  void countOut(int bytes) {
    ++packetsOut;
    bytesOut += bytes;
  }

  void countDrop(DropReason reason) {
    ++drops[reason.ordinal()];
  }

  void countDisconnect(DisconnectReason reason) {
    ++disconnects[reason.ordinal()];
  }

  void countConnection() {
    ++connectionsTotal;
  }

  void setReliableResends(long resends) {
    reliableResends = resends;
  }
}
