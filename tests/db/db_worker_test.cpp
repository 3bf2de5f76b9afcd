// The DB thread: jobs run off the caller's thread, results come back through the caller's post,
// in order; a locked database delays results but never blocks the caller; a full queue and a
// stopped worker answer at once; the password threads serve existing accounts' logins first, at
// a lower priority.

#include "ricochet/db/db_worker.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <iterator>
#include <sstream>

#include "db_test_util.h"
#include "test_database.h"

namespace ricochet::db::test::db_worker_test {
namespace {

using namespace std::chrono_literals;
constexpr UnixMillis kT0 = 1'700'000'000'000;

/// The caller's executor: completions queue here and run when the caller drains them.
class CallerQueue {
 public:
  Post post() {
    return [this](std::function<void()> completion) {
      std::lock_guard lock(mutex_);
      pending_.push_back(std::move(completion));
    };
  }
  /// Runs what has arrived; returns how many ran.
  int drain() {
    std::deque<std::function<void()>> ready;
    {
      std::lock_guard lock(mutex_);
      ready.swap(pending_);
    }
    for (auto& f : ready) f();
    return static_cast<int>(ready.size());
  }
  /// Drains until `done()` or the deadline; the caller keeps "ticking" meanwhile.
  bool drain_until(const std::function<bool()>& done, std::chrono::milliseconds limit = 10s) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (!done()) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      drain();
      std::this_thread::sleep_for(1ms);
    }
    return true;
  }

 private:
  std::mutex mutex_;
  std::deque<std::function<void()>> pending_;
};

/// A job that holds the DB thread until released, so later jobs wait in the queue.
class BlockingJob {
 public:
  /// Submits the job and returns once the DB thread is inside it.
  template <class Done>
  void submit(DbWorker& worker, Post post, Done done) {
    std::shared_future<void> released = release_.get_future().share();
    worker.submit(
        [this, released](DbServices&) {
          running_ = true;
          released.wait();
          return DbStatus();
        },
        std::move(post), std::move(done));
    while (!running_) std::this_thread::sleep_for(1ms);
  }
  void release() { release_.set_value(); }

 private:
  std::promise<void> release_;
  std::atomic<bool> running_{false};
};

DbWorkerOptions fast_options() {
  DbWorkerOptions o;
  o.accounts.cost = PasswordCost::Minimum;
  return o;
}

/// Each test on a fresh database of either backend (test_database.h).
class DbWorkerTest : public ::testing::TestWithParam<Backend> {
 protected:
  std::unique_ptr<Store> open_store(int busy_timeout_ms = 5000) {
    return db_.open(busy_timeout_ms);
  }
  TestDatabase db_{GetParam()};
};

TEST_P(DbWorkerTest, JobsRunOnTheDbThreadAndCompleteOnTheCallers) {
  DbWorker worker(open_store(), fast_options());
  CallerQueue caller;
  const auto caller_thread = std::this_thread::get_id();
  std::thread::id job_thread;
  std::optional<DbResult<AccountId>> result;
  std::thread::id completion_thread;
  worker.submit(
      [&](DbServices& db) {
        job_thread = std::this_thread::get_id();
        return db.accounts.register_account("alice", "correct horse", "", kT0);
      },
      caller.post(),
      [&](DbResult<AccountId> r) {
        completion_thread = std::this_thread::get_id();
        result = std::move(r);
      });
  ASSERT_TRUE(caller.drain_until([&] { return result.has_value(); }));
  ASSERT_TRUE(result->ok()) << describe(result->error());
  EXPECT_NE(job_thread, caller_thread);
  EXPECT_EQ(completion_thread, caller_thread);
}

TEST_P(DbWorkerTest, CompletionsArriveInSubmissionOrder) {
  DbWorker worker(open_store(), fast_options());
  CallerQueue caller;
  std::vector<int> order;
  for (int i = 0; i < 50; ++i) {
    worker.submit(
        [i](DbServices& db) {
          return db.accounts.register_account("user" + std::to_string(i), "correct horse", "", kT0);
        },
        caller.post(),
        [&order, i](DbResult<AccountId> r) {
          EXPECT_TRUE(r.ok());
          order.push_back(i);
        });
  }
  ASSERT_TRUE(caller.drain_until([&] { return order.size() == 50; }));
  for (int i = 0; i < 50; ++i) EXPECT_EQ(order[i], i);
  EXPECT_EQ(worker.completed(), 50u);
}

TEST_P(DbWorkerTest, ALockedDatabaseIsLatencyNotABlockedCaller) {
  DbWorker worker(open_store(10'000), fast_options());
  TestDatabase::WriteLock other(db_);  // another process holds the write lock

  CallerQueue caller;
  std::optional<DbResult<AccountId>> result;
  std::atomic<bool> started{false};
  const auto before = std::chrono::steady_clock::now();
  worker.submit(
      [&started](DbServices& db) {
        started = true;
        // From an address: its registration limit is checked in a transaction (Store::
        // transaction), which waits for the write lock on either backend.
        return db.accounts.register_account("bob", "correct horse", "198.51.100.1", kT0);
      },
      caller.post(), [&](DbResult<AccountId> r) { result = std::move(r); });
  const auto submit_took = std::chrono::steady_clock::now() - before;
  // The DB thread is inside the job, waiting for the lock (up to 10 s)...
  ASSERT_TRUE(caller.drain_until([&] { return started.load(); }));
  std::this_thread::sleep_for(50ms);
  caller.drain();
  EXPECT_FALSE(result.has_value()) << "the write finished while another connection held the lock";
  // ...and submit() came back long before: the caller never waits for the database.
  EXPECT_LT(submit_took, 1s);
  other.release();
  ASSERT_TRUE(caller.drain_until([&] { return result.has_value(); }));
  EXPECT_TRUE(result->ok()) << describe(result->error());
}

TEST_P(DbWorkerTest, ALockHeldPastTheBusyTimeoutIsBusy) {
  DbWorker worker(open_store(100), fast_options());
  TestDatabase::WriteLock other(db_);
  CallerQueue caller;
  std::optional<DbResult<AccountId>> result;
  worker.submit(
      [](DbServices& db) {
        return db.accounts.register_account("carol", "correct horse", "198.51.100.1", kT0);
      },
      caller.post(), [&](DbResult<AccountId> r) { result = std::move(r); });
  ASSERT_TRUE(caller.drain_until([&] { return result.has_value(); }));
  EXPECT_TRUE(fails_with(*result, DbErrorCode::Busy));
}

TEST_P(DbWorkerTest, AFullQueueAnswersQueueFullAtOnce) {
  DbWorkerOptions options = fast_options();
  options.max_queued = 1;
  DbWorker worker(open_store(), options);
  CallerQueue caller;
  std::vector<DbErrorCode> codes;
  std::vector<bool> oks;
  const auto record = [&](DbStatus s) {
    oks.push_back(s.ok());
    if (!s.ok()) codes.push_back(s.error().code);
  };
  // Job 1 holds the DB thread; job 2 waits in the queue; job 3 finds the queue full.
  BlockingJob blocking;
  blocking.submit(worker, caller.post(), record);
  worker.submit([](DbServices&) { return DbStatus(); }, caller.post(), record);
  EXPECT_EQ(worker.queued(), 1u);
  worker.submit([](DbServices&) { return DbStatus(); }, caller.post(), record);
  EXPECT_EQ(worker.queued(), 1u);
  EXPECT_EQ(caller.drain(), 1);  // the refusal is already there
  ASSERT_EQ(codes.size(), 1u);
  EXPECT_EQ(codes[0], DbErrorCode::QueueFull);
  blocking.release();
  ASSERT_TRUE(caller.drain_until([&] { return oks.size() == 3; }));
  EXPECT_EQ(std::count(oks.begin(), oks.end(), true), 2);
}

TEST_P(DbWorkerTest, StopCompletesQueuedJobsWithStopped) {
  auto worker = std::make_unique<DbWorker>(open_store(), fast_options());
  CallerQueue caller;
  std::vector<DbStatus> results;
  const auto record = [&](DbStatus s) { results.push_back(std::move(s)); };
  BlockingJob blocking;
  blocking.submit(*worker, caller.post(), record);
  for (int i = 0; i < 3; ++i)
    worker->submit([](DbServices&) { return DbStatus(); }, caller.post(), record);
  ASSERT_EQ(worker->queued(), 3u);
  std::thread stopper([&] { worker->stop(); });
  // stop() takes the queued jobs away before it waits for the running one to finish.
  while (worker->queued() != 0) std::this_thread::sleep_for(1ms);
  blocking.release();
  stopper.join();
  worker->submit([](DbServices&) { return DbStatus(); }, caller.post(), record);
  caller.drain();
  ASSERT_EQ(results.size(), 5u);
  EXPECT_TRUE(results[0].ok());  // the running job finished
  for (std::size_t i = 1; i < results.size(); ++i)
    EXPECT_TRUE(fails_with(results[i], DbErrorCode::Stopped));
  worker.reset();  // a second stop in the destructor is harmless
}

TEST_P(DbWorkerTest, RegisterAndLoginHashOnThePasswordThread) {
  DbWorker worker(open_store(), fast_options());
  CallerQueue caller;
  std::optional<DbResult<AccountId>> registered;
  worker.register_account("alice", "correct horse", "", kT0, caller.post(),
                          [&](DbResult<AccountId> r) { registered = std::move(r); });
  ASSERT_TRUE(caller.drain_until([&] { return registered.has_value(); }));
  ASSERT_TRUE(registered->ok()) << describe(registered->error());
  std::optional<DbResult<LoginResult>> login, wrong, invalid;
  worker.login("Alice", "correct horse", "10.0.0.1", kT0 + 1, caller.post(),
               [&](DbResult<LoginResult> r) { login = std::move(r); });
  worker.login("alice", "wrong horse", "10.0.0.1", kT0 + 2, caller.post(),
               [&](DbResult<LoginResult> r) { wrong = std::move(r); });
  std::optional<DbResult<AccountId>> bad_name;
  worker.register_account("a!", "correct horse", "", kT0, caller.post(),
                          [&](DbResult<AccountId> r) { bad_name = std::move(r); });
  ASSERT_TRUE(caller.drain_until([&] { return login && wrong && bad_name; }));
  ASSERT_TRUE(login->ok()) << describe(login->error());
  EXPECT_EQ(login->value().account, registered->value());
  EXPECT_TRUE(fails_with(*wrong, DbErrorCode::WrongCredentials));
  EXPECT_TRUE(fails_with(*bad_name, DbErrorCode::InvalidUsername));
  // The session is in the store the DB thread uses.
  std::optional<DbResult<SessionInfo>> session;
  worker.submit([token = login->value().token](
                    DbServices& db) { return db.accounts.check_session(token, kT0 + 3); },
                caller.post(), [&](DbResult<SessionInfo> r) { session = std::move(r); });
  ASSERT_TRUE(caller.drain_until([&] { return session.has_value(); }));
  EXPECT_TRUE(session->ok());
}

/// Registers `name` with "correct horse" through the worker (hashing on a password thread).
AccountId register_through(DbWorker& worker, CallerQueue& caller, const std::string& name) {
  std::optional<DbResult<AccountId>> registered;
  worker.register_account(name, "correct horse", "", kT0, caller.post(),
                          [&](DbResult<AccountId> r) { registered = std::move(r); });
  if (!caller.drain_until([&] { return registered.has_value(); }, 60s))
    throw std::runtime_error("registering " + name + " took over 60 s");
  return must(std::move(*registered), "register_account");
}

/// Submits a stats read that notes "stats" in `order` when it completes.
void submit_stats_read(DbWorker& worker, CallerQueue& caller, std::vector<std::string>& order) {
  worker.submit([](DbServices& db) { return db.matches.player_stats(1); }, caller.post(),
                [&order](DbResult<PlayerStats> r) {
                  EXPECT_TRUE(r.ok());
                  order.push_back("stats");
                });
}

TEST_P(DbWorkerTest, ALoginBurstDoesNotHoldUpOtherDatabaseWork) {
  DbWorkerOptions options;  // Argon2id at the interactive cost: ~0.1 s per check
  DbWorker worker(open_store(), options);
  CallerQueue caller;
  register_through(worker, caller, "bob");
  std::vector<std::string> order;
  for (int i = 0; i < 3; ++i) {
    worker.login("bob", "correct horse", "", kT0 + i, caller.post(),
                 [&order](DbResult<LoginResult> r) {
                   EXPECT_TRUE(r.ok());
                   order.push_back("login");
                 });
  }
  submit_stats_read(worker, caller, order);
  ASSERT_TRUE(caller.drain_until([&] { return order.size() == 4; }, 60s));
  // Three Argon2id checks queue on the password thread; the stats read, submitted after them,
  // is answered before any of them (the first takes ~100 ms, the read well under 1 ms).
  EXPECT_EQ(order.front(), "stats");
}

TEST_P(DbWorkerTest, APasswordChangeHashesOnThePasswordThread) {
  DbWorkerOptions options;  // Argon2id at the interactive cost: ~0.1 s per hash
  DbWorker worker(open_store(), options);
  CallerQueue caller;
  const AccountId id = register_through(worker, caller, "dora");
  std::vector<std::string> order;
  std::optional<DbStatus> changed;
  worker.change_password(id, "correct horse", "battery staple", caller.post(), [&](DbStatus s) {
    changed = std::move(s);
    order.push_back("change");
  });
  submit_stats_read(worker, caller, order);
  ASSERT_TRUE(caller.drain_until([&] { return order.size() == 2; }, 60s));
  // The two Argon2id runs (old password, new hash) held a password thread, not the DB thread.
  EXPECT_EQ(order, (std::vector<std::string>{"stats", "change"}));
  RICOCHET_DB_EXPECT_OK(*changed);
  std::optional<DbResult<LoginResult>> login;
  worker.login("dora", "battery staple", "", kT0 + 1, caller.post(),
               [&](DbResult<LoginResult> r) { login = std::move(r); });
  ASSERT_TRUE(caller.drain_until([&] { return login.has_value(); }, 60s));
  EXPECT_TRUE(login->ok()) << describe(login->error());
}

TEST_P(DbWorkerTest, ConcurrentWrongPasswordsCannotSlipPastTheRateLimit) {
  DbWorkerOptions options = fast_options();
  options.accounts.per_account = {3, 60'000};
  DbWorker worker(open_store(), options);
  CallerQueue caller;
  std::optional<DbResult<AccountId>> registered;
  worker.register_account("carol", "correct horse", "", kT0, caller.post(),
                          [&](DbResult<AccountId> r) { registered = std::move(r); });
  ASSERT_TRUE(caller.drain_until([&] { return registered.has_value(); }));
  std::vector<DbErrorCode> codes;
  for (int i = 0; i < 10; ++i) {
    worker.login("carol", "guess " + std::to_string(i), "", kT0 + 1, caller.post(),
                 [&codes](DbResult<LoginResult> r) {
                   codes.push_back(r.ok() ? DbErrorCode::Stopped : r.error().code);
                 });
  }
  ASSERT_TRUE(caller.drain_until([&] { return codes.size() == 10; }));
  EXPECT_EQ(std::count(codes.begin(), codes.end(), DbErrorCode::WrongCredentials), 3);
  EXPECT_EQ(std::count(codes.begin(), codes.end(), DbErrorCode::RateLimited), 7);
}

// Issue 29: registrations queued ahead of a login held it up for as long as they took.
TEST_P(DbWorkerTest, AnExistingAccountsLoginGoesBeforeQueuedRegistrations) {
  DbWorkerOptions options;  // Argon2id at the interactive cost: ~0.1 s per hash, one thread
  DbWorker worker(open_store(), options);
  CallerQueue caller;
  register_through(worker, caller, "owner");
  std::vector<std::string> order;
  constexpr int kRegistrations = 8;
  for (int i = 0; i < kRegistrations; ++i) {
    worker.register_account("new" + std::to_string(i), "correct horse", "", kT0, caller.post(),
                            [&order](DbResult<AccountId> r) {
                              EXPECT_TRUE(r.ok());
                              order.push_back("register");
                            });
  }
  // Each registration's checks run on the DB thread before its hash is queued: once a job
  // submitted after them is done, every hash is queued (or done, on a slow DB thread: under
  // ThreadSanitizer with PostgreSQL the checks took as long as five hashes). The login goes now.
  bool checked = false;
  worker.submit([](DbServices&) { return DbStatus(); }, caller.post(),
                [&checked](DbStatus) { checked = true; });
  ASSERT_TRUE(caller.drain_until([&] { return checked; }, 60s));
  order.push_back("login submitted");
  worker.login("owner", "correct horse", "", kT0, caller.post(), [&order](DbResult<LoginResult> r) {
    EXPECT_TRUE(r.ok());
    order.push_back("login");
  });
  ASSERT_TRUE(caller.drain_until([&] { return order.size() == kRegistrations + 2; }, 60s));
  // It waits for at most the hashes the password thread took before its check was queued (the
  // one running, and one more when the DB thread was slow to look the account up), not for every
  // registration still queued.
  const auto submitted = std::find(order.begin(), order.end(), "login submitted");
  const auto position = std::find(submitted, order.end(), "login") - submitted - 1;
  EXPECT_LE(position, 2) << "the login came after " << position << " of the "
                         << order.end() - submitted - 2
                         << " registrations finishing after it was submitted";
}

// Issue 29: registrations could queue minutes of Argon2id work.
TEST_P(DbWorkerTest, RegistrationsPastTheHashQueueAreRefusedAtOnce) {
  DbWorkerOptions options;  // the interactive cost: the first hash is still running
  options.max_queued_hashes = 2;
  DbWorker worker(open_store(), options);
  CallerQueue caller;
  std::vector<DbErrorCode> codes;
  for (int i = 0; i < 8; ++i) {
    worker.register_account("new" + std::to_string(i), "correct horse", "", kT0, caller.post(),
                            [&codes](DbResult<AccountId> r) {
                              codes.push_back(r.ok() ? DbErrorCode::Stopped : r.error().code);
                            });
  }
  ASSERT_TRUE(caller.drain_until([&] { return codes.size() == 8; }, 60s));
  // One hashing, two waiting; the rest were told at once (the refusals come back first).
  EXPECT_GE(std::count(codes.begin(), codes.end(), DbErrorCode::QueueFull), 4);
  EXPECT_EQ(codes.front(), DbErrorCode::QueueFull);
  EXPECT_GE(std::count(codes.begin(), codes.end(), DbErrorCode::Stopped), 2);  // registered
}

// Issue 29: a registration refused SERVER_BUSY (the hash queue full) took a place in its
// address's hourly limit, so a client retrying it later was refused REGISTRATION_RATE_LIMITED.
TEST_P(DbWorkerTest, ARegistrationRefusedForAFullHashQueueIsNotCountedAgainstItsAddress) {
  DbWorkerOptions options;  // the interactive cost: the first hash is still running
  options.max_queued_hashes = 1;
  options.accounts.registrations_per_address = {3, 3'600'000};
  DbWorker worker(open_store(), options);
  CallerQueue caller;
  std::vector<DbErrorCode> codes;
  const auto record = [&codes](DbResult<AccountId> r) {
    codes.push_back(r.ok() ? DbErrorCode::Stopped : r.error().code);
  };
  for (int i = 0; i < 8; ++i) {
    worker.register_account("burst" + std::to_string(i), "correct horse", "10.0.0.1", kT0,
                            caller.post(), record);
  }
  ASSERT_TRUE(caller.drain_until([&] { return codes.size() == 8; }, 60s));
  const auto registered = std::count(codes.begin(), codes.end(), DbErrorCode::Stopped);
  EXPECT_GE(registered, 1);
  EXPECT_LE(registered, 2);  // one hashing and one waiting, or one more if the first was quick
  EXPECT_EQ(std::count(codes.begin(), codes.end(), DbErrorCode::QueueFull), 8 - registered);
  // Retried later from the same address: only the registrations made count (3 an hour).
  codes.clear();
  for (int i = 0; i < 3 - registered; ++i) {
    worker.register_account("later" + std::to_string(i), "correct horse", "10.0.0.1", kT0 + 1000,
                            caller.post(), record);
    ASSERT_TRUE(
        caller.drain_until([&] { return codes.size() == static_cast<std::size_t>(i + 1); }, 60s));
    EXPECT_EQ(codes.back(), DbErrorCode::Stopped) << to_string(codes.back());
  }
  worker.register_account("over", "correct horse", "10.0.0.1", kT0 + 2000, caller.post(), record);
  ASSERT_TRUE(caller.drain_until(
      [&] { return codes.size() == static_cast<std::size_t>(4 - registered); }, 60s));
  EXPECT_EQ(codes.back(), DbErrorCode::RateLimited);
}

/// The nice values of this process's threads (Linux: field 19 of /proc/self/task/<tid>/stat).
std::vector<int> thread_nice_values() {
  std::vector<int> values;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::ifstream stat(task.path() / "stat");
    std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
    const auto close = text.rfind(')');  // the name may hold spaces; the fields follow it
    if (close == std::string::npos) continue;
    std::istringstream fields(text.substr(close + 2));
    std::string field;
    for (int i = 3; i <= 19 && fields >> field; ++i) {
      if (i == 19) values.push_back(std::stoi(field));
    }
  }
  return values;
}

TEST_P(DbWorkerTest, PasswordThreadsRunAtTheirLowerPriority) {
  DbWorkerOptions options = fast_options();
  options.password_threads = 2;
  options.password_nice = 19;
  const auto lowest = [] {
    const std::vector<int> nice = thread_nice_values();
    return std::count(nice.begin(), nice.end(), 19);
  };
  const auto before = lowest();
  DbWorker worker(open_store(), options);
  CallerQueue caller;
  register_through(worker, caller, "ada");  // a password thread has run
  const auto deadline = std::chrono::steady_clock::now() + 2s;
  while (lowest() < before + 2 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(1ms);
  EXPECT_EQ(lowest(), before + 2);  // the two password threads, not the DB thread
}

INSTANTIATE_TEST_SUITE_P(Backends, DbWorkerTest, kBackends, backend_name);

}  // namespace
}  // namespace ricochet::db::test::db_worker_test
