#pragma once
/// The DB thread: every database job runs here, in submission order, never on the game thread.
///
///   game thread ── submit(job, post, done) ──▶ queue ──▶ DB thread runs job(services)
///   game thread ◀── post(done(result)) ─────────────────┘
///
/// `post` is how a result gets back to the caller: it receives a completion and must run it on
/// the caller's executor (the server passes `asio::post(io_context, ...)`; tests pass a queue
/// they drain). The game tick therefore never waits for the disk: a slow or locked database
/// shows as latency on logins, never as a late tick. When more than `max_queued` jobs wait, a
/// new job is refused at once with QueueFull (back-pressure instead of unbounded memory). Jobs
/// still queued at stop() complete with Stopped.
///
/// Argon2id is deliberately slow (~100 ms per hash at interactive cost), so login(),
/// register_account() and change_password() run it on separate password threads between two
/// short DB-thread steps (accounts.h):
///
///   DB thread: lookup, rate limits ─▶ password thread: Argon2id ─▶ DB thread: session, counters
///
/// A burst of logins then delays other logins, not match results or token checks. The password
/// threads take a waiting login check of an existing account before any other hash, so a storm of
/// registrations delays an existing account's login by at most the hashes already running;
/// registrations and password changes past `max_queued_hashes` are refused at once (QueueFull)
/// instead of waiting minutes, and such a registration is not counted against its address's
/// registration limit. The password threads run at a low priority (`password_nice`), so
/// Argon2id gets the cores the game ticks leave, never the ones they need.

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "ricochet/db/accounts.h"
#include "ricochet/db/matches.h"
#include "ricochet/db/placement.h"
#include "ricochet/db/store.h"

namespace ricochet::db {

/// Runs a completion on the caller's executor.
using Post = std::function<void(std::function<void()>)>;

namespace detail {

/// Hands one job's result to the caller through its post; also the answers of a worker that
/// is stopped or whose queue is full. Copies share the post and the completion.
template <class R>
class Delivery {
 public:
  template <class Done>
  Delivery(Post post, Done done)
      : post_(std::make_shared<Post>(std::move(post))),
        done_(std::make_shared<std::function<void(R)>>(std::move(done))) {}
  void operator()(R result) const {
    (*post_)([done = done_, result = std::move(result)]() mutable { (*done)(std::move(result)); });
  }
  void stopped() const { (*this)(R(DbError{DbErrorCode::Stopped, "the DB worker stopped"})); }
  void queue_full() const {
    (*this)(R(DbError{DbErrorCode::QueueFull, "the DB queue is full; retry later"}));
  }

 private:
  std::shared_ptr<Post> post_;
  std::shared_ptr<std::function<void(R)>> done_;
};

}  // namespace detail

/// What a job on the DB thread works with: the rules over the worker's store.
struct DbServices {
  Accounts& accounts;
  Matches& matches;
  Placement& placement;
};

struct DbWorkerOptions {
  AccountsOptions accounts;
  MatchesOptions matches;
  PlacementOptions placement;
  std::size_t max_queued = 10'000;  ///< per queue (DB jobs, login password checks)
  /// Registrations and password changes waiting for a password thread (each ~100 ms of Argon2id
  /// at interactive cost: 256 are ~26 s of one thread's work); more are refused with QueueFull
  /// at once. A 200-bot load test on a fresh database registers them all.
  std::size_t max_queued_hashes = 256;
  int password_threads = 1;  ///< each Argon2id interactive hash holds 64 MiB while it runs
  /// Nice value of the password threads (Linux, per thread; 0..19, 19 the lowest priority).
  /// At 10 (CFS weight 110 against 1024) a hash gets about a tenth of a core a busy nice-0
  /// thread (a match tick) also wants, and the tick preempts it when it wakes; 19 would starve
  /// logins for as long as anything else keeps the cores busy.
  int password_nice = 10;
};

class DbWorker {
 public:
  /// Starts the DB thread; it owns the store from here on.
  DbWorker(std::unique_ptr<Store> store, DbWorkerOptions options = {});
  /// stop(), then joins.
  ~DbWorker();
  DbWorker(const DbWorker&) = delete;
  DbWorker& operator=(const DbWorker&) = delete;

  /// Queues job(DbServices&) -> R for the DB thread, then posts done(R) through `post`. R is a
  /// DbResult<T> or DbStatus. Never blocks on the database; thread-safe.
  template <class Job, class Done>
  void submit(Job job, Post post, Done done);

  /// Accounts::login with the password check on a password thread (see above).
  void login(std::string username, std::string password, std::string address, UnixMillis now,
             Post post, std::function<void(DbResult<LoginResult>)> done);
  /// Accounts::register_account with the hashing on a password thread.
  void register_account(std::string username, std::string password, std::string address,
                        UnixMillis now, Post post, std::function<void(DbResult<AccountId>)> done);
  /// Accounts::change_password with both Argon2id runs on a password thread.
  void change_password(AccountId id, std::string old_password, std::string new_password, Post post,
                       std::function<void(DbStatus)> done);

  /// Lets the running jobs finish, completes the queued ones with Stopped, joins the threads.
  void stop();
  std::size_t queued() const;
  /// Jobs run so far (for metrics and tests).
  std::size_t completed() const;

 private:
  using Task = std::function<void(DbServices*)>;  ///< nullptr: the worker stopped
  using CpuTask = std::function<void(bool stopped)>;
  /// Which queue of the password threads a task waits in; LoginCheck (an existing account's
  /// login) is taken first, NewHash (registrations, password changes, unknown names) after.
  enum class PasswordWork { LoginCheck, NewHash };
  /// Queues a task, or runs it at once as stopped; false when the queue holds `cap` tasks.
  template <class T, class Stopped>
  bool push(std::deque<T>& queue, std::size_t cap, std::condition_variable& wake, T task,
            Stopped stopped);
  /// Waits for a task; false when the worker stops.
  bool pop(Task& task);
  bool pop_cpu(CpuTask& task);
  /// One job in three steps: begin(DbServices&) -> DbResult<S> or DbStatus on the DB thread,
  /// then work(S&) -> W on a password thread (in the queue kind_of(S&) names), then
  /// finish(DbServices&, S&, W&) -> R back on the DB thread, delivered. Defined in
  /// db_worker.cpp, the only place that uses it.
  template <class R, class Kind, class Begin, class Work, class Finish>
  void in_three_steps(Kind kind_of, detail::Delivery<R> deliver, Begin begin, Work work,
                      Finish finish);
  bool enqueue(Task task);
  bool enqueue_cpu(PasswordWork kind, CpuTask task);
  /// True when a NewHash task would be refused now (max_queued_hashes waiting).
  bool hash_queue_full() const;
  void run();
  void run_cpu();

  std::unique_ptr<Store> store_;
  Accounts accounts_;
  Matches matches_;
  Placement placement_;
  DbServices services_;
  std::size_t max_queued_;
  std::size_t max_queued_hashes_;
  int password_nice_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<Task> queue_;
  bool stopping_ = false;
  std::size_t completed_ = 0;
  std::thread thread_;
  std::condition_variable cpu_wake_;
  std::deque<CpuTask> login_checks_;  ///< guarded by mutex_; taken before new_hashes_
  std::deque<CpuTask> new_hashes_;    ///< guarded by mutex_
  std::vector<std::thread> cpu_threads_;
};

template <class Job, class Done>
void DbWorker::submit(Job job, Post post, Done done) {
  using R = std::invoke_result_t<Job&, DbServices&>;
  const detail::Delivery<R> deliver(std::move(post), std::move(done));
  Task task = [job = std::move(job), deliver](DbServices* services) mutable {
    if (!services) return deliver.stopped();
    deliver(job(*services));
  };
  if (!enqueue(std::move(task))) deliver.queue_full();
}

}  // namespace ricochet::db
