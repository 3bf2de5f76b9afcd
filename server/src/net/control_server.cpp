#include "control_server.h"

#include <openssl/ssl.h>
#include <spdlog/spdlog.h>

#include <boost/asio/as_tuple.hpp>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <stdexcept>

namespace ricochet::server {
namespace asio = boost::asio;
namespace {

constexpr auto kAsTuple = asio::as_tuple(asio::use_awaitable);

ControlServerConfig checked(ControlServerConfig config) {
  if (std::string problem = config.validate(); !problem.empty()) {
    throw std::invalid_argument(problem);
  }
  if (!config.clock) throw std::invalid_argument("control: the config has no clock");
  return config;
}

/// A TLS 1.3-only server context holding the identity.
void configure_tls(asio::ssl::context& tls, const TlsIdentity& identity) {
  SSL_CTX* context = tls.native_handle();
  if (SSL_CTX_set_min_proto_version(context, TLS1_3_VERSION) != 1 ||
      SSL_CTX_set_max_proto_version(context, TLS1_3_VERSION) != 1) {
    throw TlsIdentityError("this OpenSSL cannot restrict the control channel to TLS 1.3");
  }
  SSL_CTX_set_options(context, SSL_OP_NO_COMPRESSION | SSL_OP_NO_RENEGOTIATION);
  SSL_CTX_set_num_tickets(context, 0);  // no resumption: a session is a login, not a ticket
  boost::system::error_code error;
  tls.use_certificate_chain(asio::buffer(identity.certificate_pem), error);
  if (error) {
    throw TlsIdentityError("cannot use the certificate " + identity.certificate_path.string() +
                           ": " + error.message());
  }
  tls.use_private_key(asio::buffer(identity.private_key_pem), asio::ssl::context::pem, error);
  if (error) {
    throw TlsIdentityError("cannot use the key " + identity.private_key_path.string() + ": " +
                           error.message());
  }
}

}  // namespace

ControlServer::ControlServer(asio::io_context& io, ControlServerConfig config, db::DbWorker& db,
                             MatchDirectory& matches)
    : config_(checked(std::move(config))),
      identity_(load_or_create_tls_identity(config_.tls)),
      tls_(asio::ssl::context::tls_server),
      strand_(asio::make_strand(io)),
      acceptor_(strand_),
      context_{config_.limits, counters_,        db, matches,
               config_.clock,  config_.episodes, {}, config_.placement} {
  configure_tls(tls_, identity_);
}

ControlServer::~ControlServer() {
  boost::system::error_code ignored;
  acceptor_.close(ignored);
}

void ControlServer::start() {
  const asio::ip::tcp::endpoint endpoint(asio::ip::make_address(config_.bind_address),
                                         config_.port);
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(asio::socket_base::reuse_address(true));
  acceptor_.bind(endpoint);
  acceptor_.listen(asio::socket_base::max_listen_connections);
  port_ = acceptor_.local_endpoint().port();
  spdlog::info("control channel: TLS 1.3 on {}:{}, certificate SHA-256 {}{}", config_.bind_address,
               port_.load(), identity_.fingerprint_sha256,
               identity_.generated ? " (generated now)" : "");
  asio::co_spawn(strand_, accept_loop(), asio::detached);
}

void ControlServer::stop() {
  asio::post(strand_, [this] {
    if (stopping_) return;
    stopping_ = true;
    boost::system::error_code ignored;
    acceptor_.close(ignored);
    spdlog::info("control channel: stopping, closing {} sessions", sessions_.size());
    // ended() erases from sessions_ while close() runs only on later handlers, but copy anyway.
    std::vector<std::shared_ptr<ControlSession>> open;
    for (auto& [id, session] : sessions_) open.push_back(session);
    for (auto& session : open) {
      session->close(wire::SHUTTING_DOWN, "the server is stopping", "server stopping");
    }
  });
}

void ControlServer::check_deadlines() {
  asio::post(strand_, [this] {
    for (auto& [id, session] : sessions_) session->check_deadlines();
  });
}

void ControlServer::send_to_account(std::uint64_t account, wire::ServerMessage message) {
  asio::post(strand_, [this, account, message = std::move(message)] {
    for (auto& [id, session] : sessions_) {
      if (session->account() == account) session->push(message);
    }
  });
}

void ControlServer::ban_account(std::uint64_t account, std::string message,
                                std::function<void(std::size_t closed)> then) {
  asio::post(strand_, [this, account, message = std::move(message), then = std::move(then)] {
    context_.banned.insert(account);
    std::vector<std::shared_ptr<ControlSession>> signed_in;
    for (auto& [id, session] : sessions_) {
      if (session->account() == account) signed_in.push_back(session);
    }
    for (auto& session : signed_in) session->close(wire::ACCOUNT_BANNED, message, "banned");
    if (then) then(signed_in.size());
  });
}

void ControlServer::unban_account(std::uint64_t account) {
  asio::post(strand_, [this, account] { context_.banned.erase(account); });
}

asio::awaitable<void> ControlServer::accept_loop() {
  asio::steady_timer backoff(strand_);
  while (!stopping_) {
    auto [error, socket] = co_await acceptor_.async_accept(kAsTuple);
    if (stopping_ || error == asio::error::operation_aborted) break;
    if (error) {
      // Out of descriptors or memory: wait a little instead of spinning on the error.
      spdlog::warn("control channel: accept failed: {}", error.message());
      backoff.expires_after(std::chrono::milliseconds(100));
      co_await backoff.async_wait(kAsTuple);
      continue;
    }
    counters_.add(counters_.accepted);
    boost::system::error_code endpoint_error;
    const auto remote = socket.remote_endpoint(endpoint_error);
    if (endpoint_error) continue;  // already reset by the peer
    const std::string address = remote.address().to_string();
    if (!admit(socket, address)) continue;
    const std::uint64_t id = next_session_id_++;
    auto session = std::make_shared<ControlSession>(id, std::move(socket), tls_, address, context_,
                                                    [this](ControlSession& s) { ended(s); });
    sessions_.emplace(id, session);
    ++per_address_[address];
    connections_ = sessions_.size();
    spdlog::debug("control #{} {}: accepted ({} open)", id, address, sessions_.size());
    asio::co_spawn(strand_, session->run(), asio::detached);
  }
}

bool ControlServer::admit(asio::ip::tcp::socket& socket, const std::string& address) {
  std::optional<ControlRefusal> refusal;
  std::string detail;
  const ControlLimits& limits = config_.limits;
  if (sessions_.size() >= static_cast<std::size_t>(limits.max_connections)) {
    refusal = ControlRefusal::ConnectionCap;
    detail = std::to_string(sessions_.size()) + " connections open, the cap is " +
             std::to_string(limits.max_connections);
  } else if (const auto it = per_address_.find(address);
             it != per_address_.end() && it->second >= limits.max_connections_per_address) {
    refusal = ControlRefusal::AddressCap;
    detail = std::to_string(it->second) + " connections open from this address, the cap is " +
             std::to_string(limits.max_connections_per_address);
  }
  if (!refusal) return true;
  counters_.refused(*refusal);
  spdlog::debug("control {}: refused ({}): {}", address, name(*refusal), detail);
  boost::system::error_code ignored;
  socket.close(ignored);
  return false;
}

void ControlServer::ended(ControlSession& session) {
  const auto it = per_address_.find(session.address());
  if (it != per_address_.end() && --it->second <= 0) per_address_.erase(it);
  spdlog::debug("control #{} {}: ended", session.id(), session.address());
  // The session may be running its last lines: keep it alive until this handler returns.
  const auto found = sessions_.find(session.id());
  if (found != sessions_.end()) {
    auto keep = std::move(found->second);
    sessions_.erase(found);
    connections_ = sessions_.size();
    asio::post(strand_, [keep = std::move(keep)] {});
  }
}

}  // namespace ricochet::server
