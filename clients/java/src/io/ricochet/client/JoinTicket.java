package io.ricochet.client;

import io.ricochet.wire.ControlProto.JoinMatchReply;
import io.ricochet.wire.GameProto.WeaponSpec;
import io.ricochet.wire.SnapshotProto.Quantization;
import java.util.Collections;
import java.util.List;

/**
 * What {@link RicochetClient#joinMatch} gives: everything the game channel needs to connect (the
 * connect token, the two 32-byte keys, the UDP port on the control channel's host) and to play
 * (rates, quantisation, weapons, the collision world). Checked when the reply arrives: the keys
 * are 32 bytes, the token is not empty, the port is 1..65535. The byte arrays are copies.
 */
public final class JoinTicket {
  /** Bytes of each key. */
  public static final int KEY_BYTES = 32;

  private final String host;
  private final JoinMatchReply reply;
  private final long receivedAtMs;

  private JoinTicket(String host, JoinMatchReply reply, long receivedAtMs) {
    this.host = host;
    this.reply = reply;
    this.receivedAtMs = receivedAtMs;
  }

  /** The ticket of {@code reply}, or null with {@code why[0]} set when it breaks the protocol. */
  static JoinTicket of(String host, JoinMatchReply reply, long receivedAtMs, String[] why) {
    if (reply.getClientToServerKey().size() != KEY_BYTES
        || reply.getServerToClientKey().size() != KEY_BYTES) {
      why[0] = "join reply keys of " + reply.getClientToServerKey().size() + " and "
          + reply.getServerToClientKey().size() + " bytes; both must be " + KEY_BYTES;
      return null;
    }
    if (reply.getConnectToken().isEmpty()) {
      why[0] = "join reply with an empty connect token";
      return null;
    }
    if (reply.getUdpPort() <= 0 || reply.getUdpPort() > 65535) {
      why[0] = "join reply with udp_port " + (reply.getUdpPort() & 0xFFFFFFFFL);
      return null;
    }
    return new JoinTicket(host, reply, receivedAtMs);
  }

  /** The match joined. */
  public long matchId() {
    return reply.getMatchId() & 0xFFFFFFFFL;
  }

  /** The game server's host: the control channel's. */
  public String host() {
    return host;
  }

  /** The game server's UDP port, 1..65535. */
  public int udpPort() {
    return reply.getUdpPort();
  }

  /** The opaque connect token, sent as is in the connection request (a copy). */
  public byte[] connectToken() {
    return reply.getConnectToken().toByteArray();
  }

  /** The 32-byte key of the packets the client seals (a copy). */
  public byte[] clientToServerKey() {
    return reply.getClientToServerKey().toByteArray();
  }

  /** The 32-byte key of the packets the server seals (a copy). */
  public byte[] serverToClientKey() {
    return reply.getServerToClientKey().toByteArray();
  }

  /** How long after {@link #receivedAtMs()} the token may open a connection (ms). */
  public long tokenExpiresInMs() {
    return reply.getTokenExpiresInMs() & 0xFFFFFFFFL;
  }

  /** When the reply arrived, on the client's monotonic clock ({@code System.nanoTime()} / 1e6). */
  public long receivedAtMs() {
    return receivedAtMs;
  }

  /** The game channel's silence timeout (ms). */
  public long timeoutMs() {
    return (reply.getTimeoutS() & 0xFFFFFFFFL) * 1000;
  }

  /** The match's fixed steps per second. */
  public int tickRateHz() {
    return reply.getTickRateHz();
  }

  /** Snapshots per second to this client. */
  public int snapshotRateHz() {
    return reply.getSnapshotRateHz();
  }

  /** How the match quantises its snapshots: build the snapshot decoder from it. */
  public Quantization quantization() {
    return reply.getQuantization();
  }

  /** Whether the reply carries the collision world (left out when the map's is too large). */
  public boolean hasCollisionWorld() {
    return reply.hasWorld();
  }

  /**
   * The collision world as serialised {@code CollisionWorld} bytes (world.proto); empty if none.
   */
  public byte[] collisionWorldBytes() {
    return reply.hasWorld() ? reply.getWorld().toByteArray() : new byte[0];
  }

  /** The match's weapons, one per Weapon, rifle first (game.proto messages). */
  public List<WeaponSpec> weapons() {
    return Collections.unmodifiableList(reply.getWeaponsList());
  }

  /** The reply as the server sent it, for the game channel's code. */
  public JoinMatchReply reply() {
    return reply;
  }

  @Override
  public String toString() {
    return "JoinTicket{match " + matchId() + " " + host + ":" + udpPort() + "}";
  }
}
