#pragma once
/// The leaderboard queries of the SQLite and PostgreSQL stores, in one place so that a test can
/// check their query plans (each must walk its player_stats index in order: no sort, no full scan).
///
/// Every player_stats row has matches >= 1 (migrations.cpp), so the rating and kills boards need
/// no filter. The win-rate expression must be spelled exactly as in player_stats_by_win_rate,
/// or SQLite will not use that index. PostgreSQL's differ in two words: parameters are $N, and
/// the win rate is a DOUBLE PRECISION (its REAL is 32-bit).

#include "ricochet/db/records.h"

namespace ricochet::db::leaderboard_sql {

/// The best `limit` entries: account_id, username, value, matches. Parameters: limit, then
/// min_matches for WinRate.
inline const char* top(LeaderboardKind kind) {
  switch (kind) {
    case LeaderboardKind::Rating:
      return "SELECT s.account_id, a.username, s.rating, s.matches"
             " FROM player_stats AS s JOIN accounts AS a ON a.id = s.account_id"
             " ORDER BY s.rating DESC, s.account_id LIMIT ?1";
    case LeaderboardKind::Kills:
      return "SELECT s.account_id, a.username, s.kills, s.matches"
             " FROM player_stats AS s JOIN accounts AS a ON a.id = s.account_id"
             " ORDER BY s.kills DESC, s.account_id LIMIT ?1";
    case LeaderboardKind::WinRate:
      return "SELECT s.account_id, a.username, CAST(s.wins AS REAL) / s.matches, s.matches"
             " FROM player_stats AS s JOIN accounts AS a ON a.id = s.account_id"
             " WHERE s.matches >= ?2"
             " ORDER BY CAST(s.wins AS REAL) / s.matches DESC, s.account_id LIMIT ?1";
  }
  return nullptr;
}

/// One account's username, matches and value; matches and value are NULL when it never played.
/// Parameter: account id.
inline const char* entry_of(LeaderboardKind kind) {
  switch (kind) {
    case LeaderboardKind::Rating:
      return "SELECT a.username, s.matches, s.rating"
             " FROM accounts AS a LEFT JOIN player_stats AS s ON s.account_id = a.id"
             " WHERE a.id = ?1";
    case LeaderboardKind::Kills:
      return "SELECT a.username, s.matches, s.kills"
             " FROM accounts AS a LEFT JOIN player_stats AS s ON s.account_id = a.id"
             " WHERE a.id = ?1";
    case LeaderboardKind::WinRate:
      return "SELECT a.username, s.matches, CAST(s.wins AS REAL) / s.matches"
             " FROM accounts AS a LEFT JOIN player_stats AS s ON s.account_id = a.id"
             " WHERE a.id = ?1";
  }
  return nullptr;
}

/// How many entries of the board have a strictly better value (rank - 1). Parameters: value,
/// then min_matches for WinRate.
inline const char* count_better(LeaderboardKind kind) {
  switch (kind) {
    case LeaderboardKind::Rating:
      return "SELECT COUNT(*) FROM player_stats WHERE rating > ?1";
    case LeaderboardKind::Kills:
      return "SELECT COUNT(*) FROM player_stats WHERE kills > ?1";
    case LeaderboardKind::WinRate:
      return "SELECT COUNT(*) FROM player_stats"
             " WHERE CAST(wins AS REAL) / matches > ?1 AND matches >= ?2";
  }
  return nullptr;
}

/// top() for PostgreSQL.
inline const char* postgres_top(LeaderboardKind kind) {
  switch (kind) {
    case LeaderboardKind::Rating:
      return "SELECT s.account_id, a.username, s.rating, s.matches"
             " FROM player_stats AS s JOIN accounts AS a ON a.id = s.account_id"
             " ORDER BY s.rating DESC, s.account_id LIMIT $1";
    case LeaderboardKind::Kills:
      return "SELECT s.account_id, a.username, s.kills, s.matches"
             " FROM player_stats AS s JOIN accounts AS a ON a.id = s.account_id"
             " ORDER BY s.kills DESC, s.account_id LIMIT $1";
    case LeaderboardKind::WinRate:
      return "SELECT s.account_id, a.username, CAST(s.wins AS DOUBLE PRECISION) / s.matches,"
             " s.matches FROM player_stats AS s JOIN accounts AS a ON a.id = s.account_id"
             " WHERE s.matches >= $2"
             " ORDER BY CAST(s.wins AS DOUBLE PRECISION) / s.matches DESC, s.account_id LIMIT $1";
  }
  return nullptr;
}

/// entry_of() for PostgreSQL.
inline const char* postgres_entry_of(LeaderboardKind kind) {
  switch (kind) {
    case LeaderboardKind::Rating:
      return "SELECT a.username, s.matches, s.rating"
             " FROM accounts AS a LEFT JOIN player_stats AS s ON s.account_id = a.id"
             " WHERE a.id = $1";
    case LeaderboardKind::Kills:
      return "SELECT a.username, s.matches, s.kills"
             " FROM accounts AS a LEFT JOIN player_stats AS s ON s.account_id = a.id"
             " WHERE a.id = $1";
    case LeaderboardKind::WinRate:
      return "SELECT a.username, s.matches, CAST(s.wins AS DOUBLE PRECISION) / s.matches"
             " FROM accounts AS a LEFT JOIN player_stats AS s ON s.account_id = a.id"
             " WHERE a.id = $1";
  }
  return nullptr;
}

/// count_better() for PostgreSQL.
inline const char* postgres_count_better(LeaderboardKind kind) {
  switch (kind) {
    case LeaderboardKind::Rating:
      return "SELECT COUNT(*) FROM player_stats WHERE rating > $1";
    case LeaderboardKind::Kills:
      return "SELECT COUNT(*) FROM player_stats WHERE kills > $1";
    case LeaderboardKind::WinRate:
      return "SELECT COUNT(*) FROM player_stats"
             " WHERE CAST(wins AS DOUBLE PRECISION) / matches > $1 AND matches >= $2";
  }
  return nullptr;
}

}  // namespace ricochet::db::leaderboard_sql
