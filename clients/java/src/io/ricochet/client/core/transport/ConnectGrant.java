package io.ricochet.client.core.transport;

/**
 * What the control channel's join reply gives the game channel (PROTOCOL.md Game channel
 * transport §4): the opaque 128-byte connect token, the two session keys and the silence timeout.
 * Made by the control layer from {@code JoinMatchReply}; one grant opens one handshake, so a
 * reconnect asks for a new one.
 */
public final class ConnectGrant {
  private final byte[] connectToken;
  private final byte[] clientToServerKey;
  private final byte[] serverToClientKey;
  private final int timeoutS;
  private final long protocolId;

  /**
   * Copies its arrays. Throws IllegalArgumentException when the token is not 128 bytes, a key not
   * 32, or {@code timeoutS} outside 1..60 (the join reply was checked before: a caller's bug).
   */
  public ConnectGrant(byte[] connectToken, byte[] clientToServerKey, byte[] serverToClientKey,
      int timeoutS, long protocolId) {
    if (connectToken.length != Packets.CONNECT_TOKEN_BYTES) {
      throw new IllegalArgumentException(
          "a connect token is 128 bytes, got " + connectToken.length);
    }
    if (clientToServerKey.length != Packets.KEY_BYTES
        || serverToClientKey.length != Packets.KEY_BYTES) {
      throw new IllegalArgumentException("a session key is 32 bytes");
    }
    if (timeoutS < 1 || timeoutS > 60) {
      throw new IllegalArgumentException("timeout_s must be 1..60, got " + timeoutS);
    }
    this.connectToken = connectToken.clone();
    this.clientToServerKey = clientToServerKey.clone();
    this.serverToClientKey = serverToClientKey.clone();
    this.timeoutS = timeoutS;
    this.protocolId = protocolId;
  }

  /** The same with this build's {@link Packets#PROTOCOL_ID}. */
  public ConnectGrant(
      byte[] connectToken, byte[] clientToServerKey, byte[] serverToClientKey, int timeoutS) {
    this(connectToken, clientToServerKey, serverToClientKey, timeoutS, Packets.PROTOCOL_ID);
  }

  byte[] connectToken() {
    return connectToken;
  }

  byte[] clientToServerKey() {
    return clientToServerKey;
  }

  byte[] serverToClientKey() {
    return serverToClientKey;
  }

  /** Silence timeout of the connection and of each handshake phase, in seconds (1..60). */
  public int timeoutS() {
    return timeoutS;
  }

  /** The protocol id sent in the request and bound into every packet's additional data. */
  public long protocolId() {
    return protocolId;
  }
}
