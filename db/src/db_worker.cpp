/// The DB thread (db_worker.h).

#include "ricochet/db/db_worker.h"

#include <algorithm>

namespace ricochet::db {

DbWorker::DbWorker(std::unique_ptr<Store> store, DbWorkerOptions options)
    : store_(std::move(store)),
      accounts_(*store_, options.accounts),
      matches_(*store_, options.matches),
      services_{accounts_, matches_},
      max_queued_(options.max_queued),
      thread_([this] { run(); }) {
  for (int i = 0; i < std::max(1, options.password_threads); ++i)
    cpu_threads_.emplace_back([this] { run_cpu(); });
}

DbWorker::~DbWorker() {
  stop();
}

template <class T, class Stopped>
bool DbWorker::push(std::deque<T>& queue, std::condition_variable& wake, T task, Stopped stopped) {
  std::unique_lock lock(mutex_);
  if (stopping_) {
    lock.unlock();  // never call back into the caller while holding the queues
    stopped(task);
    return true;
  }
  if (queue.size() >= max_queued_) return false;
  queue.push_back(std::move(task));
  lock.unlock();
  wake.notify_one();
  return true;
}

template <class T>
bool DbWorker::pop(std::deque<T>& queue, std::condition_variable& wake, T& task) {
  std::unique_lock lock(mutex_);
  wake.wait(lock, [&] { return stopping_ || !queue.empty(); });
  if (stopping_) return false;
  task = std::move(queue.front());
  queue.pop_front();
  return true;
}

bool DbWorker::enqueue(Task task) {
  return push(queue_, wake_, std::move(task), [](Task& t) { t(nullptr); });
}

bool DbWorker::enqueue_cpu(CpuTask task) {
  return push(cpu_queue_, cpu_wake_, std::move(task), [](CpuTask& t) { t(true); });
}

void DbWorker::run() {
  Task task;
  while (pop(queue_, wake_, task)) {
    task(&services_);
    std::lock_guard lock(mutex_);
    ++completed_;
  }
}

void DbWorker::run_cpu() {
  CpuTask task;
  while (pop(cpu_queue_, cpu_wake_, task)) task(false);
}

void DbWorker::login(std::string username, std::string password, std::string address,
                     UnixMillis now, Post post, std::function<void(DbResult<LoginResult>)> done) {
  const detail::Delivery<DbResult<LoginResult>> deliver(std::move(post), std::move(done));
  Task lookup = [this, username = std::move(username), password = std::move(password),
                 address = std::move(address), now, deliver](DbServices* db) mutable {
    if (!db) return deliver.stopped();
    DbResult<Accounts::LoginAttempt> attempt =
        db->accounts.begin_login(username, password.size(), address, now);
    if (!attempt.ok()) return deliver(attempt.error());
    auto shared = std::make_shared<Accounts::LoginAttempt>(std::move(attempt).value());
    CpuTask check = [this, shared, password = std::move(password), now,
                     deliver](bool stopped) mutable {
      if (stopped) return deliver.stopped();
      const bool ok = Accounts::password_verifies(*shared, password);
      Task finish = [shared, ok, password = std::move(password), now, deliver](DbServices* db) {
        if (!db) return deliver.stopped();
        deliver(db->accounts.finish_login(*shared, ok, password, now));
      };
      if (!enqueue(std::move(finish))) deliver.queue_full();
    };
    if (!enqueue_cpu(std::move(check))) deliver.queue_full();
  };
  if (!enqueue(std::move(lookup))) deliver.queue_full();
}

void DbWorker::register_account(std::string username, std::string password, UnixMillis now,
                                Post post, std::function<void(DbResult<AccountId>)> done) {
  const detail::Delivery<DbResult<AccountId>> deliver(std::move(post), std::move(done));
  Task check = [this, username = std::move(username), password = std::move(password), now,
                deliver](DbServices* db) mutable {
    if (!db) return deliver.stopped();
    Accounts* accounts = &db->accounts;
    if (DbStatus s = accounts->check_registration(username, password); !s.ok())
      return deliver(s.error());
    CpuTask hash = [this, accounts, username = std::move(username), password = std::move(password),
                    now, deliver](bool stopped) mutable {
      if (stopped) return deliver.stopped();
      std::string hashed = accounts->hash_new_password(password);
      Task store = [username = std::move(username), hashed = std::move(hashed), now,
                    deliver](DbServices* db) {
        if (!db) return deliver.stopped();
        deliver(db->accounts.finish_registration(username, hashed, now));
      };
      if (!enqueue(std::move(store))) deliver.queue_full();
    };
    if (!enqueue_cpu(std::move(hash))) deliver.queue_full();
  };
  if (!enqueue(std::move(check))) deliver.queue_full();
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
