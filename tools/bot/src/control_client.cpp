#include "ricochet/bot/control_client.h"

#include <openssl/ssl.h>
#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <boost/asio/write.hpp>

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
                             Callbacks callbacks)
    : stream_(io, tls), trust_(trust), callbacks_(std::move(callbacks)) {}

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
  write_next();
}

void ControlClient::request(wire::ClientMessage message, ReplyHandler on_reply) {
  if (closed_) return;
  last_request_id_ = last_request_id_ == UINT32_MAX ? 1 : last_request_id_ + 1;
  message.set_request_id(last_request_id_);
  std::vector<std::uint8_t> frame;
  if (!proto::append_frame(message, frame)) {
    spdlog::warn("control: a request of {} bytes does not fit a frame", message.ByteSizeLong());
    return;
  }
  pending_.push_back({last_request_id_, std::move(on_reply)});
  outbox_.push_back(std::move(frame));
  if (ready_) write_next();
}

void ControlClient::write_next() {
  if (writing_ || outbox_.empty() || closed_) return;
  writing_ = true;
  asio::async_write(
      stream_, asio::buffer(outbox_.front()),
      [self = shared_from_this()](const boost::system::error_code& error, std::size_t) {
        self->writing_ = false;
        if (self->closed_) return;
        if (error) return self->fail("write failed: " + error.message());
        self->outbox_.pop_front();
        self->write_next();
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
  reader_.feed(std::span<const std::uint8_t>(read_buffer_.data(), bytes));
  while (!closed_) {
    const auto status = reader_.next(payload_);
    if (status == proto::FrameReader::Status::NeedMore) break;
    if (status == proto::FrameReader::Status::Refused) {
      ++bad_frames_;
      return fail(std::string("the server sent a bad frame (") + name(*reader_.refusal()) +
                  ", length " + std::to_string(reader_.refused_length()) + ")");
    }
    wire::ServerMessage message;
    if (const auto refusal = proto::parse_server_message(payload_, message)) {
      ++bad_frames_;
      return fail(std::string("the server sent a frame that is not a ServerMessage (") +
                  name(*refusal) + ")");
    }
    dispatch(message);
  }
  if (closed_) return;
  if (error) {
    return fail(error == asio::error::eof || error == asio::ssl::error::stream_truncated
                    ? std::string("the server closed the connection")
                    : "read failed: " + error.message());
  }
  read_more();
}

void ControlClient::dispatch(const wire::ServerMessage& message) {
  if (message.request_id() == 0) {
    if (callbacks_.on_push) callbacks_.on_push(message);
    return;
  }
  if (pending_.empty() || pending_.front().request_id != message.request_id()) {
    ++bad_frames_;
    return fail("the server answered request " + std::to_string(message.request_id()) +
                (pending_.empty() ? std::string(", none was pending")
                                  : ", expected " + std::to_string(pending_.front().request_id)));
  }
  ReplyHandler handler = std::move(pending_.front().on_reply);
  pending_.pop_front();
  if (handler) handler(message);
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
  pending_.clear();
  boost::system::error_code ignored;
  stream_.lowest_layer().shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
  stream_.lowest_layer().close(ignored);
}

}  // namespace ricochet::bot
