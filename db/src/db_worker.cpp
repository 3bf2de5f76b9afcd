/// The DB thread (db_worker.h).

#include "ricochet/db/db_worker.h"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <variant>

namespace ricochet::db {

DbWorker::DbWorker(std::unique_ptr<Store> store, DbWorkerOptions options)
    : store_(std::move(store)),
      accounts_(*store_, options.accounts),
      matches_(*store_, options.matches),
      placement_(*store_, options.placement),
      services_{accounts_, matches_, placement_},
      max_queued_(options.max_queued),
      max_queued_hashes_(options.max_queued_hashes),
      password_nice_(std::clamp(options.password_nice, 0, 19)),
      thread_([this] { run(); }) {
  for (int i = 0; i < std::max(1, options.password_threads); ++i)
    cpu_threads_.emplace_back([this] { run_cpu(); });
}

DbWorker::~DbWorker() {
  stop();
}

template <class T, class Stopped>
bool DbWorker::push(std::deque<T>& queue, std::size_t cap, std::condition_variable& wake, T task,
                    Stopped stopped) {
  std::unique_lock lock(mutex_);
  if (stopping_) {
    lock.unlock();  // never call back into the caller while holding the queues
    stopped(task);
    return true;
  }
  if (queue.size() >= cap) return false;
  queue.push_back(std::move(task));
  lock.unlock();
  wake.notify_one();
  return true;
}

bool DbWorker::pop(Task& task) {
  std::unique_lock lock(mutex_);
  wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
  if (stopping_) return false;
  task = std::move(queue_.front());
  queue_.pop_front();
  return true;
}

bool DbWorker::pop_cpu(CpuTask& task) {
  std::unique_lock lock(mutex_);
  cpu_wake_.wait(lock, [&] { return stopping_ || !login_checks_.empty() || !new_hashes_.empty(); });
  if (stopping_) return false;
  std::deque<CpuTask>& queue = login_checks_.empty() ? new_hashes_ : login_checks_;
  task = std::move(queue.front());
  queue.pop_front();
  return true;
}

bool DbWorker::enqueue(Task task) {
  return push(queue_, max_queued_, wake_, std::move(task), [](Task& t) { t(nullptr); });
}

bool DbWorker::enqueue_cpu(PasswordWork kind, CpuTask task) {
  const bool login = kind == PasswordWork::LoginCheck;
  return push(login ? login_checks_ : new_hashes_, login ? max_queued_ : max_queued_hashes_,
              cpu_wake_, std::move(task), [](CpuTask& t) { t(true); });
}

bool DbWorker::hash_queue_full() const {
  std::lock_guard lock(mutex_);
  return new_hashes_.size() >= max_queued_hashes_;
}

void DbWorker::run() {
  Task task;
  while (pop(task)) {
    task(&services_);
    std::lock_guard lock(mutex_);
    ++completed_;
  }
}

void DbWorker::run_cpu() {
  // Linux gives each thread its own nice value; where it cannot be lowered the hashes still
  // run, at the normal priority.
  if (password_nice_ > 0)
    (void)setpriority(PRIO_PROCESS, static_cast<id_t>(gettid()), password_nice_);
  CpuTask task;
  while (pop_cpu(task)) task(false);
}

namespace {

/// What the first step of a job hands to the second: a DbResult's value, or nothing.
template <class T>
T state_of(DbResult<T>&& started) {
  return std::move(started).value();
}
std::monostate state_of(DbStatus&&) {
  return {};
}

}  // namespace

template <class R, class Kind, class Begin, class Work, class Finish>
void DbWorker::in_three_steps(Kind kind_of, detail::Delivery<R> deliver, Begin begin, Work work,
                              Finish finish) {
  Task first = [this, kind_of, deliver, begin = std::move(begin), work = std::move(work),
                finish = std::move(finish)](DbServices* db) mutable {
    if (!db) return deliver.stopped();
    auto started = begin(*db);
    if (!started.ok()) return deliver(started.error());
    auto state =
        std::make_shared<decltype(state_of(std::move(started)))>(state_of(std::move(started)));
    CpuTask second = [this, deliver, state, work = std::move(work),
                      finish = std::move(finish)](bool stopped) mutable {
      if (stopped) return deliver.stopped();
      auto worked = std::make_shared<decltype(work(*state))>(work(*state));
      Task third = [deliver, state, worked, finish = std::move(finish)](DbServices* db) mutable {
        if (!db) return deliver.stopped();
        deliver(finish(*db, *state, *worked));
      };
      if (!enqueue(std::move(third))) deliver.queue_full();
    };
    const PasswordWork kind = kind_of(*state);
    if (!enqueue_cpu(kind, std::move(second))) deliver.queue_full();
  };
  if (!enqueue(std::move(first))) deliver.queue_full();
}

void DbWorker::login(std::string username, std::string password, std::string address,
                     UnixMillis now, Post post, std::function<void(DbResult<LoginResult>)> done) {
  const std::size_t password_bytes = password.size();
  in_three_steps(
      // An existing account's login goes first; an unknown name waits with the registrations
      // (what that tells about a name, registering it tells anyway).
      [](const Accounts::LoginAttempt& attempt) {
        return attempt.found ? PasswordWork::LoginCheck : PasswordWork::NewHash;
      },
      detail::Delivery<DbResult<LoginResult>>(std::move(post), std::move(done)),
      [username = std::move(username), password_bytes, address = std::move(address),
       now](DbServices& db) {
        return db.accounts.begin_login(username, password_bytes, address, now);
      },
      [accounts = &accounts_, password = std::move(password)](Accounts::LoginAttempt& attempt) {
        return accounts->check_password(attempt, password);
      },
      [now](DbServices& db, Accounts::LoginAttempt& attempt, Accounts::PasswordCheck& check) {
        return db.accounts.finish_login(attempt, check, now);
      });
}

void DbWorker::register_account(std::string username, std::string password, std::string address,
                                UnixMillis now, Post post,
                                std::function<void(DbResult<AccountId>)> done) {
  auto name = std::make_shared<const std::string>(std::move(username));
  auto secret = std::make_shared<const std::string>(std::move(password));
  in_three_steps([](const std::monostate&) { return PasswordWork::NewHash; },
                 detail::Delivery<DbResult<AccountId>>(std::move(post), std::move(done)),
                 [this, name, secret, address = std::move(address), now](DbServices& db) {
                   // Refused before the address's limit notes it: SERVER_BUSY is not a
                   // registration (only this thread queues hashes, so the room stays).
                   if (hash_queue_full()) {
                     return DbStatus(DbError{DbErrorCode::QueueFull,
                                             "the password hashing queue is full; retry later"});
                   }
                   return db.accounts.check_registration(*name, *secret, address, now);
                 },
                 [accounts = &accounts_, secret](std::monostate&) {
                   return accounts->hash_new_password(*secret);
                 },
                 [name, now](DbServices& db, std::monostate&, DbResult<std::string>& hash) {
                   return db.accounts.finish_registration(*name, hash, now);
                 });
}

void DbWorker::change_password(AccountId id, std::string old_password, std::string new_password,
                               Post post, std::function<void(DbStatus)> done) {
  auto new_secret = std::make_shared<const std::string>(std::move(new_password));
  in_three_steps([](const Accounts::PasswordChange&) { return PasswordWork::NewHash; },
                 detail::Delivery<DbStatus>(std::move(post), std::move(done)),
                 [id, new_secret](DbServices& db) {
                   return db.accounts.begin_password_change(id, *new_secret);
                 },
                 [accounts = &accounts_, old_secret = std::move(old_password),
                  new_secret](Accounts::PasswordChange& change) {
                   return accounts->hash_password_change(change, old_secret, *new_secret);
                 },
                 [](DbServices& db, Accounts::PasswordChange& change, DbResult<std::string>& hash) {
                   return db.accounts.finish_password_change(change, hash);
                 });
}

void DbWorker::stop() {
  std::deque<Task> abandoned;
  std::deque<CpuTask> abandoned_cpu;
  std::deque<CpuTask> abandoned_hashes;
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && !thread_.joinable()) return;
    stopping_ = true;
    abandoned.swap(queue_);
    abandoned_cpu.swap(login_checks_);
    abandoned_hashes.swap(new_hashes_);
  }
  wake_.notify_all();
  cpu_wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  for (std::thread& t : cpu_threads_) {
    if (t.joinable()) t.join();
  }
  for (Task& task : abandoned) task(nullptr);
  for (CpuTask& task : abandoned_cpu) task(true);
  for (CpuTask& task : abandoned_hashes) task(true);
}

std::size_t DbWorker::queued() const {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

std::size_t DbWorker::completed() const {
  std::lock_guard lock(mutex_);
  return completed_;
}

}  // namespace ricochet::db
