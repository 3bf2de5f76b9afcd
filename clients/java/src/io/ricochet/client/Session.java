package io.ricochet.client;

/**
 * A signed-in session, the result of {@link RicochetClient#login} and {@link
 * RicochetClient#resume}. Keep {@link #sessionToken()} to resume after a reconnect.
 */
public final class Session {
  private final long accountId;
  private final String username;
  private final String sessionToken;
  private final long expiresUnixMs;
  private final long matchId;

  Session(long accountId, String username, String sessionToken, long expiresUnixMs, long matchId) {
    this.accountId = accountId;
    this.username = username;
    this.sessionToken = sessionToken;
    this.expiresUnixMs = expiresUnixMs;
    this.matchId = matchId;
  }

  /** The account's id on the server. */
  public long accountId() {
    return accountId;
  }

  /**
   * The username as the server names it: for a resume, as registered; for a login, as typed
   * (names are unique ignoring case).
   */
  public String username() {
    return username;
  }

  /** 64 lowercase hex digits; for a resume, the token that was resumed. A secret. */
  public String sessionToken() {
    return sessionToken;
  }

  /** When the token stops working, Unix ms on the server's clock. */
  public long expiresUnixMs() {
    return expiresUnixMs;
  }

  /**
   * For a resume, the match this sign-in still holds a seat in: the resumed connection is back in
   * it ({@link io.ricochet.client.core.control.ControlState#IN_MATCH}: {@code leave} and {@code
   * chat} work, its results arrive; a running game connection plays on). 0 for a login, or when
   * the seat was given up meanwhile (the connection is then only signed in).
   */
  public long matchId() {
    return matchId;
  }

  @Override
  public String toString() {
    return "Session{account " + accountId + " " + username
        + (matchId != 0 ? " in match " + matchId : "") + "}";
  }
}
