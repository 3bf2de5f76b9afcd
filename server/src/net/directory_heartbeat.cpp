#include "directory_heartbeat.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/asio/post.hpp>
#include <boost/unordered/unordered_flat_map.hpp>
#include <future>

#include "match_registry.h"
#include "steady_time.h"

namespace ricochet::server {
namespace asio = boost::asio;
namespace {

db::UnixMillis unix_now_ms() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

DirectoryHeartbeat::DirectoryHeartbeat(asio::io_context& io, db::DbWorker& db,
                                       MatchRegistry& matches, PlacementCounters& counters,
                                       proto::TimeUs period_us, proto::TimeUs ttl_us,
                                       Describe describe)
    : strand_(asio::make_strand(io)),
      timer_(strand_),
      db_(db),
      matches_(matches),
      counters_(counters),
      schedule_(period_us, ttl_us, steady_now_us()),
      describe_(std::move(describe)) {}

void DirectoryHeartbeat::start() {
  asio::post(strand_, [this] { beat(); });
}

void DirectoryHeartbeat::matches_changed() {
  asio::post(strand_, [this] {
    schedule_.changed(steady_now_us());
    arm();  // moves the timer's wait, or nothing while a beat is in flight or once stopped
  });
}

void DirectoryHeartbeat::arm() {
  const auto next = schedule_.next_at();
  if (!next) return;
  timer_.expires_at(steady_time_point(*next));
  timer_.async_wait([this](const boost::system::error_code& error) {
    if (!error) beat();
  });
}

void DirectoryHeartbeat::beat() {
  if (!schedule_.start(steady_now_us())) return arm();
  DirectoryEntry entry = describe_();
  server_id_ = entry.server.server_id;
  // Not before the figures were counted, should the wall clock have stepped back since.
  const db::UnixMillis now = std::max(unix_now_ms(), entry.server.counted_ms);
  using Held = db::DbResult<std::vector<db::HeldSeats>>;
  db_.submit(
      [entry = std::move(entry), now](db::DbServices& services) -> Held {
        if (db::DbStatus written = services.placement.heartbeat(entry.server, entry.matches, now);
            !written.ok()) {
          return written.error();
        }
        // Every server purges: whichever beats first after a server stops removes it.
        if (auto purged = services.placement.purge_stale(now); !purged.ok()) {
          spdlog::debug("placement: purging the directory failed: {}", purged.error().message);
        }
        return services.placement.held_seats(entry.server.server_id, now);
      },
      [this](std::function<void()> completion) { asio::post(strand_, std::move(completion)); },
      [this](Held held) {
        const bool written = held.ok();
        counters_.count(written ? HeartbeatOutcome::Written : HeartbeatOutcome::Failed);
        switch (schedule_.finished(written, steady_now_us())) {
          case DirectoryListing::Listed:
            spdlog::info("placement: server {} is in the fleet directory", server_id_);
            break;
          case DirectoryListing::Lost:
            spdlog::warn(
                "placement: server {} has had no heartbeat written for longer than the TTL: the "
                "fleet no longer places players here ({})",
                server_id_, held.error().message);
            break;
          case DirectoryListing::Unchanged:
            if (!written) {
              spdlog::debug("placement: heartbeat not written: {}", held.error().message);
            }
            break;
        }
        if (written) {
          boost::unordered_flat_map<std::uint32_t, int> by_match;
          // Against direct joins, the open tickets only: the players of claimed ones are
          // seated here already, or being seated with their ticket.
          for (const db::HeldSeats& seats : held.value()) {
            if (seats.match_id > 0 && seats.seats > seats.claimed) {
              by_match[static_cast<std::uint32_t>(seats.match_id)] =
                  static_cast<int>(seats.seats - seats.claimed);
            }
          }
          matches_.set_held_seats(std::move(by_match));
        }
        arm();
      });
}

bool DirectoryHeartbeat::leave(std::chrono::milliseconds wait) {
  auto left = std::make_shared<std::promise<bool>>();
  std::future<bool> done = left->get_future();
  // On the strand, so that no beat starts after the stop; the DB thread runs the leave after
  // any beat already queued, so the row is not written again.
  asio::post(strand_, [this, left] {
    schedule_.stop();
    timer_.cancel();
    if (server_id_.empty()) return left->set_value(true);
    db_.submit([id = server_id_](db::DbServices& services) { return services.placement.leave(id); },
               [](std::function<void()> completion) { completion(); },  // on the DB thread
               [left, id = server_id_](db::DbResult<bool> result) {
                 if (!result.ok()) {
                   spdlog::warn("placement: leaving the directory failed: {}",
                                result.error().message);
                 } else {
                   spdlog::info("placement: server {} left the fleet directory", id);
                 }
                 left->set_value(result.ok());
               });
  });
  return done.wait_for(wait) == std::future_status::ready && done.get();
}

}  // namespace ricochet::server
