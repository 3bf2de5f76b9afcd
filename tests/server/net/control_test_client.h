#pragma once
/// The control channel's test rig: a real server (TLS on 127.0.0.1, a port chosen free, a real
/// DbWorker on a temporary SQLite file at the minimum password cost, a fake match directory)
/// and a small blocking socket with a deadline on every call under proto::ControlClient.

#include <gtest/gtest.h>
#include <openssl/ssl.h>
#include <openssl/x509.h>
#include <stdlib.h>

#include <array>
#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ssl.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <deque>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "control_server.h"
#include "match_directory.h"
#include "ricochet/db/db_worker.h"
#include "ricochet/db/store.h"
#include "ricochet/proto/control_client.h"
#include "ricochet/proto/frame.h"
#include "temp_dir.h"

namespace ricochet::server::test {

using namespace std::chrono_literals;
namespace asio = boost::asio;

/// A temp directory named ricochet-control-XXXXXX (tests/temp_dir.h).
class TempDir : public ricochet::test::TempDir {
 public:
  TempDir() : ricochet::test::TempDir("ricochet-control") {}
};

/// A match directory that records what it is asked and answers from a small table. Like the
/// registry, one control session plays a seated account (the newest join's, or a resume's of
/// the same session token): leave and chat from another session are NotInMatch.
class FakeDirectory : public MatchDirectory {
 public:
  FakeDirectory() { matches_.push_back({1, "arena 1", "ffa", "arena", 0, 16}); }

  std::vector<MatchSummary> list() const override {
    std::lock_guard lock(mutex_);
    return matches_;
  }
  DirectoryResult<MatchSummary> create(const CreateMatchRequest& request) override {
    std::lock_guard lock(mutex_);
    if (request.max_players < 1 || request.max_players > 64) {
      return DirectoryError{
          DirectoryErrorCode::InvalidRequest,
          "max_players must be 1..64, got " + std::to_string(request.max_players)};
    }
    MatchSummary summary{static_cast<std::uint32_t>(matches_.size() + 1),
                         request.name,
                         "ffa",
                         request.map.empty() ? "arena" : request.map,
                         0,
                         request.max_players};
    matches_.push_back(summary);
    created.push_back(request);
    return summary;
  }
  /// Sets match `id`'s seated players as list() shows them.
  void set_players(std::uint32_t id, int players) {
    std::lock_guard lock(mutex_);
    for (MatchSummary& match : matches_) {
      if (match.id == id) match.players = players;
    }
  }
  DirectoryResult<JoinGrant> join(std::uint64_t account, const std::string& username,
                                  std::uint32_t match_id, const JoinOrigin& origin) override {
    std::lock_guard lock(mutex_);
    if (match_id == 0 || match_id > matches_.size()) {
      return DirectoryError{DirectoryErrorCode::MatchNotFound,
                            "no match " + std::to_string(match_id)};
    }
    seated_[account] = Seat{match_id, origin.session, origin.session_token};
    joined_names.push_back(username);
    JoinGrant grant;
    grant.match_id = match_id;
    grant.udp_port = 7778;
    grant.token.connect_token.assign(64, 0xab);
    grant.token.client_to_server.fill(1);
    grant.token.server_to_client.fill(2);
    grant.token.expires_at = now_us() + 30 * proto::kMicrosPerSecond;
    grant.token.timeout_s = 5;
    return grant;
  }
  std::optional<std::uint32_t> rejoin(std::uint64_t account, const JoinOrigin& origin) override {
    std::lock_guard lock(mutex_);
    const auto seat = seated_.find(account);
    if (seat == seated_.end() || origin.session_token.empty() ||
        seat->second.session_token != origin.session_token) {
      return std::nullopt;
    }
    seat->second.session = origin.session;
    return seat->second.match_id;
  }
  DirectoryResult<Done> leave(std::uint64_t account, std::uint64_t session) override {
    std::lock_guard lock(mutex_);
    if (const auto refused = refuse_session(account, session)) return *refused;
    seated_.erase(account);
    return Done{};
  }
  DirectoryResult<Done> chat(std::uint64_t account, std::uint64_t session,
                             const std::string& text) override {
    std::lock_guard lock(mutex_);
    if (const auto refused = refuse_session(account, session)) return *refused;
    chats.push_back(text);
    return Done{};
  }
  static proto::TimeUs now_us() {
    return std::chrono::duration_cast<std::chrono::microseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
  std::vector<std::string> chats_seen() const {
    std::lock_guard lock(mutex_);
    return chats;
  }
  bool seated(std::uint64_t account) const {
    std::lock_guard lock(mutex_);
    return seated_.count(account) != 0;
  }

  std::vector<std::string> chats;
  std::vector<std::string> joined_names;
  std::vector<CreateMatchRequest> created;  ///< every create() that opened a match

 private:
  struct Seat {
    std::uint32_t match_id = 0;
    std::uint64_t session = 0;  ///< the control session that plays the account
    std::string session_token;  ///< what it signed in with
  };
  /// NotInMatch when the account holds no seat or `session` does not play it. Holds mutex_.
  std::optional<DirectoryError> refuse_session(std::uint64_t account, std::uint64_t session) {
    const auto seat = seated_.find(account);
    if (seat == seated_.end()) {
      return DirectoryError{DirectoryErrorCode::NotInMatch, "not in a match"};
    }
    if (seat->second.session != session) {
      return DirectoryError{DirectoryErrorCode::NotInMatch,
                            "the account is played from another control connection now"};
    }
    return std::nullopt;
  }

  mutable std::mutex mutex_;
  std::vector<MatchSummary> matches_;
  std::map<std::uint64_t, Seat> seated_;
};

/// A server whose io_context runs on two threads of its own (the control server keeps its
/// state on one strand, so any number of threads must be safe). Its clock is the steady one
/// unless the test hands it another (control_limits_test's fake time); `accounts` sets the
/// account rules' limits (the password cost stays the minimum); `episodes` logs the account
/// refusals.
class ControlRig {
 public:
  explicit ControlRig(ControlLimits limits = {}, std::function<proto::TimeUs()> clock = {},
                      db::AccountsOptions accounts = {}, EpisodeLog* episodes = nullptr,
                      FleetPlacement* placement = nullptr) {
    db::DbWorkerOptions options;
    options.accounts = std::move(accounts);
    options.accounts.cost = db::PasswordCost::Minimum;
    auto store = db::open_sqlite_store({.path = (dir_.path() / "ricochet.db").string()});
    if (!store.ok()) throw std::runtime_error("cannot open the test database");
    db_ = std::make_unique<db::DbWorker>(std::move(store).value(), options);
    ControlServerConfig config;
    config.bind_address = "127.0.0.1";
    config.port = 0;
    config.tls.data_dir = dir_.path() / "data";
    config.limits = limits;
    if (clock) config.clock = std::move(clock);
    config.episodes = episodes;
    config.placement = placement;
    server_ = std::make_unique<ControlServer>(io_, config, *db_, directory_);
    server_->start();
    for (auto& thread : threads_) thread = std::thread([this] { io_.run(); });
  }
  ~ControlRig() {
    server_->stop();
    // Give the sessions their goodbye, then stop the loop whatever is left.
    for (int i = 0; i < 300 && server_->connections() > 0; ++i) std::this_thread::sleep_for(10ms);
    io_.stop();
    for (auto& thread : threads_) thread.join();
    server_.reset();
    db_->stop();
  }
  ControlRig(const ControlRig&) = delete;
  ControlRig& operator=(const ControlRig&) = delete;

  ControlServer& server() { return *server_; }
  FakeDirectory& directory() { return directory_; }
  db::DbWorker& db() { return *db_; }
  std::uint16_t port() const { return server_->port(); }
  std::uint64_t refusals(ControlRefusal refusal) const {
    return server_->counters().refusals(refusal);
  }
  /// Waits until the refusal's counter reaches `at_least` (counters move on the server thread).
  bool wait_refusals(ControlRefusal refusal, std::uint64_t at_least,
                     std::chrono::milliseconds limit = 5s) const {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (refusals(refusal) < at_least) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      std::this_thread::sleep_for(2ms);
    }
    return true;
  }
  const std::filesystem::path& dir() const { return dir_.path(); }

 private:
  TempDir dir_;
  asio::io_context io_;
  std::unique_ptr<db::DbWorker> db_;
  FakeDirectory directory_;
  std::unique_ptr<ControlServer> server_;
  std::array<std::thread, 2> threads_;
};

/// A blocking client over proto::ControlClient, which numbers the requests, matches the replies
/// and follows the connection's state; this class is only its socket. Every call has a deadline,
/// so a test never hangs. Two ways around the ControlClient, for tests of the server's own
/// checks:
///   - a request the ControlClient refuses for its state (counted there) is sent raw, numbered
///     from kRawRequestIds, and its reply taken out of the stream before the ControlClient sees
///     it;
///   - after send_bytes() the stream is no longer the ControlClient's: receive() returns every
///     frame the server sends as it came.
class ControlTestClient {
 public:
  static constexpr std::uint32_t kRawRequestIds = 0x8000'0000;

  explicit ControlTestClient(std::uint16_t port, int max_tls_version = TLS1_3_VERSION)
      : port_(port),
        tls_(asio::ssl::context::tls_client),
        stream_(io_, make_tls(max_tls_version)),
        protocol_(now_us(), test_config()) {}

  /// Connects from `ip` (another loopback address, 127.0.0.2 ...), to look like another host
  /// to the server's per-address limits; 127.0.0.1 unless called before connect().
  void use_source(const std::string& ip) { source_ = ip; }
  /// TCP connect only (for plaintext probes).
  bool connect_tcp(std::chrono::milliseconds limit = 3s) {
    bool done = false;
    boost::system::error_code result;
    if (!source_.empty()) {
      auto& socket = stream_.next_layer();
      socket.open(asio::ip::tcp::v4(), result);
      if (!result) socket.bind({asio::ip::make_address(source_), 0}, result);
      if (result) return false;
    }
    stream_.next_layer().async_connect({asio::ip::make_address("127.0.0.1"), port_},
                                       [&](boost::system::error_code error) {
                                         result = error;
                                         done = true;
                                       });
    run(done, limit);
    return done && !result;
  }
  /// connect() from `source`, a loopback address such as 127.0.0.2: what the server's
  /// per-address limits see.
  bool connect_from(const std::string& source, std::chrono::milliseconds limit = 3s) {
    use_source(source);
    return connect(limit);
  }
  /// TCP connect and TLS handshake; true when the server let us in.
  bool connect(std::chrono::milliseconds limit = 3s) {
    if (!connect_tcp(limit)) return false;
    bool done = false;
    boost::system::error_code result;
    stream_.async_handshake(asio::ssl::stream_base::client, [&](boost::system::error_code error) {
      result = error;
      done = true;
    });
    run(done, limit);
    return done && !result;
  }
  /// The server certificate's fingerprint as tls_identity.h formats it.
  std::string peer_fingerprint() {
    X509* certificate = SSL_get1_peer_certificate(stream_.native_handle());
    if (!certificate) return {};
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int size = 0;
    X509_digest(certificate, EVP_sha256(), digest, &size);
    X509_free(certificate);
    std::string text;
    char pair[4];
    for (unsigned int i = 0; i < size; ++i) {
      std::snprintf(pair, sizeof pair, "%02X", digest[i]);
      if (i) text += ':';
      text += pair;
    }
    return text;
  }
  std::string negotiated_version() { return SSL_get_version(stream_.native_handle()); }
  /// The connection's state as the replies so far have set it.
  proto::ControlState state() const { return protocol_.state(); }

  /// Sends a request and waits for its reply (the reply body or an Error).
  wire::ServerMessage request(wire::ClientMessage message) {
    if (raw_) {
      ADD_FAILURE() << "request() after send_bytes(): the stream is no longer the client's";
      return {};
    }
    const proto::RequestResult sent = protocol_.request(message, now_us());
    if (sent.refusal == proto::RequestRefusal::WrongState) return request_raw(std::move(message));
    if (!sent) {
      ADD_FAILURE() << "the control client refused the request: " << proto::name(*sent.refusal);
      return {};
    }
    write(take_transmit());
    const auto deadline = std::chrono::steady_clock::now() + 3s;
    while (!replies_.count(sent.request_id) && read_some(deadline)) {
    }
    const auto reply = replies_.find(sent.request_id);
    if (reply == replies_.end()) {
      ADD_FAILURE() << "no reply to request " << sent.request_id;
      return {};
    }
    wire::ServerMessage message_out = std::move(reply->second);
    replies_.erase(reply);
    return message_out;
  }
  /// Raw bytes over TLS; from here on receive() returns the server's frames as they come.
  void send_bytes(const std::vector<std::uint8_t>& bytes) {
    raw_ = true;
    write(bytes);
  }
  /// Raw bytes over TCP, no TLS.
  void send_plain(const std::string& text) {
    bool done = false;
    asio::async_write(stream_.next_layer(), asio::buffer(text),
                      [&](boost::system::error_code, std::size_t) { done = true; });
    run(done, 3s);
  }

  /// The next message the server sent unasked (MatchResults, the Error it closes with; after
  /// send_bytes(), any frame), or nullopt when the server closed the connection (closed() is
  /// then true) or nothing came within `limit`.
  std::optional<wire::ServerMessage> receive(std::chrono::milliseconds limit = 3s) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (inbox_.empty() && read_some(deadline)) {
    }
    if (inbox_.empty()) return std::nullopt;
    wire::ServerMessage message = std::move(inbox_.front());
    inbox_.pop_front();
    return message;
  }
  /// Reads until the server closes the connection; true when it did within `limit`.
  /// Messages that came first are returned through `before`.
  bool wait_closed(std::chrono::milliseconds limit = 5s,
                   std::vector<wire::ServerMessage>* before = nullptr) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (!closed_ && std::chrono::steady_clock::now() < deadline) {
      auto message = receive(std::chrono::duration_cast<std::chrono::milliseconds>(
          deadline - std::chrono::steady_clock::now()));
      if (message && before) before->push_back(*message);
    }
    return closed_;
  }
  /// Raw TCP bytes until the server closes; nullopt when it did not close within `limit`.
  std::optional<std::size_t> plain_bytes_until_closed(std::chrono::milliseconds limit = 5s) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    std::size_t total = 0;
    while (std::chrono::steady_clock::now() < deadline) {
      bool done = false;
      bool ended = false;
      std::array<std::uint8_t, 4096> buffer;
      stream_.next_layer().async_read_some(asio::buffer(buffer),
                                           [&](boost::system::error_code error, std::size_t n) {
                                             total += n;
                                             ended = static_cast<bool>(error);
                                             done = true;
                                           });
      run(done, std::chrono::duration_cast<std::chrono::milliseconds>(
                    deadline - std::chrono::steady_clock::now()));
      if (ended) return total;
      if (!done) return std::nullopt;
    }
    return std::nullopt;
  }
  /// The server closed the connection.
  bool closed() const { return closed_; }
  /// The protocol state machine under this socket (its state, its counters).
  const proto::ControlClient& protocol() const { return protocol_; }

  // Requests, built.
  static wire::ClientMessage register_account(const std::string& name, const std::string& pw) {
    wire::ClientMessage m;
    m.mutable_register_account()->set_username(name);
    m.mutable_register_account()->set_password(pw);
    return m;
  }
  static wire::ClientMessage login(const std::string& name, const std::string& pw) {
    wire::ClientMessage m;
    m.mutable_login()->set_username(name);
    m.mutable_login()->set_password(pw);
    return m;
  }
  static wire::ClientMessage resume(const std::string& token) {
    wire::ClientMessage m;
    m.mutable_resume()->set_session_token(token);
    return m;
  }
  static wire::ClientMessage ping(std::uint64_t t) {
    wire::ClientMessage m;
    m.mutable_ping()->set_client_time_us(t);
    return m;
  }
  static wire::ClientMessage list_matches() {
    wire::ClientMessage m;
    m.mutable_list_matches();
    return m;
  }
  static wire::ClientMessage leave() {
    wire::ClientMessage m;
    m.mutable_leave_match();
    return m;
  }
  static wire::ClientMessage join(std::uint32_t match) {
    wire::ClientMessage m;
    m.mutable_join_match()->set_match_id(match);
    return m;
  }
  static wire::ClientMessage logout() {
    wire::ClientMessage m;
    m.mutable_logout();
    return m;
  }
  static wire::ClientMessage chat(const std::string& text) {
    wire::ClientMessage m;
    m.mutable_chat()->set_text(text);
    return m;
  }
  /// Registers (if `fresh`) and logs in; returns the session reply.
  wire::SessionReply sign_in(const std::string& name, bool fresh = true) {
    if (fresh) {
      const auto reply = request(register_account(name, "password-" + name));
      EXPECT_TRUE(reply.has_register_account()) << reply.DebugString();
    }
    const auto reply = request(login(name, "password-" + name));
    EXPECT_TRUE(reply.has_session()) << reply.DebugString();
    return reply.session();
  }

 private:
  static proto::TimeUs now_us() {
    return std::chrono::duration_cast<std::chrono::microseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
  /// The test decides what is sent and how long it waits: no keep-alive, no request timeout.
  static proto::ControlClientConfig test_config() {
    proto::ControlClientConfig config;
    config.request_timeout_us = 0;
    config.keep_alive_us = 0;
    return config;
  }
  asio::ssl::context& make_tls(int max_version) {
    SSL_CTX_set_min_proto_version(tls_.native_handle(), TLS1_VERSION);
    SSL_CTX_set_max_proto_version(tls_.native_handle(), max_version);
    tls_.set_verify_mode(asio::ssl::verify_none);  // pinned by fingerprint instead
    return tls_;
  }
  std::vector<std::uint8_t> take_transmit() {
    std::vector<std::uint8_t> bytes;
    protocol_.poll_transmit(bytes);
    return bytes;
  }
  void write(const std::vector<std::uint8_t>& bytes) {
    bool done = false;
    asio::async_write(stream_, asio::buffer(bytes),
                      [&](boost::system::error_code, std::size_t) { done = true; });
    run(done, 3s);
  }
  /// A request the client's state table refuses, sent past it (the server's table is tested).
  wire::ServerMessage request_raw(wire::ClientMessage message) {
    const std::uint32_t request_id = next_raw_id_++;
    message.set_request_id(request_id);
    std::vector<std::uint8_t> frame;
    EXPECT_TRUE(proto::append_frame(message, frame));
    write(frame);
    const auto deadline = std::chrono::steady_clock::now() + 3s;
    while (true) {
      for (auto it = inbox_.begin(); it != inbox_.end(); ++it) {
        if (it->request_id() != request_id) continue;
        wire::ServerMessage reply = std::move(*it);
        inbox_.erase(it);
        return reply;
      }
      if (!read_some(deadline)) break;
    }
    ADD_FAILURE() << "no reply to raw request " << request_id;
    return {};
  }
  /// Reads once, until `deadline` at the latest, and sorts the frames that came: replies to raw
  /// requests (and every frame after send_bytes()) to the inbox, the rest through the
  /// ControlClient (replies by request id; MatchResults and the closing Error to the inbox).
  /// False when the server closed the connection or nothing came in time.
  bool read_some(std::chrono::steady_clock::time_point deadline) {
    if (closed_) return false;
    const auto left = deadline - std::chrono::steady_clock::now();
    if (left <= 0s) return false;
    bool done = false;
    std::array<std::uint8_t, 16384> buffer;
    stream_.async_read_some(asio::buffer(buffer),
                            [&](boost::system::error_code error, std::size_t n) {
                              if (error && error != asio::error::operation_aborted) closed_ = true;
                              sort(std::span<const std::uint8_t>(buffer.data(), n));
                              done = true;
                            });
    run(done, std::chrono::duration_cast<std::chrono::milliseconds>(left));
    return done && !closed_;
  }
  void sort(std::span<const std::uint8_t> bytes) {
    reader_.feed(bytes);
    std::vector<std::uint8_t> payload;
    proto::FrameReader::Status status;
    while ((status = reader_.next(payload)) == proto::FrameReader::Status::Frame) {
      wire::ServerMessage message;
      if (proto::parse_server_message(payload, message)) {
        ADD_FAILURE() << "the server sent a frame that is not a ServerMessage";
        continue;
      }
      if (raw_ || message.request_id() >= kRawRequestIds) {
        inbox_.push_back(std::move(message));
        continue;
      }
      std::vector<std::uint8_t> frame;
      EXPECT_TRUE(proto::append_frame(message, frame));
      protocol_.receive(frame);
    }
    if (status == proto::FrameReader::Status::Refused)
      ADD_FAILURE() << "the server sent a bad frame";
    proto::ControlEvent event;
    while (protocol_.poll_event(event)) {
      if (auto* reply = std::get_if<proto::ControlReply>(&event)) {
        replies_[reply->request_id] = std::move(reply->message);
      } else if (auto* pushed = std::get_if<proto::ControlMatchResults>(&event)) {
        wire::ServerMessage message;
        *message.mutable_match_results() = std::move(pushed->results);
        inbox_.push_back(std::move(message));
      } else if (auto& end = std::get<proto::ControlClosed>(event);
                 end.reason == proto::ControlCloseReason::ServerError) {
        wire::ServerMessage message;
        *message.mutable_error() = std::move(end.server_error);
        inbox_.push_back(std::move(message));
      } else {
        ADD_FAILURE() << "the control client closed: " << end.detail;
      }
    }
  }
  /// Runs the client's loop until `done` or `limit`; on timeout, cancels what is pending.
  void run(bool& done, std::chrono::milliseconds limit) {
    io_.restart();
    const auto deadline = std::chrono::steady_clock::now() + limit;
    while (!done && std::chrono::steady_clock::now() < deadline) io_.run_one_for(5ms);
    if (!done) {
      boost::system::error_code ignored;
      stream_.next_layer().cancel(ignored);
      io_.restart();
      io_.run_for(200ms);  // the cancelled handler runs and touches only `done` and locals
    }
  }

  std::uint16_t port_;
  std::string source_;  ///< the local address to connect from; empty: the kernel's choice
  asio::io_context io_;
  asio::ssl::context tls_;
  asio::ssl::stream<asio::ip::tcp::socket> stream_;
  proto::ControlClient protocol_;
  proto::FrameReader reader_;  ///< in front of protocol_, to take raw frames out
  std::deque<wire::ServerMessage> inbox_;
  std::map<std::uint32_t, wire::ServerMessage> replies_;  ///< by request id
  std::uint32_t next_raw_id_ = kRawRequestIds;
  bool raw_ = false;  ///< send_bytes() was called
  bool closed_ = false;
};

}  // namespace ricochet::server::test
