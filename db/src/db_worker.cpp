/// The DB thread (db_worker.h).

#include "ricochet/db/db_worker.h"

namespace ricochet::db {

DbWorker::DbWorker(std::unique_ptr<Store> store, DbWorkerOptions options)
    : store_(std::move(store)),
      accounts_(*store_, options.accounts),
      max_queued_(options.max_queued),
      thread_([this] { run(); }) {}

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
  {
    std::lock_guard lock(mutex_);
    if (stopping_ && !thread_.joinable()) return;
    stopping_ = true;
    abandoned.swap(queue_);
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
  for (Task& task : abandoned) task(nullptr);
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
