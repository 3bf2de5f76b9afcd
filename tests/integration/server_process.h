#pragma once
/// The real ricochet-server binary as a child process, for end-to-end tests: a temporary data
/// directory, a configuration on 127.0.0.1 with every port 0 (the kernel picks free ones), its
/// log in a file. The bound ports, the certificate fingerprint and the pid are read from the
/// ports file the server writes once it listens (server.ports_file), and must agree with the
/// start-up lines it logs ("control TLS 1.3 on ADDR:PORT, game UDP on ..." and "fingerprint
/// (pin it in clients): ...").

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>

#include "temp_dir.h"
#include "text_file.h"

namespace ricochet::test {

class ServerProcess {
 public:
  /// `matches_toml`: the body of the [matches] table (maps, seed, limits ...); `more_toml`:
  /// further tables, written after it; `data_dir`: the server's data directory (empty: `data`
  /// in the process's temporary directory); `admin_toml`, `game_toml`: more keys of the [admin]
  /// and [game] tables.
  explicit ServerProcess(const std::string& matches_toml, int shutdown_grace_s = 10,
                         const std::string& more_toml = "", std::filesystem::path data_dir = {},
                         const std::string& admin_toml = "", const std::string& game_toml = "")
      : dir_("ricochet-e2e"),
        matches_toml_(matches_toml),
        more_toml_(more_toml),
        admin_toml_(admin_toml),
        game_toml_(game_toml),
        shutdown_grace_s_(shutdown_grace_s),
        data_dir_(data_dir.empty() ? dir_.path() / "data" : std::move(data_dir)) {
    start();
  }
  ~ServerProcess() {
    if (pid_ > 0 && !exit_status_) {
      kill(pid_, SIGKILL);
      int status = 0;
      waitpid(pid_, &status, 0);
    }
  }
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  /// Waits for the ports file and the start-up lines; false when they did not come within
  /// `limit` (or the server exited); throws when the file and the log disagree.
  bool wait_listening(std::chrono::milliseconds limit = std::chrono::seconds(20)) {
    const std::regex file_fields(
        R"re(^\{"control_port":(\d+),"game_port":(\d+),"admin_port":(\d+),"fingerprint":"([0-9A-F:]{95})","pid":(\d+)\}\n$)re");
    const std::regex ports(
        R"(control TLS 1\.3 on 127\.0\.0\.1:(\d+), game UDP on 127\.0\.0\.1:(\d+), admin HTTP on 127\.0\.0\.1:(\d+))");
    const std::regex fingerprint(R"(fingerprint \(pin it in clients\): ([0-9A-F:]{95}))");
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (std::chrono::steady_clock::now() < deadline) {
      const std::string text = log();
      std::smatch port_match;
      std::smatch fingerprint_match;
      std::smatch file_match;
      const std::string file = read_text(ports_path());
      if (std::regex_search(text, port_match, ports) &&
          std::regex_search(text, fingerprint_match, fingerprint) &&
          std::regex_match(file, file_match, file_fields)) {
        if (file_match[1] != port_match[1] || file_match[2] != port_match[2] ||
            file_match[3] != port_match[3] || file_match[4] != fingerprint_match[1] ||
            std::stoi(file_match[5].str()) != pid_) {
          throw std::runtime_error("the ports file " + file + " disagrees with the log " + text);
        }
        control_port_ = static_cast<std::uint16_t>(std::stoi(file_match[1].str()));
        game_port_ = static_cast<std::uint16_t>(std::stoi(file_match[2].str()));
        admin_port_ = static_cast<std::uint16_t>(std::stoi(file_match[3].str()));
        fingerprint_ = file_match[4].str();
        return true;
      }
      if (wait_exit(std::chrono::milliseconds(0))) return false;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
  }

  void terminate() { kill(pid_, SIGTERM); }
  /// kill -9, and waits for the exit.
  void kill_now() {
    kill(pid_, SIGKILL);
    wait_exit(std::chrono::seconds(10));
  }
  /// Starts the server again after it exited, on the same data directory and the ports it had
  /// (so clients that knew it find it again). Call wait_listening() next.
  void restart() {
    if (!exit_status_) throw std::logic_error("restart() while the server is running");
    exit_status_.reset();
    start();
  }
  /// The exit code once the server exited (128 + signal when a signal killed it); nullopt when
  /// it is still running after `limit`.
  std::optional<int> wait_exit(std::chrono::milliseconds limit) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (!exit_status_) {
      int status = 0;
      const pid_t done = waitpid(pid_, &status, WNOHANG);
      if (done == pid_) {
        exit_status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        break;
      }
      if (std::chrono::steady_clock::now() >= deadline) break;
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return exit_status_;
  }

  std::uint16_t control_port() const { return control_port_; }
  std::uint16_t game_port() const { return game_port_; }
  std::uint16_t admin_port() const { return admin_port_; }
  const std::string& fingerprint() const { return fingerprint_; }
  std::filesystem::path db_path() const { return data_dir_ / "ricochet.db"; }
  const std::filesystem::path& data_dir() const { return data_dir_; }
  const std::filesystem::path& dir() const { return dir_.path(); }
  std::string log() const { return read_text(log_path()); }

 private:
  /// Writes the configuration (the ports known so far, 0 before the first start) and forks the
  /// server.
  void start() {
    std::ofstream config(config_path());
    config << "[server]\ndata_dir = \"" << data_dir_.string() << "\"\nports_file = \""
           << ports_path().string() << "\"\nthreads = 2\nshutdown_grace_s = " << shutdown_grace_s_
           << "\n[control]\nbind = \"127.0.0.1\"\nport = " << control_port_
           << "\n[game]\nbind = \"127.0.0.1\"\nport = " << game_port_ << "\n"
           << game_toml_ << "\n[admin]\nbind = \"127.0.0.1\"\nport = " << admin_port_ << "\n"
           << admin_toml_ << "\n[matches]\n"
           << matches_toml_ << "\n"
           << more_toml_ << "\n";
    config.close();
    std::filesystem::remove(ports_path());
    // Everything the child needs is made before fork(): it only redirects and execs.
    const std::string log = log_path().string();
    const std::string path = config_path().string();
    const int log_fd = open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (log_fd < 0) throw std::runtime_error("cannot create " + log);
    const pid_t parent = getpid();
    pid_ = fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      // A test killed by its timeout takes its server with it.
      if (prctl(PR_SET_PDEATHSIG, SIGKILL) != 0 || getppid() != parent) _exit(125);
      if (dup2(log_fd, STDOUT_FILENO) < 0 || dup2(log_fd, STDERR_FILENO) < 0) _exit(126);
      // The password threads at the priority of everything else: the server shares its cores
      // with other test processes here, not with its own ticks, and behind them at the default
      // nice 10 a sign-in would take many times its hash (the priority itself is tested in
      // db_tests, DbWorker.PasswordThreadsRunAtTheirLowerPriority).
      execl(RICOCHET_SERVER_BINARY, RICOCHET_SERVER_BINARY, "--config", path.c_str(),
            "--password-thread-nice", "0", static_cast<char*>(nullptr));
      _exit(127);
    }
    close(log_fd);
  }
  std::filesystem::path ports_path() const { return dir_.path() / "ports.json"; }
  std::filesystem::path config_path() const { return dir_.path() / "server.toml"; }
  std::filesystem::path log_path() const { return dir_.path() / "server.log"; }

  TempDir dir_;
  std::string matches_toml_;
  std::string more_toml_;
  std::string admin_toml_;
  std::string game_toml_;
  int shutdown_grace_s_;
  std::filesystem::path data_dir_;
  pid_t pid_ = -1;
  std::optional<int> exit_status_;
  std::uint16_t control_port_ = 0;
  std::uint16_t game_port_ = 0;
  std::uint16_t admin_port_ = 0;
  std::string fingerprint_;
};

}  // namespace ricochet::test
