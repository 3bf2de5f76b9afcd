#include "ricochet/proto/control_client.h"

#include <algorithm>
#include <climits>

namespace ricochet::proto {
namespace {

using Body = wire::ServerMessage::BodyCase;

/// Whether a reply with `body` answers a request of `kind` (an Error answers any).
bool answers(ClientMessageKind kind, Body body) {
  if (body == wire::ServerMessage::kError) return true;
  switch (kind) {
    case ClientMessageKind::Register:
      return body == wire::ServerMessage::kRegisterAccount;
    case ClientMessageKind::Login:
    case ClientMessageKind::Resume:
      return body == wire::ServerMessage::kSession;
    case ClientMessageKind::ListMatches:
      return body == wire::ServerMessage::kListMatches;
    case ClientMessageKind::CreateMatch:
      return body == wire::ServerMessage::kCreateMatch;
    case ClientMessageKind::JoinMatch:
      return body == wire::ServerMessage::kJoinMatch;
    case ClientMessageKind::LeaveMatch:
      return body == wire::ServerMessage::kLeaveMatch;
    case ClientMessageKind::Chat:
      return body == wire::ServerMessage::kChat;
    case ClientMessageKind::Ping:
      return body == wire::ServerMessage::kPong;
    case ClientMessageKind::Logout:
      return body == wire::ServerMessage::kLogout;
    case ClientMessageKind::FindMatch:
      return body == wire::ServerMessage::kFindMatch;
  }
  return false;
}

/// The body's field name ("pong", "match_results") for messages to people.
std::string body_name(const wire::ServerMessage& message) {
  const auto* field = wire::ServerMessage::descriptor()->FindFieldByNumber(message.body_case());
  return field ? field->name() : "message with no body";
}

std::string describe(const wire::Error& error) {
  const std::string& code = wire::ErrorCode_Name(error.code());
  return (code.empty() ? "error code " + std::to_string(error.code()) : code) + ": " +
         error.message();
}

std::string request_name(std::uint32_t request_id, ClientMessageKind kind) {
  return "request " + std::to_string(request_id) + " (" + name(kind) + ")";
}

}  // namespace

const char* name(RequestRefusal refusal) {
  switch (refusal) {
    case RequestRefusal::WrongState:
      return "wrong_state";
    case RequestRefusal::Closed:
      return "closed";
    case RequestRefusal::NoBody:
      return "no_body";
    case RequestRefusal::TooLarge:
      return "too_large";
  }
  return "unknown";
}

const char* name(ControlCloseReason reason) {
  switch (reason) {
    case ControlCloseReason::Requested:
      return "requested";
    case ControlCloseReason::ConnectionLost:
      return "connection_lost";
    case ControlCloseReason::ServerError:
      return "server_error";
    case ControlCloseReason::RequestTimeout:
      return "request_timeout";
    case ControlCloseReason::FrameOversize:
      return "frame_oversize";
    case ControlCloseReason::FrameEmpty:
      return "frame_empty";
    case ControlCloseReason::Malformed:
      return "malformed";
    case ControlCloseReason::MissingBody:
      return "missing_body";
    case ControlCloseReason::UnknownRequest:
      return "unknown_request";
    case ControlCloseReason::WrongReply:
      return "wrong_reply";
    case ControlCloseReason::UnexpectedMessage:
      return "unexpected_message";
  }
  return "unknown";
}

ControlClient::ControlClient(TimeUs now, ControlClientConfig config)
    : config_(std::move(config)), machine_(config_.on_transition), last_sent_(now) {}

RequestResult ControlClient::request(wire::ClientMessage message, TimeUs now) {
  const auto refuse = [this](RequestRefusal refusal) {
    ++counters_.refused_requests[static_cast<std::size_t>(refusal)];
    return RequestResult{0, refusal};
  };
  if (state() == ControlState::Closed) return refuse(RequestRefusal::Closed);
  if (message.body_case() == wire::ClientMessage::BODY_NOT_SET) {
    return refuse(RequestRefusal::NoBody);
  }
  const ClientMessageKind kind = kind_of(message);
  if (!admits(kind)) return refuse(RequestRefusal::WrongState);
  const std::uint32_t request_id = queue(message, kind, now);
  if (request_id == 0) return refuse(RequestRefusal::TooLarge);
  return {request_id, std::nullopt};
}

std::uint32_t ControlClient::queue(wire::ClientMessage& message, ClientMessageKind kind,
                                   TimeUs now) {
  const std::uint32_t request_id = last_request_id_ == UINT32_MAX ? 1 : last_request_id_ + 1;
  message.set_request_id(request_id);
  const std::size_t before = outbox_.size();
  if (!append_frame(message, outbox_)) return 0;
  last_request_id_ = request_id;
  ++counters_.frames_out;
  counters_.bytes_out += outbox_.size() - before;
  last_sent_ = now;
  pending_.push_back({request_id, kind, now, false});
  return request_id;
}

void ControlClient::receive(std::span<const std::uint8_t> bytes) {
  if (state() == ControlState::Closed) return;
  counters_.bytes_in += bytes.size();
  reader_.feed(bytes);
  while (state() != ControlState::Closed) {
    const FrameReader::Status status = reader_.next(payload_);
    if (status == FrameReader::Status::NeedMore) return;
    if (status == FrameReader::Status::Refused) {
      const bool oversize = reader_.refusal() == FrameRefusal::Oversize;
      return end(oversize ? ControlCloseReason::FrameOversize : ControlCloseReason::FrameEmpty,
                 "the server sent a frame header declaring " +
                     std::to_string(reader_.refused_length()) + " bytes; a frame holds 1.." +
                     std::to_string(kMaxFramePayloadBytes));
    }
    ++counters_.frames_in;
    wire::ServerMessage message;
    if (const auto refusal = parse_server_message(payload_, message)) {
      if (*refusal == FrameRefusal::MissingBody) {
        return end(ControlCloseReason::MissingBody,
                   "the server sent a ServerMessage with no body (request_id " +
                       std::to_string(message.request_id()) + ")");
      }
      return end(ControlCloseReason::Malformed, "the server sent " +
                                                    std::to_string(payload_.size()) +
                                                    " bytes that are not a ServerMessage");
    }
    on_message(message);
  }
}

void ControlClient::on_message(const wire::ServerMessage& message) {
  if (message.request_id() != 0) return on_reply(message);
  switch (message.body_case()) {
    case wire::ServerMessage::kMatchResults:
      if (state() == ControlState::InMatch) {
        machine_.transition(
            ControlState::Authenticated,
            "match " + std::to_string(message.match_results().match_id()) + " ended");
      }
      events_.push_back(ControlMatchResults{message.match_results()});
      return;
    case wire::ServerMessage::kError:
      return end(ControlCloseReason::ServerError,
                 "the server closed the connection: " + describe(message.error()), message.error());
    default:
      return end(ControlCloseReason::UnexpectedMessage,
                 "the server sent a " + body_name(message) +
                     " with request_id 0; only match_results and a closing error come unasked");
  }
}

void ControlClient::on_reply(const wire::ServerMessage& message) {
  const std::uint32_t request_id = message.request_id();
  const auto found = std::find_if(pending_.begin(), pending_.end(),
                                  [&](const Pending& p) { return p.request_id == request_id; });
  if (found == pending_.end()) {
    return end(ControlCloseReason::UnknownRequest,
               "the server answered request " + std::to_string(request_id) +
                   ", which is not pending (" + std::to_string(pending_.size()) + " are)");
  }
  const Pending request = *found;
  if (!answers(request.kind, message.body_case())) {
    return end(ControlCloseReason::WrongReply, "the server answered " +
                                                   request_name(request_id, request.kind) +
                                                   " with a " + body_name(message));
  }
  pending_.erase(found);
  switch (message.body_case()) {
    case wire::ServerMessage::kSession:
      // A resume back in the match its sign-in plays (PROTOCOL.md, resume): InMatch at once.
      if (request.kind == ClientMessageKind::Resume && message.session().match_id() != 0) {
        machine_.transition(ControlState::InMatch,
                            "resumed account " + std::to_string(message.session().account_id()) +
                                " into match " + std::to_string(message.session().match_id()));
      } else {
        machine_.transition(
            ControlState::Authenticated,
            "signed in as account " + std::to_string(message.session().account_id()));
      }
      break;
    case wire::ServerMessage::kJoinMatch:
      machine_.transition(ControlState::InMatch,
                          "joined match " + std::to_string(message.join_match().match_id()));
      break;
    case wire::ServerMessage::kLeaveMatch:
      machine_.transition(ControlState::Authenticated, "left the match");
      break;
    case wire::ServerMessage::kLogout:
      machine_.transition(ControlState::Unauthenticated, "logged out");
      break;
    case wire::ServerMessage::kError:
      if (request.kind == ClientMessageKind::LeaveMatch &&
          message.error().code() == wire::NOT_IN_MATCH) {
        machine_.transition(ControlState::Authenticated, "the match had already let go");
      }
      break;
    default:
      break;
  }
  if (request.keep_alive) return;
  events_.push_back(ControlReply{request_id, request.kind, message});
}

void ControlClient::update(TimeUs now) {
  if (state() == ControlState::Closed) return;
  // pending_ is in the order sent, so its front was sent first.
  if (config_.request_timeout_us > 0 && !pending_.empty() &&
      now - pending_.front().sent_at >= config_.request_timeout_us) {
    const Pending& oldest = pending_.front();
    return end(ControlCloseReason::RequestTimeout,
               request_name(oldest.request_id, oldest.kind) + " had no reply within " +
                   std::to_string(config_.request_timeout_us / kMicrosPerMilli) + " ms");
  }
  if (config_.keep_alive_us > 0 && now - last_sent_ >= config_.keep_alive_us) {
    wire::ClientMessage ping;
    ping.mutable_ping()->set_client_time_us(static_cast<std::uint64_t>(now));
    if (queue(ping, ClientMessageKind::Ping, now) != 0) {
      pending_.back().keep_alive = true;
      ++counters_.keep_alives;
    }
  }
}

std::optional<TimeUs> ControlClient::deadline() const {
  if (state() == ControlState::Closed) return std::nullopt;
  std::optional<TimeUs> due;
  if (config_.request_timeout_us > 0 && !pending_.empty()) {
    due = pending_.front().sent_at + config_.request_timeout_us;
  }
  if (config_.keep_alive_us > 0) {
    const TimeUs keep_alive_due = last_sent_ + config_.keep_alive_us;
    due = due ? std::min(*due, keep_alive_due) : keep_alive_due;
  }
  return due;
}

bool ControlClient::poll_transmit(std::vector<std::uint8_t>& out) {
  if (outbox_.empty()) return false;
  out.swap(outbox_);
  outbox_.clear();
  return true;
}

bool ControlClient::poll_event(ControlEvent& out) {
  if (events_.empty()) return false;
  out = std::move(events_.front());
  events_.pop_front();
  return true;
}

void ControlClient::connection_lost(std::string_view why) {
  end(ControlCloseReason::ConnectionLost, std::string(why));
}

void ControlClient::close() {
  end(ControlCloseReason::Requested, "closed by this client");
}

void ControlClient::end(ControlCloseReason reason, std::string detail, wire::Error server_error) {
  if (state() == ControlState::Closed) return;
  machine_.transition(ControlState::Closed, detail);
  ++counters_.closes[static_cast<std::size_t>(reason)];
  pending_.clear();
  outbox_.clear();
  events_.push_back(ControlClosed{reason, std::move(detail), std::move(server_error)});
}

}  // namespace ricochet::proto
