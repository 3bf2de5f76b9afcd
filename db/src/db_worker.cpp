/// The DB thread (db_worker.h).

#include "ricochet/db/db_worker.h"

#include <algorithm>

namespace ricochet::db {

DbWorker::DbWorker(std::unique_ptr<Store> store, DbWorkerOptions options)
    : store_(std::move(store)),
      accounts_(*store_, options.accounts),
      max_queued_(options.max_queued),
      thread_([this] { run(); }) {
  for (int i = 0; i < std::max(1, options.password_threads); ++i)
    cpu_threads_.emplace_back([this] { run_cpu(); });
}

DbWorker::~DbWorker() {
  stop();
}

bool DbWorker::enqueue(Task task) {
  std::unique_lock lock(mutex_);
  if (stopping_) {
    lock.unlock();  // never call back into the caller while holding the queue
    task(nullptr);
    return true;
  }
  if (queue_.size() >= max_queued_) return false;
  queue_.push_back(std::move(task));
  lock.unlock();
  wake_.notify_one();
  return true;
}

bool DbWorker::enqueue_cpu(CpuTask task) {
  std::unique_lock lock(mutex_);
  if (stopping_) {
    lock.unlock();
    task(true);
    return true;
  }
  if (cpu_queue_.size() >= max_queued_) return false;
  cpu_queue_.push_back(std::move(task));
  lock.unlock();
  cpu_wake_.notify_one();
  return true;
}

void DbWorker::run_cpu() {
  for (;;) {
    CpuTask task;
    {
      std::unique_lock lock(mutex_);
      cpu_wake_.wait(lock, [&] { return stopping_ || !cpu_queue_.empty(); });
      if (stopping_) return;
      task = std::move(cpu_queue_.front());
      cpu_queue_.pop_front();
    }
    task(false);
  }
}

void DbWorker::login(std::string username, std::string password, std::string address,
                     UnixMillis now, Post post, std::function<void(DbResult<LoginResult>)> done) {
  using R = DbResult<LoginResult>;
  auto deliver = [post = std::make_shared<Post>(std::move(post)),
                  done = std::make_shared<std::function<void(R)>>(std::move(done))](R result) {
    (*post)([done, result = std::move(result)]() mutable { (*done)(std::move(result)); });
  };
  const auto stopped = [] { return R(DbError{DbErrorCode::Stopped, "the DB worker stopped"}); };
  const auto full = [] {
    return R(DbError{DbErrorCode::Busy, "the DB queue is full; retry later"});
  };
  Task lookup = [this, username = std::move(username), password = std::move(password),
                 address = std::move(address), now, deliver, stopped,
                 full](Accounts* accounts) mutable {
    if (!accounts) return deliver(stopped());
    DbResult<Accounts::LoginAttempt> attempt =
        accounts->begin_login(username, password.size(), address, now);
    if (!attempt.ok()) return deliver(attempt.error());
    auto shared = std::make_shared<Accounts::LoginAttempt>(std::move(attempt).value());
    CpuTask check = [this, shared, password = std::move(password), now, deliver, stopped,
                     full](bool is_stopped) mutable {
      if (is_stopped) return deliver(stopped());
      const bool ok = Accounts::password_verifies(*shared, password);
      Task finish = [shared, ok, password = std::move(password), now, deliver,
                     stopped](Accounts* accounts) {
        if (!accounts) return deliver(stopped());
        deliver(accounts->finish_login(*shared, ok, password, now));
      };
      if (!enqueue(std::move(finish))) deliver(full());
    };
    if (!enqueue_cpu(std::move(check))) deliver(full());
  };
  if (!enqueue(std::move(lookup))) deliver(full());
}

void DbWorker::register_account(std::string username, std::string password, UnixMillis now,
                                Post post, std::function<void(DbResult<AccountId>)> done) {
  using R = DbResult<AccountId>;
  auto deliver = [post = std::make_shared<Post>(std::move(post)),
                  done = std::make_shared<std::function<void(R)>>(std::move(done))](R result) {
    (*post)([done, result = std::move(result)]() mutable { (*done)(std::move(result)); });
  };
  const auto stopped = [] { return R(DbError{DbErrorCode::Stopped, "the DB worker stopped"}); };
  const auto full = [] {
    return R(DbError{DbErrorCode::Busy, "the DB queue is full; retry later"});
  };
  Task check = [this, username = std::move(username), password = std::move(password), now, deliver,
                stopped, full](Accounts* accounts) mutable {
    if (!accounts) return deliver(stopped());
    if (DbStatus s = accounts->check_registration(username, password); !s.ok())
      return deliver(s.error());
    CpuTask hash = [this, accounts, username = std::move(username), password = std::move(password),
                    now, deliver, stopped, full](bool is_stopped) mutable {
      if (is_stopped) return deliver(stopped());
      std::string hashed = accounts->hash_new_password(password);
      Task store = [username = std::move(username), hashed = std::move(hashed), now, deliver,
                    stopped](Accounts* accounts) {
        if (!accounts) return deliver(stopped());
        deliver(accounts->finish_registration(username, hashed, now));
      };
      if (!enqueue(std::move(store))) deliver(full());
    };
    if (!enqueue_cpu(std::move(hash))) deliver(full());
  };
  if (!enqueue(std::move(check))) deliver(full());
}

void DbWorker::run() {
  for (;;) {
    Task task;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
      if (stopping_) return;
      task = std::move(queue_.front());
      queue_.pop_front();
    }
    task(&accounts_);
    std::lock_guard lock(mutex_);
    ++completed_;
  }
}

void DbWorker::stop() {
  std::deque<Task> abandoned;
  std::deque<CpuTask> abandoned_cpu;
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && !thread_.joinable()) return;
    stopping_ = true;
    abandoned.swap(queue_);
    abandoned_cpu.swap(cpu_queue_);
  }
  wake_.notify_all();
  cpu_wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  for (std::thread& t : cpu_threads_) {
    if (t.joinable()) t.join();
  }
  for (Task& task : abandoned) task(nullptr);
  for (CpuTask& task : abandoned_cpu) task(true);
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
