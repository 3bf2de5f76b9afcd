#include "ricochet/bot/control_client.h"

#include <openssl/ssl.h>
#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <boost/asio/write.hpp>
#include <chrono>
#include <variant>

#include "ricochet/bot/game_session.h"

namespace ricochet::bot {

namespace asio = boost::asio;

asio::ssl::context make_control_tls_context() {
  asio::ssl::context tls(asio::ssl::context::tls_client);
  SSL_CTX_set_min_proto_version(tls.native_handle(), TLS1_3_VERSION);
  // The certificate is self-signed: it is pinned by fingerprint after the handshake instead.
  tls.set_verify_mode(asio::ssl::verify_none);
  return tls;
}

ControlClient::ControlClient(asio::io_context& io, asio::ssl::context& tls, ServerTrust& trust,
                             Callbacks callbacks, proto::ControlClientConfig config)
    : stream_(io, tls),
      trust_(trust),
      callbacks_(std::move(callbacks)),
      protocol_(steady_now_us(), std::move(config)),
      deadline_(io) {}

void ControlClient::connect(const asio::ip::tcp::endpoint& server, const asio::ip::address& local) {
  if (!local.is_unspecified()) {
    boost::system::error_code error;
    stream_.next_layer().open(server.protocol(), error);
    if (!error) stream_.next_layer().bind({local, 0}, error);
    if (error) {
      return asio::post(stream_.get_executor(),
                        [self = shared_from_this(), error] { self->on_connected(error); });
    }
  }
  stream_.next_layer().async_connect(
      server, [self = shared_from_this()](const boost::system::error_code& error) {
        self->on_connected(error);
      });
}

void ControlClient::on_connected(const boost::system::error_code& error) {
  if (closed_) return;
  if (error) return fail("cannot connect: " + error.message());
  boost::system::error_code ignored;
  stream_.next_layer().set_option(asio::ip::tcp::no_delay(true), ignored);
  stream_.async_handshake(asio::ssl::stream_base::client,
                          [self = shared_from_this()](const boost::system::error_code& error) {
                            self->on_handshake(error);
                          });
}

void ControlClient::on_handshake(const boost::system::error_code& error) {
  if (closed_) return;
  if (error) {
    // A server over its connection caps closes right after the TCP accept, before TLS.
    return fail("TLS handshake failed: " + error.message() +
                " (a server at its connection cap closes before TLS: see its "
                "control.max_connections_per_address and control.max_connections)");
  }
  X509* certificate = SSL_get1_peer_certificate(stream_.native_handle());
  const std::string fingerprint = certificate_fingerprint_sha256(certificate);
  X509_free(certificate);
  if (const std::string refusal = trust_.check(fingerprint); !refusal.empty()) {
    untrusted_ = true;
    return fail(refusal);
  }
  ready_ = true;
  if (callbacks_.on_ready) callbacks_.on_ready({});
  if (closed_) return;
  read_more();
  pump();
}

bool ControlClient::request(wire::ClientMessage message, ReplyHandler on_reply) {
  if (closed_) return false;
  const proto::ClientMessageKind kind = proto::kind_of(message);
  const proto::RequestResult result = protocol_.request(std::move(message), steady_now_us());
  if (!result) {
    spdlog::warn("control: {} not sent: {} (the connection is {})", proto::name(kind),
                 proto::name(*result.refusal), proto::name(protocol_.state()));
    return false;
  }
  handlers_.emplace(result.request_id, std::move(on_reply));
  write_next();
  arm_deadline();
  return true;
}

void ControlClient::pump() {
  proto::ControlEvent event;
  while (!closed_ && protocol_.poll_event(event)) {
    if (auto* reply = std::get_if<proto::ControlReply>(&event)) {
      auto handler = handlers_.extract(reply->request_id);
      if (!handler.empty() && handler.mapped()) handler.mapped()(reply->message);
    } else if (auto* pushed = std::get_if<proto::ControlMatchResults>(&event)) {
      if (callbacks_.on_match_results) callbacks_.on_match_results(pushed->results);
    } else {
      return fail(std::get<proto::ControlClosed>(event).detail);
    }
  }
  if (closed_) return;
  write_next();
  arm_deadline();
}

void ControlClient::write_next() {
  if (!ready_ || closed_ || !writing_.empty() || !protocol_.poll_transmit(writing_)) return;
  asio::async_write(
      stream_, asio::buffer(writing_),
      [self = shared_from_this()](const boost::system::error_code& error, std::size_t) {
        self->writing_.clear();
        if (self->closed_) return;
        if (error) self->protocol_.connection_lost("write failed: " + error.message());
        self->pump();
      });
}

void ControlClient::arm_deadline() {
  const std::optional<proto::TimeUs> due = protocol_.deadline();
  if (!ready_ || closed_ || !due || due == armed_for_) return;
  armed_for_ = due;
  deadline_.expires_at(std::chrono::steady_clock::time_point(std::chrono::microseconds(*due)));
  deadline_.async_wait([self = shared_from_this()](const boost::system::error_code& error) {
    if (error || self->closed_) return;
    self->armed_for_.reset();
    self->protocol_.update(steady_now_us());
    self->pump();
  });
}

void ControlClient::read_more() {
  stream_.async_read_some(
      asio::buffer(read_buffer_),
      [self = shared_from_this()](const boost::system::error_code& error, std::size_t bytes) {
        self->on_read(error, bytes);
      });
}

void ControlClient::on_read(const boost::system::error_code& error, std::size_t bytes) {
  if (closed_) return;
  protocol_.receive(std::span<const std::uint8_t>(read_buffer_.data(), bytes));
  if (error) {
    // After the server's closing Error this changes nothing: its reason is the one reported.
    protocol_.connection_lost(error == asio::error::eof ||
                                      error == asio::ssl::error::stream_truncated
                                  ? std::string("the server closed the connection")
                                  : "read failed: " + error.message());
  }
  pump();
  if (!closed_) read_more();
}

bool ControlClient::refused_server() const {
  for (std::size_t reason = 0; reason < proto::kControlCloseReasonCount; ++reason) {
    if (proto::refuses_server(static_cast<proto::ControlCloseReason>(reason)) &&
        protocol_.counters().closes[reason] > 0) {
      return true;
    }
  }
  return false;
}

void ControlClient::fail(const std::string& reason) {
  if (closed_) return;
  const bool was_ready = ready_;
  const Callbacks callbacks = callbacks_;
  close();
  if (!was_ready) {
    if (callbacks.on_ready) callbacks.on_ready(reason);
  } else if (callbacks.on_closed) {
    callbacks.on_closed(reason);
  }
}

void ControlClient::close() {
  if (closed_) return;
  // The callbacks stay (one of them may be the caller): closed_ stops every further call.
  closed_ = true;
  protocol_.close();
  handlers_.clear();
  deadline_.cancel();
  boost::system::error_code ignored;
  stream_.lowest_layer().shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
  stream_.lowest_layer().close(ignored);
}

}  // namespace ricochet::bot
