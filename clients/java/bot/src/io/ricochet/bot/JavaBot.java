package io.ricochet.bot;

import io.ricochet.client.GameConnection;
import io.ricochet.client.GameListener;
import io.ricochet.client.GameSnapshot;
import io.ricochet.client.GameStats;
import io.ricochet.client.MatchInfo;
import io.ricochet.client.PinStore;
import io.ricochet.client.RicochetClient;
import io.ricochet.client.RicochetException;
import io.ricochet.client.Session;
import io.ricochet.client.core.transport.DisconnectReason;
import io.ricochet.wire.ControlProto.ErrorCode;
import io.ricochet.wire.ControlProto.MatchResults;
import io.ricochet.wire.ControlProto.PlayerMatchResult;
import io.ricochet.wire.GameProto.GameEvent;
import io.ricochet.wire.GameProto.Kill;
import io.ricochet.wire.GameProto.MatchPhase;
import io.ricochet.wire.GameProto.MatchState;
import io.ricochet.wire.GameProto.PlayerScore;
import java.io.PrintStream;
import java.util.ArrayList;
import java.util.List;
import java.util.Random;
import java.util.concurrent.CompletionException;
import java.util.concurrent.ScheduledExecutorService;
import java.util.concurrent.ScheduledFuture;
import java.util.concurrent.TimeUnit;

/**
 * One bot: its own {@link RicochetClient} (the library's public API only), through an explicit
 * lifecycle:
 *
 * <pre>
 *   STARTING ─▶ SIGNING_IN ─▶ JOINING ─▶ PLAYING ─▶ AWAITING_RESULTS ─▶ DONE
 *                                ▲                          │ (MatchResults; more --matches)
 *                                └──────────────────────────┘
 * </pre>
 *
 * <p>SIGNING_IN registers the account (an existing one is fine) and logs in; JOINING lists the
 * matches and joins one (waiting out MATCH_FULL); PLAYING decides an input per snapshot ({@link
 * Brain}) and counts kills and deaths from the match's Kill events (of the running phase, where the
 * match counts them, as ricochet-bot does); the match's end ({@code MatchEnded}, then the game
 * channel closed by the server) waits for the control channel's MatchResults. Anything else that
 * ends a channel, and every deadline, ends it in DONE with an error. Every method but the
 * constructor runs on the bots' shared loop thread (the clients' listener executor), so its state
 * needs no lock.
 */
final class JavaBot {
  /** Where a bot is in its lifecycle. */
  enum State { STARTING, SIGNING_IN, JOINING, PLAYING, AWAITING_RESULTS, DONE }

  /** Bound on signing in, and on finding a match with room, each, ms. */
  static final long STEP_DEADLINE_MS = 60_000;
  /** Bound on the MatchResults after the match ended, ms. */
  static final long RESULTS_DEADLINE_MS = 15_000;
  private static final long JOIN_RETRY_MS = 1000;
  private static final int LOGIN_ATTEMPTS = 6;

  private final BotOptions options;
  private final String name;
  private final ScheduledExecutorService loop;
  private final PinStore pinStore;
  private final Runnable onDone;
  private final PrintStream log;
  private final Brain brain;
  private final Random jitter;
  private final Scene scene = new Scene();
  private final Brain.Decision decision = new Brain.Decision();
  private final BotFigures figures = new BotFigures();

  private volatile State state =
      State.STARTING; // volatile: the exit report may read it off the loop
  private volatile String error = "";
  private long startedNs;
  private long stepDeadlineNs;
  private ScheduledFuture<?> timer;
  private RicochetClient client; // the server it plays on
  // --find-match: the clients of servers it was sent away from, closed at the end (closing one
  // earlier would end the bot: every client calls its one control listener).
  private final List<RicochetClient> leftBehind = new ArrayList<>();
  private long accountId;
  private String username = "";
  private long matchId;
  private GameConnection game;
  private Connection connection; // the listener of the newest game connection
  // The match as the Kill and MatchState events tell it.
  private long ownEntity;
  private MatchPhase phase = MatchPhase.MATCH_PHASE_UNSPECIFIED;
  private boolean matchEnded;
  private boolean arrived; // a MatchState came on the newest game connection
  private int matchKills;
  private int matchDeaths;
  private int scoreCounted;

  /**
   * Bot {@code k} (1..bots) of {@code options}; {@code pinStore} for --trust-file (null: the pin);
   * {@code onDone} runs on the loop once it is DONE; transitions go to {@code log} when verbose.
   */
  JavaBot(BotOptions options, int k, ScheduledExecutorService loop, PinStore pinStore,
      Runnable onDone, PrintStream log) {
    this.options = options;
    this.name = options.nameOf(k);
    this.loop = loop;
    this.pinStore = pinStore;
    this.onDone = onDone;
    this.log = log;
    long seed = options.seed + k - 1;
    brain = new Brain(options.skill, seed);
    jitter = new Random(~seed);
  }

  /** Account name. */
  String name() {
    return name;
  }

  /** Where it is. */
  State state() {
    return state;
  }

  /** Why it failed; empty when it did not. */
  String error() {
    return error;
  }

  /** Its figures so far, the open game connection's included (a copy). */
  BotFigures figures() {
    BotFigures now = figures.copy();
    if (connection != null) connection.addTo(now);
    return now;
  }

  /** Connects, signs in, joins and plays (on the loop). */
  void start() {
    if (state != State.STARTING) return; // stopped before its turn came
    startedNs = System.nanoTime();
    RicochetClient.Builder builder = RicochetClient.builder()
                                         .host(options.host)
                                         .controlPort(options.port)
                                         .listenerExecutor(loop)
                                         .listener(new ControlListener());
    if (!options.fingerprint.isEmpty()) builder.pinSha256(options.fingerprint);
    if (pinStore != null) builder.pinStore(pinStore);
    client = builder.build();
    transition(State.SIGNING_IN, "starting");
    stepDeadlineNs = System.nanoTime() + TimeUnit.MILLISECONDS.toNanos(STEP_DEADLINE_MS);
    client.register(name, options.password).whenComplete((id, failure) -> {
      if (state != State.SIGNING_IN) return;
      ErrorCode code = errorCode(failure);
      if (failure != null && code != ErrorCode.DUPLICATE_USERNAME
          && code != ErrorCode.REGISTRATION_RATE_LIMITED) {
        // A lost reply of an earlier attempt may have registered it: the login says.
        finish("register: " + cause(failure).getMessage());
        return;
      }
      login(1);
    });
  }

  /** Ends it (the time is up, a signal): leaves the game, closes the client; not an error. */
  void stop(String why) {
    if (state == State.DONE) return;
    transition(State.DONE, why);
    end();
  }

  private void login(int attempt) {
    client.login(name, options.password).whenComplete((session, failure) -> {
      if (state != State.SIGNING_IN) return;
      if (failure == null) {
        signedIn(session);
        return;
      }
      ErrorCode code = errorCode(failure);
      boolean busy = code == ErrorCode.SERVER_BUSY || code == ErrorCode.LOGIN_RATE_LIMITED;
      if (!busy || attempt >= LOGIN_ATTEMPTS || System.nanoTime() > stepDeadlineNs) {
        finish("login: " + cause(failure).getMessage());
        return;
      }
      // 0.5 s doubling, +-50 %: bots refused together spread out.
      long backOffMs = (long) (500L * (1L << (attempt - 1)) * (0.5 + jitter.nextDouble()));
      later(backOffMs, () -> login(attempt + 1));
    });
  }

  private void signedIn(Session session) {
    accountId = session.accountId();
    username = session.username();
    join("signed in as account " + accountId);
  }

  private void join(String why) {
    transition(State.JOINING, why);
    stepDeadlineNs = System.nanoTime() + TimeUnit.MILLISECONDS.toNanos(STEP_DEADLINE_MS);
    tryJoin();
  }

  private void tryJoin() {
    if (state != State.JOINING) return;
    if (System.nanoTime() > stepDeadlineNs) {
      finish("no match to join within " + STEP_DEADLINE_MS + " ms");
      return;
    }
    if (!options.findMode.isEmpty()) {
      findMatch();
      return;
    }
    client.listMatches().whenComplete((matches, failure) -> {
      if (state != State.JOINING) return;
      if (failure != null) {
        finish("list matches: " + cause(failure).getMessage());
        return;
      }
      long id = chooseMatch(matches);
      if (id == 0) {
        later(JOIN_RETRY_MS, this::tryJoin);
        return;
      }
      Connection listener = new Connection();
      client.joinMatch(id, listener).whenComplete((joined, joinFailure) -> {
        if (state != State.JOINING) {
          if (joined != null) joined.close();
          return;
        }
        if (joinFailure != null) {
          ErrorCode code = errorCode(joinFailure);
          if (code == ErrorCode.MATCH_FULL || code == ErrorCode.ADDRESS_SEAT_LIMIT) {
            later(JOIN_RETRY_MS, this::tryJoin);
          } else {
            finish("join match " + id + ": " + cause(joinFailure).getMessage());
          }
          return;
        }
        playing(id, joined, listener, "");
      });
    });
  }

  /**
   * --find-match: asks for a seat, follows the assignment (a client of the server it names,
   * signed in with this session's token, unless it is this one) and joins there with the ticket.
   * No seat anywhere yet, a match that filled up or ended meanwhile (MATCH_NOT_FOUND: the fleet
   * directory lags a match's end by up to a heartbeat) or a ticket gone stale: asks again a
   * second later.
   */
  private void findMatch() {
    client.findMatch(options.findMode, options.findMap)
        .thenCompose(assignment
            -> client.follow(assignment)
                   .thenCompose(there -> there.joinMatch(assignment).handle((ticket, failure) -> {
                     if (there != client && state == State.DONE) {
                       there.close(); // stopped meanwhile: end() closed the others
                     } else if (there != client) {
                       // From now on the bot plays there; the one it left is closed at the end.
                       leftBehind.add(client);
                       client = there;
                     }
                     if (failure != null) throw new CompletionException(cause(failure));
                     return ticket;
                   })))
        .whenComplete((ticket, failure) -> {
          if (state != State.JOINING) return;
          if (failure != null) {
            ErrorCode code = errorCode(failure);
            if (code == ErrorCode.NO_SERVER_AVAILABLE || code == ErrorCode.FIND_MATCH_RATE_LIMITED
                || code == ErrorCode.MATCH_FULL || code == ErrorCode.MATCH_NOT_FOUND
                || code == ErrorCode.UNKNOWN_TICKET || code == ErrorCode.EXPIRED_TICKET) {
              later(JOIN_RETRY_MS, this::tryJoin);
            } else {
              finish("find match " + options.findMode + ": " + cause(failure).getMessage());
            }
            return;
          }
          Connection listener = new Connection();
          client.connectGame(ticket, listener).whenComplete((joined, connectFailure) -> {
            if (state != State.JOINING) {
              if (joined != null) joined.close();
              return;
            }
            if (connectFailure != null) {
              finish("connect to match " + ticket.matchId() + " at " + ticket.host() + ": "
                  + cause(connectFailure).getMessage());
              return;
            }
            playing(ticket.matchId(), joined, listener, " on " + ticket.host());
          });
        });
  }

  /** Joined match {@code id} ({@code where}, for the log): plays it on {@code joined}. */
  private void playing(long id, GameConnection joined, Connection listener, String where) {
    matchId = id;
    game = joined;
    connection = listener;
    matchEnded = false;
    phase = MatchPhase.MATCH_PHASE_UNSPECIFIED;
    transition(State.PLAYING, "joined match " + id + where + " from port " + joined.localPort());
  }

  /** --match, or the first listed match with room; 0 when none has room. */
  private long chooseMatch(List<MatchInfo> matches) {
    for (MatchInfo match : matches) {
      boolean room = match.players() < match.maxPlayers();
      if (options.matchId != 0 ? match.matchId() == options.matchId : room) {
        return match.matchId();
      }
    }
    return 0;
  }

  /** The game channel of one joined match: what the bot sees, and its input per snapshot. */
  private final class Connection implements GameListener {
    private boolean active = true;
    private long connectedSinceNs = -1;
    private GameStats newest;

    /** Adds its time connected and its counts from the start to {@code out}. */
    void addTo(BotFigures out) {
      if (connectedSinceNs >= 0) out.connectedS += (System.nanoTime() - connectedSinceNs) / 1e9;
      if (newest != null) out.addConnection(newest);
    }

    /** It is over: its figures join the bot's; later callbacks are ignored. */
    void retire() {
      if (!active) return;
      active = false;
      addTo(figures);
      connectedSinceNs = -1;
      newest = null;
    }

    @Override
    public void onConnected() {
      if (!active) return;
      connectedSinceNs = System.nanoTime();
      arrived = false;
    }

    @Override
    public void onSnapshot(GameSnapshot snapshot) {
      if (!active) return;
      ++figures.snapshots;
      if (figures.firstSnapshotMs < 0) {
        figures.firstSnapshotMs = (System.nanoTime() - startedNs) / 1e6;
      }
      if (snapshot.yourEntityId() != 0) ownEntity = snapshot.yourEntityId();
      if (state != State.PLAYING || game == null) return;
      scene.fill(snapshot);
      brain.decide(scene, System.nanoTime() / 1_000_000, decision);
      game.setInput(decision.moveRight, decision.moveForward, decision.yawRad, decision.pitchRad,
          decision.buttons, 0);
    }

    @Override
    public void onEvent(GameEvent event) {
      if (active) onGameEvent(event);
    }

    @Override
    public void onReconnecting(DisconnectReason why) {
      if (!active) return;
      ++figures.reconnects;
      if (connectedSinceNs >= 0) {
        figures.connectedS += (System.nanoTime() - connectedSinceNs) / 1e9;
        connectedSinceNs = -1;
      }
    }

    @Override
    public void onStats(GameStats stats) {
      if (!active) return;
      figures.addPeriod(stats);
      newest = stats;
    }

    @Override
    public void onDisconnected(DisconnectReason reason) {
      if (!active) return;
      retire();
      if (connection == this) {
        connection = null;
        game = null;
      }
      if (state != State.PLAYING) return;
      if (matchEnded) {
        transition(State.AWAITING_RESULTS, "the match ended; game channel " + reason);
        later(RESULTS_DEADLINE_MS, () -> {
          if (state == State.AWAITING_RESULTS) {
            finish("no MatchResults within " + RESULTS_DEADLINE_MS + " ms of the match's end");
          }
        });
      } else {
        finish("game channel ended: " + reason);
      }
    }
  }

  private void onGameEvent(GameEvent event) {
    switch (event.getEventCase()) {
      case KILL:
        onKill(event.getKill());
        break;
      case HIT:
        if (ownEntity != 0 && event.getHit().getAttackerEntityId() == ownEntity) {
          ++figures.hitsDealt;
        }
        break;
      case PLAYER_JOINED:
        // Our own PlayerJoined comes last of those sent on arrival, before any payload.
        if (ownEntity == 0 && event.getPlayerJoined().getName().equalsIgnoreCase(username)) {
          ownEntity = event.getPlayerJoined().getEntityId();
        }
        break;
      case MATCH_STATE: {
        MatchState match = event.getMatchState();
        if (match.getPhase() == MatchPhase.MATCH_PHASE_RUNNING
            && phase != MatchPhase.MATCH_PHASE_RUNNING) {
          // Entering running resets every score (a reconnect's arrival does not change it).
          matchKills = 0;
          matchDeaths = 0;
          scoreCounted = 0;
        }
        phase = match.getPhase();
        if (!arrived) {
          arrived = true;
          adoptScores(match);
        }
        break;
      }
      case MATCH_ENDED:
        matchEnded = true;
        break;
      default:
        break;
    }
  }

  private void onKill(Kill kill) {
    ++figures.killEvents;
    if (phase != MatchPhase.MATCH_PHASE_RUNNING || ownEntity == 0) return;
    if (kill.getVictimEntityId() == ownEntity) {
      ++figures.deaths;
      ++matchDeaths;
      // A suicide, or a death by the world, costs a point.
      if (kill.getKillerEntityId() == ownEntity || kill.getKillerEntityId() == 0) --scoreCounted;
    } else if (kill.getKillerEntityId() == ownEntity) {
      ++figures.kills;
      ++matchKills;
      ++scoreCounted;
    }
  }

  /**
   * On each arrival in a running match (a reconnect's too): Kill events sent to an earlier
   * connection and not received went with it (the reliable stream is per connection); the
   * arrival's scoreboard is the server's word.
   */
  private void adoptScores(MatchState match) {
    if (phase != MatchPhase.MATCH_PHASE_RUNNING || ownEntity == 0) return;
    for (PlayerScore score : match.getScoresList()) {
      if (score.getEntityId() != ownEntity) continue;
      int missedKills = score.getKills() - matchKills;
      int missedDeaths = score.getDeaths() - matchDeaths;
      if (missedKills == 0 && missedDeaths == 0 && score.getScore() == scoreCounted) return;
      ++figures.scoreResyncs;
      figures.kills += missedKills;
      figures.deaths += missedDeaths;
      matchKills = score.getKills();
      matchDeaths = score.getDeaths();
      scoreCounted = score.getScore();
      return;
    }
  }

  private final class ControlListener implements RicochetClient.Listener {
    @Override
    public void onMatchResults(MatchResults results) {
      if (state != State.PLAYING && state != State.AWAITING_RESULTS) return;
      if (results.getMatchId() != matchId) return;
      ++figures.matches;
      for (PlayerMatchResult player : results.getPlayersList()) {
        if (player.getAccountId() != accountId) continue;
        figures.resultKills += player.getKills();
        figures.resultDeaths += player.getDeaths();
        figures.resultScore += player.getScore();
      }
      closeGame();
      ownEntity = 0;
      String why = "match " + results.getMatchId() + " results (" + results.getEndReason() + ")";
      if (options.matches > 0 && figures.matches >= options.matches) {
        transition(State.DONE, why);
        end();
      } else {
        join(why);
      }
    }

    @Override
    public void onDisconnected(io.ricochet.client.Disconnect disconnect) {
      if (state != State.DONE) finish("control channel ended: " + disconnect);
    }
  }

  private void closeGame() {
    if (connection != null) connection.retire();
    connection = null;
    if (game != null) game.close();
    game = null;
  }

  /** Fails: DONE with {@code why} as the error. */
  private void finish(String why) {
    if (state == State.DONE) return;
    error = why;
    log.println("ricochet-java-bot: " + name + ": " + why);
    transition(State.DONE, "failed");
    end();
  }

  /** Closes everything once in DONE, and says so. */
  private void end() {
    if (timer != null) timer.cancel(false);
    closeGame();
    if (client != null) client.close();
    for (RicochetClient earlier : leftBehind) earlier.close();
    onDone.run();
  }

  private void transition(State next, String why) {
    if (options.verbose)
      log.println("ricochet-java-bot: " + name + ": " + state + " -> " + next + " (" + why + ")");
    state = next;
  }

  /** Runs {@code task} on the loop after {@code delayMs}, unless DONE by then. */
  private void later(long delayMs, Runnable task) {
    timer = loop.schedule(() -> {
      if (state != State.DONE) task.run();
    }, delayMs, TimeUnit.MILLISECONDS);
  }

  private static Throwable cause(Throwable failure) {
    return failure instanceof CompletionException && failure.getCause() != null ? failure.getCause()
                                                                                : failure;
  }

  private static ErrorCode errorCode(Throwable failure) {
    if (failure == null) return null;
    Throwable cause = cause(failure);
    return cause instanceof RicochetException ? ((RicochetException) cause).errorCode() : null;
  }
}
