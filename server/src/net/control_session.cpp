#include "control_session.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <boost/asio/as_tuple.hpp>
#include <boost/asio/co_spawn.hpp>
#include <boost/asio/detached.hpp>
#include <boost/asio/use_awaitable.hpp>
#include <boost/asio/write.hpp>
#include <chrono>

#include "ricochet/proto/address.h"

namespace ricochet::server {
namespace asio = boost::asio;
namespace {

constexpr auto kAsTuple = asio::as_tuple(asio::use_awaitable);
constexpr std::size_t kReadChunkBytes = 16 * 1024;

wire::ErrorCode error_code_of(proto::FrameRefusal refusal) {
  return refusal == proto::FrameRefusal::Oversize ? wire::FRAME_TOO_LARGE : wire::MALFORMED;
}

ControlRefusal control_refusal_of(proto::FrameRefusal refusal) {
  switch (refusal) {
    case proto::FrameRefusal::Oversize:
      return ControlRefusal::FrameOversize;
    case proto::FrameRefusal::Empty:
      return ControlRefusal::FrameEmpty;
    case proto::FrameRefusal::Malformed:
      return ControlRefusal::FrameMalformed;
    case proto::FrameRefusal::MissingBody:
      return ControlRefusal::FrameMissingBody;
  }
  return ControlRefusal::FrameMalformed;
}

std::string describe_frame_refusal(proto::FrameRefusal refusal, std::uint32_t declared) {
  switch (refusal) {
    case proto::FrameRefusal::Oversize:
      return "a frame's payload must be 1.." + std::to_string(proto::kMaxFramePayloadBytes) +
             " bytes, the header declared " + std::to_string(declared);
    case proto::FrameRefusal::Empty:
      return "a frame's payload must be 1.." + std::to_string(proto::kMaxFramePayloadBytes) +
             " bytes, the header declared 0";
    case proto::FrameRefusal::Malformed:
      return "the frame's payload is not a valid ricochet.wire.ClientMessage";
    case proto::FrameRefusal::MissingBody:
      return "the ClientMessage has no body set in its oneof";
  }
  return "the frame was refused";
}

/// What the account limits count an IP (text) under: proto::host_key's text (an IPv4 address, or
/// an IPv6 /64; an IPv4-mapped IPv6 address is its IPv4 address).
std::string host_key_of(const std::string& ip) {
  boost::system::error_code error;
  asio::ip::address parsed = asio::ip::make_address(ip, error);
  if (error) return ip;
  if (parsed.is_v6() && parsed.to_v6().is_v4_mapped()) {
    parsed = asio::ip::make_address_v4(asio::ip::v4_mapped, parsed.to_v6());
  }
  proto::Address address;
  if (parsed.is_v4()) {
    const auto bytes = parsed.to_v4().to_bytes();
    std::copy(bytes.begin(), bytes.end(), address.ip.begin());
  } else {
    const auto bytes = parsed.to_v6().to_bytes();
    std::copy(bytes.begin(), bytes.end(), address.ip.begin());
    address.v6 = true;
  }
  return proto::host_key(address).to_string();
}

/// A session's times as it is accepted at `now`.
ControlTimes accepted(proto::TimeUs now) {
  ControlTimes times;
  times.accepted_at = now;
  return times;
}

/// The message kinds a state admits, for WRONG_STATE errors ("login, register, ...").
std::string admitted_kinds(proto::ControlState state) {
  std::string list;
  for (std::size_t k = 0; k < proto::kClientMessageKindCount; ++k) {
    const auto kind = static_cast<proto::ClientMessageKind>(k);
    if (!proto::admits(state, kind)) continue;
    if (!list.empty()) list += ", ";
    list += proto::name(kind);
  }
  return list.empty() ? "nothing" : list;
}

}  // namespace

ControlSession::ControlSession(std::uint64_t id, asio::ip::tcp::socket socket,
                               asio::ssl::context& tls, std::string address,
                               ControlContext& context, OnEnded on_ended)
    : id_(id),
      stream_(std::move(socket), tls),
      address_(std::move(address)),
      host_key_(host_key_of(address_)),
      context_(context),
      on_ended_(std::move(on_ended)),
      machine_([this](proto::ControlState from, proto::ControlState to, std::string_view reason) {
        context_.counters.leave_state(from);
        context_.counters.enter_state(to);
        spdlog::debug("control #{} {}: {} -> {} ({})", id_, address_, proto::name(from),
                      proto::name(to), reason);
      }),
      read_buffer_(kReadChunkBytes),
      watchdog_(stream_.get_executor()),
      outbox_signal_(stream_.get_executor()),
      times_(accepted(context.clock())),
      rate_(context.limits.messages_per_second, context.limits.message_burst, times_.accepted_at) {}

asio::awaitable<void> ControlSession::run() {
  auto self = shared_from_this();
  context_.counters.add(context_.counters.handshaking);
  asio::co_spawn(stream_.get_executor(), watch(self), asio::detached);
  const bool handshaken = co_await handshake();
  context_.counters.handshaking.fetch_sub(1, std::memory_order_relaxed);
  if (!handshaken) {
    abort("no TLS session");
    times_.phase = ControlPhase::Ended;
    watchdog_.cancel();
    context_.counters.add(context_.counters.closed);
    if (on_ended_) on_ended_(*this);
    co_return;
  }
  context_.counters.add(context_.counters.handshakes);
  context_.counters.enter_state(machine_.state());
  times_.phase = ControlPhase::Open;
  times_.last_frame_at = context_.clock();
  times_.opened_at = times_.last_frame_at;
  check_deadlines();
  running_tasks_ = 2;
  asio::co_spawn(stream_.get_executor(), write_loop(self), asio::detached);
  co_await read_loop();
  task_ended();
}

asio::awaitable<bool> ControlSession::handshake() {
  auto [error] = co_await stream_.async_handshake(asio::ssl::stream_base::server, kAsTuple);
  if (!error) co_return true;
  if (!socket_closed_) {  // closed by the watchdog: already counted as a handshake timeout
    refuse(ControlRefusal::TlsHandshakeFailed, error.message());
  }
  co_return false;
}

asio::awaitable<void> ControlSession::read_loop() {
  while (times_.phase == ControlPhase::Open) {
    auto [error, received] = co_await stream_.async_read_some(asio::buffer(read_buffer_), kAsTuple);
    if (error || received == 0) {
      if (times_.phase == ControlPhase::Open) {
        begin_closing("the client closed the connection");
        abort(error ? error.message() : "end of stream");
      }
      break;
    }
    context_.counters.add(context_.counters.bytes_in, received);
    if (times_.phase != ControlPhase::Open) break;
    reader_.feed(std::span<const std::uint8_t>(read_buffer_.data(), received));
    note_partial_frame(context_.clock());
    co_await drain_frames();
  }
}

asio::awaitable<void> ControlSession::drain_frames() {
  std::vector<std::uint8_t> payload;
  while (times_.phase == ControlPhase::Open) {
    switch (reader_.next(payload)) {
      case proto::FrameReader::Status::NeedMore:
        co_return;
      case proto::FrameReader::Status::Refused:
        refuse_frame(*reader_.refusal());
        co_return;
      case proto::FrameReader::Status::Frame:
        break;
    }
    context_.counters.add(context_.counters.frames_in);
    times_.frame_started.reset();
    times_.busy = true;
    const proto::TimeUs handling_from = context_.clock();
    co_await handle(payload);
    times_.busy = false;
    const proto::TimeUs now = context_.clock();
    // The login deadline counts the client's time, not the server's: a registration queued
    // behind a sign-in storm's hashing may take longer than the whole deadline. (Refused
    // requests are answered at once, so nobody stretches it by asking.)
    if (!times_.logged_in) times_.opened_at += now - handling_from;
    times_.last_frame_at = now;
    note_partial_frame(now);
    check_deadlines();
  }
}

asio::awaitable<void> ControlSession::handle(const std::vector<std::uint8_t>& payload) {
  wire::ClientMessage message;
  if (const auto refusal = proto::parse_client_message(payload, message)) {
    refuse_frame(*refusal);
    co_return;
  }
  const std::uint32_t request_id = message.request_id();
  const proto::ClientMessageKind kind = proto::kind_of(message);
  if (!rate_.take(context_.clock())) {
    refuse(ControlRefusal::RateLimited, proto::name(kind));
    reply_error(request_id, wire::RATE_LIMITED,
                "at most " + std::to_string(context_.limits.messages_per_second) +
                    " requests per second (bursts of " +
                    std::to_string(context_.limits.message_burst) + "); this " + proto::name(kind) +
                    " was dropped");
    co_return;
  }
  if (!machine_.admits(kind)) {
    refuse(ControlRefusal::WrongState,
           std::string(proto::name(kind)) + " in " + proto::name(machine_.state()));
    reply_error(request_id, wire::WRONG_STATE,
                std::string(proto::name(kind)) + " is not allowed while the connection is " +
                    proto::name(machine_.state()) +
                    "; allowed: " + admitted_kinds(machine_.state()));
    co_return;
  }
  context_.counters.requested(kind);
  wire::ServerMessage reply = co_await dispatch(message);
  reply.set_request_id(request_id);
  send(reply);
}

void ControlSession::push(wire::ServerMessage message) {
  if (times_.phase != ControlPhase::Open) return;
  message.set_request_id(0);
  if (message.has_match_results() && machine_.state() == proto::ControlState::InMatch) {
    machine_.transition(proto::ControlState::Authenticated, "the match ended");
  }
  send(message);
}

void ControlSession::send(const wire::ServerMessage& message) {
  if (socket_closed_ || times_.phase == ControlPhase::Handshake ||
      times_.phase == ControlPhase::Ended)
    return;
  std::vector<std::uint8_t> frame;
  if (!proto::append_frame(message, frame)) {
    spdlog::warn("control #{}: a reply of {} bytes does not fit a frame; sent an error instead",
                 id_, message.ByteSizeLong());
    wire::ServerMessage error;
    error.set_request_id(message.request_id());
    error.mutable_error()->set_code(wire::INTERNAL);
    error.mutable_error()->set_message("the reply did not fit in one frame");
    if (!proto::append_frame(error, frame)) return;
  }
  if (outbox_bytes_ + frame.size() > context_.limits.max_outbox_bytes) {
    refuse(ControlRefusal::OutboxFull, std::to_string(outbox_bytes_) + " bytes queued");
    begin_closing("the client does not read its replies");
    abort("outbox full");
    return;
  }
  outbox_bytes_ += frame.size();
  outbox_.push_back(std::move(frame));
  context_.counters.add(context_.counters.frames_out);
  outbox_signal_.cancel();
}

void ControlSession::reply_error(std::uint32_t request_id, wire::ErrorCode code,
                                 const std::string& message) {
  wire::ServerMessage reply;
  reply.set_request_id(request_id);
  reply.mutable_error()->set_code(code);
  reply.mutable_error()->set_message(message);
  send(reply);
}

void ControlSession::refuse(ControlRefusal refusal, const std::string& detail) {
  context_.counters.refused(refusal);
  spdlog::debug("control #{} {}: refused ({}): {}", id_, address_, name(refusal), detail);
  if (context_.episodes && is_account_refusal(refusal)) {
    context_.episodes->refuse(name(refusal), host_key_, detail, context_.clock());
  }
}

void ControlSession::refuse_frame(proto::FrameRefusal refusal) {
  const std::string detail = describe_frame_refusal(refusal, reader_.refused_length());
  refuse(control_refusal_of(refusal), detail);
  close(error_code_of(refusal), detail, proto::name(refusal));
}

void ControlSession::close(wire::ErrorCode code, const std::string& message,
                           std::string_view reason) {
  if (times_.phase != ControlPhase::Open) {
    if (times_.phase == ControlPhase::Handshake) abort(reason);
    return;
  }
  reply_error(0, code, message);
  begin_closing(reason);
}

void ControlSession::begin_closing(std::string_view reason) {
  if (times_.phase != ControlPhase::Open) return;
  times_.phase = ControlPhase::Closing;
  times_.closing_since = context_.clock();
  machine_.transition(proto::ControlState::Closed, reason);
  outbox_signal_.cancel();
  check_deadlines();
}

void ControlSession::abort(std::string_view reason) {
  if (socket_closed_) return;
  socket_closed_ = true;
  spdlog::debug("control #{} {}: socket closed ({})", id_, address_, reason);
  boost::system::error_code ignored;
  stream_.lowest_layer().shutdown(asio::ip::tcp::socket::shutdown_both, ignored);
  stream_.lowest_layer().close(ignored);
  outbox_signal_.cancel();
  check_deadlines();
}

asio::awaitable<void> ControlSession::write_loop(std::shared_ptr<ControlSession> self) {
  std::vector<std::uint8_t> batch;
  while (!socket_closed_) {
    if (outbox_.empty()) {
      if (times_.phase != ControlPhase::Open) {
        abort("closed after the final message");
        break;
      }
      outbox_signal_.expires_at(asio::steady_timer::time_point::max());
      co_await outbox_signal_.async_wait(kAsTuple);
      continue;
    }
    batch.clear();
    for (auto& frame : outbox_) batch.insert(batch.end(), frame.begin(), frame.end());
    outbox_.clear();
    outbox_bytes_ = 0;
    times_.write_started = context_.clock();
    check_deadlines();
    auto [error, written] = co_await asio::async_write(stream_, asio::buffer(batch), kAsTuple);
    times_.write_started.reset();
    if (error) {
      abort("write failed: " + error.message());
      break;
    }
    context_.counters.add(context_.counters.bytes_out, written);
  }
  self->task_ended();
}

void ControlSession::task_ended() {
  if (--running_tasks_ > 0) return;
  abort("session ended");
  context_.counters.leave_state(machine_.state());
  context_.counters.add(context_.counters.closed);
  times_.phase = ControlPhase::Ended;
  watchdog_.cancel();
  if (on_ended_) on_ended_(*this);
}

void ControlSession::note_partial_frame(proto::TimeUs now) {
  if (!reader_.inside_frame()) {
    times_.frame_started.reset();
  } else if (!times_.frame_started) {
    times_.frame_started = now;
    check_deadlines();
  }
}

void ControlSession::check_deadlines() {
  watchdog_.cancel();
}

// `self` keeps the session alive for as long as the watchdog runs. A closed socket has no
// deadline left: the reader and writer end on their own.
asio::awaitable<void> ControlSession::watch(std::shared_ptr<ControlSession> self) {
  while (self->times_.phase != ControlPhase::Ended) {
    std::optional<ControlDeadline> next;
    if (!socket_closed_) next = next_deadline(times_, context_.limits);
    const proto::TimeUs now = context_.clock();
    if (next && next->at <= now) {
      expire(next->expiry);  // moves the session on, or closes its socket
      continue;
    }
    if (next) {
      watchdog_.expires_after(std::chrono::microseconds(next->at - now));
    } else {
      watchdog_.expires_at(asio::steady_timer::time_point::max());
    }
    // Fires at the deadline, or earlier when check_deadlines() cancels it: either way, look again.
    co_await watchdog_.async_wait(kAsTuple);
  }
}

void ControlSession::expire(ControlExpiry expiry) {
  const ControlLimits& limits = context_.limits;
  switch (expiry) {
    case ControlExpiry::Handshake:
      refuse(ControlRefusal::HandshakeTimeout,
             "no TLS handshake within " + std::to_string(limits.handshake_timeout_ms) + " ms");
      abort("handshake timeout");
      return;
    case ControlExpiry::Frame: {
      const std::string detail = "a frame must complete within " +
                                 std::to_string(limits.frame_timeout_ms) +
                                 " ms of its first "
                                 "byte; " +
                                 std::to_string(reader_.buffered()) + " bytes came";
      refuse(ControlRefusal::FrameTimeout, detail);
      close(wire::FRAME_TIMEOUT, detail, "frame timeout");
      return;
    }
    case ControlExpiry::Idle: {
      const std::string detail = "no frame for " + std::to_string(limits.idle_timeout_ms) +
                                 " ms; send a ping to keep the connection";
      refuse(ControlRefusal::IdleTimeout, detail);
      close(wire::IDLE_TIMEOUT, detail, "idle timeout");
      return;
    }
    case ControlExpiry::Login: {
      const std::string detail = "not logged in within " + std::to_string(limits.login_timeout_ms) +
                                 " ms of the handshake; log in or resume first";
      refuse(ControlRefusal::LoginTimeout, detail);
      close(wire::LOGIN_TIMEOUT, detail, "login timeout");
      return;
    }
    case ControlExpiry::Write:
      refuse(ControlRefusal::WriteTimeout,
             "a write did not finish within " + std::to_string(limits.write_timeout_ms) + " ms");
      begin_closing("the client does not read");
      abort("write timeout");
      return;
    case ControlExpiry::CloseGrace:
      abort("close grace over");
      return;
  }
}

}  // namespace ricochet::server
