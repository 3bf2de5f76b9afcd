#pragma once
/// A real PostgreSQL 15 cluster for tests: initdb + pg_ctl in a temporary directory, listening on
/// 127.0.0.1 at a free port and on a unix socket in that directory, fsync off (a test database
/// need not survive a power cut). One cluster per test process, started at the first use
/// (shared(), well under a second) and stopped when the process ends; each test makes its own
/// database (create_database()).
///
/// initdb and pg_ctl refuse to run as root: as root (CI) they run as `nobody` through runuser,
/// which then owns the directory; as anyone else, as that user.
///
/// A watchdog process stops the cluster and removes its directory when this process ends, even
/// by a crash or SIGKILL, so no postmaster outlives a test binary.

#include <fcntl.h>
#include <libpq-fe.h>
#include <netinet/in.h>
#include <pwd.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace ricochet::test {

class PostgresCluster {
 public:
  /// The cluster of this process, started at the first call (throws with initdb's or the
  /// server's log when it cannot start). Thread-safe.
  static PostgresCluster& shared() {
    static PostgresCluster cluster;
    return cluster;
  }

  /// A new, empty database; returns its URL (postgresql://ricochet@127.0.0.1:PORT/NAME).
  std::string create_database() {
    std::lock_guard lock(mutex_);
    const std::string name = "t" + std::to_string(getpid()) + "_" + std::to_string(++databases_);
    admin("CREATE DATABASE " + name);
    return url(name);
  }
  /// The URL of database `name` of this cluster.
  std::string url(const std::string& name) const {
    return "postgresql://ricochet@127.0.0.1:" + std::to_string(port_) + "/" + name;
  }
  int port() const { return port_; }
  /// Runs `sql` as the cluster's superuser on the `postgres` database (roles, pg_stat_activity);
  /// throws with PostgreSQL's message when it fails.
  void execute(const std::string& sql) {
    std::lock_guard lock(mutex_);
    admin(sql);
  }

  /// Stops the server (fast shutdown: connections are cut) and starts it again on the same port,
  /// for tests of a database that goes away.
  void stop() { pg_ctl({"stop", "-m", "fast"}); }
  void start() { pg_ctl({"start", "-o", server_options()}); }

  PostgresCluster(const PostgresCluster&) = delete;
  PostgresCluster& operator=(const PostgresCluster&) = delete;

 private:
  static constexpr const char* kBinDir = "/usr/lib/postgresql/15/bin";

  PostgresCluster() {
    if (!std::filesystem::exists(std::string(kBinDir) + "/initdb"))
      throw std::runtime_error(std::string(kBinDir) +
                               "/initdb is missing: install postgresql-15 (tools/deps.sh)");
    char pattern[] = "/tmp/ricochet-pg-XXXXXX";
    if (!mkdtemp(pattern)) throw std::runtime_error("mkdtemp failed for /tmp/ricochet-pg-*");
    dir_ = pattern;
    if (geteuid() == 0) {
      const passwd* nobody = getpwnam("nobody");
      if (!nobody || chown(dir_.c_str(), nobody->pw_uid, nobody->pw_gid) != 0)
        throw std::runtime_error("cannot give " + dir_ + " to the user nobody");
      as_user_ = {"runuser", "-u", "nobody", "--"};
    }
    start_watchdog();
    run({std::string(kBinDir) + "/initdb", "-D", data_dir(), "-U", "ricochet", "--auth=trust",
         "--no-locale", "--encoding=UTF8", "--no-sync"},
        dir_ + "/initdb.log");
    // A port the kernel says is free now; a clash with another process in between is retried.
    for (int attempt = 1;; ++attempt) {
      port_ = free_port();
      try {
        start();
        break;
      } catch (const std::runtime_error&) {
        if (attempt == 3) throw;
      }
    }
    admin_.reset(PQconnectdb(url("postgres").c_str()));
    if (PQstatus(admin_.get()) != CONNECTION_OK)
      throw std::runtime_error("cannot connect to the test cluster: " +
                               std::string(PQerrorMessage(admin_.get())));
  }

  /// Closing the pipe wakes the watchdog, which stops the server and removes the directory.
  ~PostgresCluster() {
    admin_.reset();
    close(watchdog_pipe_);
    int status = 0;
    waitpid(watchdog_pid_, &status, 0);
  }

  std::string data_dir() const { return dir_ + "/data"; }
  std::string server_options() const {
    return "-c listen_addresses=127.0.0.1 -p " + std::to_string(port_) + " -k " + dir_ +
           " -c fsync=off -c synchronous_commit=off -c full_page_writes=off";
  }

  void pg_ctl(std::vector<std::string> args) {
    std::vector<std::string> argv = {std::string(kBinDir) + "/pg_ctl",
                                     "-D",
                                     data_dir(),
                                     "-w",
                                     "-t",
                                     "30",
                                     "-l",
                                     dir_ + "/server.log"};
    argv.insert(argv.end(), args.begin(), args.end());
    run(argv, dir_ + "/pg_ctl.log");
  }

  /// Runs a command as the cluster's user, its output to `log`; throws with the log (and the
  /// server's) when it fails.
  void run(const std::vector<std::string>& command, const std::string& log) {
    std::vector<std::string> full = as_user_;
    full.insert(full.end(), command.begin(), command.end());
    std::vector<char*> argv;
    for (std::string& arg : full) argv.push_back(arg.data());
    argv.push_back(nullptr);
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error("fork failed");
    if (pid == 0) {
      const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0666);
      if (fd >= 0) {
        dup2(fd, 1);
        dup2(fd, 2);
      }
      execvp(argv[0], argv.data());
      _exit(127);
    }
    int status = 0;
    waitpid(pid, &status, 0);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
    std::string message = "test cluster: " + full[as_user_.size()] + " failed:\n" + read_file(log) +
                          "\nserver log:\n" + read_file(dir_ + "/server.log");
    throw std::runtime_error(message);
  }

  /// Runs an SQL command on the `postgres` database. A connection that stop()/start() cut only
  /// shows it at its next command (PQstatus still says CONNECTION_OK before): then it is reset
  /// and the command runs once more.
  void admin(const std::string& sql) {
    if (PQstatus(admin_.get()) != CONNECTION_OK) PQreset(admin_.get());
    PGresult* r = PQexec(admin_.get(), sql.c_str());
    if (PQresultStatus(r) != PGRES_COMMAND_OK && PQstatus(admin_.get()) != CONNECTION_OK) {
      PQclear(r);
      PQreset(admin_.get());
      r = PQexec(admin_.get(), sql.c_str());
    }
    const bool ok = PQresultStatus(r) == PGRES_COMMAND_OK || PQresultStatus(r) == PGRES_TUPLES_OK;
    const std::string error = PQresultErrorMessage(r);
    PQclear(r);
    if (!ok) throw std::runtime_error("test cluster: " + sql + ": " + error);
  }

  /// A child that waits for this process to end (the pipe's EOF), then stops the server at once
  /// and removes the directory. Everything it runs is prepared before the fork.
  void start_watchdog() {
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0) throw std::runtime_error("pipe2 failed");
    std::string as_user;
    for (const std::string& word : as_user_) as_user += word + " ";
    const std::string script =
        as_user + kBinDir + "/pg_ctl -D " + data_dir() + " -m immediate stop; rm -rf " + dir_;
    const int null_fd = open("/dev/null", O_RDWR | O_CLOEXEC);
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error("fork failed");
    if (pid == 0) {
      close(fds[1]);
      char byte;
      while (read(fds[0], &byte, 1) != 0) {
      }
      dup2(null_fd, 0);
      dup2(null_fd, 1);
      dup2(null_fd, 2);
      execl("/bin/sh", "sh", "-c", script.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    close(fds[0]);
    close(null_fd);
    watchdog_pipe_ = fds[1];
    watchdog_pid_ = pid;
  }

  static int free_port() {
    const int fd = socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
        getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) != 0)
      throw std::runtime_error("cannot find a free port on 127.0.0.1");
    close(fd);
    return ntohs(address.sin_port);
  }

  static std::string read_file(const std::string& path) {
    std::ifstream in(path);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }

  struct Finish {
    void operator()(PGconn* conn) const { PQfinish(conn); }
  };

  std::mutex mutex_;
  std::string dir_;
  std::vector<std::string> as_user_;  ///< runuser -u nobody -- when root
  int port_ = 0;
  int databases_ = 0;
  int watchdog_pipe_ = -1;
  pid_t watchdog_pid_ = -1;
  std::unique_ptr<PGconn, Finish> admin_;
};

}  // namespace ricochet::test
