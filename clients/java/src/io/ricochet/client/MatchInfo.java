package io.ricochet.client;

/**
 * One match as {@link RicochetClient#listMatches} and {@link RicochetClient#createMatch} show it.
 */
public final class MatchInfo {
  private final long matchId;
  private final String name;
  private final String mode;
  private final String map;
  private final int players;
  private final int maxPlayers;

  MatchInfo(long matchId, String name, String mode, String map, int players, int maxPlayers) {
    this.matchId = matchId;
    this.name = name;
    this.mode = mode;
    this.map = map;
    this.players = players;
    this.maxPlayers = maxPlayers;
  }

  static MatchInfo of(io.ricochet.wire.ControlProto.MatchInfo wire) {
    return new MatchInfo(wire.getMatchId() & 0xFFFFFFFFL, wire.getName(), wire.getMode(),
        wire.getMap(), wire.getPlayers(), wire.getMaxPlayers());
  }

  /** The match's id, what {@link RicochetClient#joinMatch} takes. */
  public long matchId() {
    return matchId;
  }

  /** Its name. */
  public String name() {
    return name;
  }

  /** "ffa" (free-for-all) or "tdm" (team deathmatch). */
  public String mode() {
    return mode;
  }

  /** Its map's name. */
  public String map() {
    return map;
  }

  /** Seats held: connected, reserved and reconnecting players. */
  public int players() {
    return players;
  }

  /** Its seats. */
  public int maxPlayers() {
    return maxPlayers;
  }

  @Override
  public String toString() {
    return "MatchInfo{" + matchId + " " + name + " " + mode + " " + map + " " + players + "/"
        + maxPlayers + "}";
  }
}
