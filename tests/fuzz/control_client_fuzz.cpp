// libFuzzer target for the control channel's client end (proto::ControlClient): the input is the
// byte stream a server might send over TLS, fed in chunks whose size comes from the input's first
// byte. The client starts with four requests pipelined (register 1, login 2, resume 3, ping 4,
// the pipeline control_client_seeds answers); after each chunk the clock moves on a second, the
// client updates, and it is asked for one more request (the kinds in turn). Nothing may crash,
// and whatever the bytes:
//   - the client closes at most once, with one ControlClosed that is its last event;
//   - every reply answers a pending request, once, with that request's kind;
//   - a request is queued exactly when the state table admits its kind (refused once Closed);
//   - what it queues to send is whole, valid ClientMessage frames.

#include <google/protobuf/stubs/logging.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "../proto/control_requests.h"
#include "fuzz_check.h"
#include "ricochet/proto/control_client.h"

namespace {

using namespace ricochet::proto;
using ricochet::proto::test::request_of;
using ricochet::wire::ClientMessage;

using ricochet::fuzz::check;

struct Run {
  ControlClient client{0};
  std::map<std::uint32_t, ClientMessageKind> pending;  ///< as this harness counts them
  bool closed = false;
  std::vector<std::uint8_t> sent;

  void ask(ClientMessageKind kind, TimeUs now) {
    const ControlState state = client.state();
    const RequestResult result = client.request(request_of(kind), now);
    if (state == ControlState::Closed) {
      check(result.refusal == RequestRefusal::Closed);
    } else if (!admits(state, kind)) {
      check(result.refusal == RequestRefusal::WrongState);
    } else {
      check(static_cast<bool>(result) && result.request_id != 0);
      check(pending.emplace(result.request_id, kind).second);
    }
  }

  void drain() {
    ControlEvent event;
    while (client.poll_event(event)) {
      check(!closed);  // nothing after ControlClosed
      if (const auto* reply = std::get_if<ControlReply>(&event)) {
        const auto found = pending.find(reply->request_id);
        check(found != pending.end() && found->second == reply->kind);
        check(reply->message.request_id() == reply->request_id);
        pending.erase(found);
      } else if (const auto* closed_event = std::get_if<ControlClosed>(&event)) {
        check(client.state() == ControlState::Closed);
        check(!closed_event->detail.empty());
        closed = true;
      }
    }
    check(closed == (client.state() == ControlState::Closed));
    std::uint64_t closes = 0;
    for (std::uint64_t count : client.counters().closes) closes += count;
    check(closes == (closed ? 1u : 0u));
    // Keep-alive pings are pending in the client but not here.
    check(closed || client.pending() >= pending.size());
    std::vector<std::uint8_t> bytes;
    if (client.poll_transmit(bytes)) {
      check(!closed);
      sent.insert(sent.end(), bytes.begin(), bytes.end());
    }
  }

  void check_sent() const {
    FrameReader reader;
    reader.feed(sent);
    std::vector<std::uint8_t> payload;
    while (true) {
      const FrameReader::Status status = reader.next(payload);
      check(status != FrameReader::Status::Refused);
      if (status == FrameReader::Status::NeedMore) break;
      ClientMessage message;
      check(!parse_client_message(payload, message));
      check(message.request_id() != 0);
    }
    check(!reader.inside_frame());
  }
};

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  google::protobuf::SetLogHandler(nullptr);  // invalid UTF-8 is expected here, not news
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  // First byte: the chunk size pattern (1..256 bytes per receive).
  const std::size_t chunk = std::size_t{data[0]} + 1;
  const std::span<const std::uint8_t> stream(data + 1, size - 1);
  Run run;
  for (ClientMessageKind kind : {ClientMessageKind::Register, ClientMessageKind::Login,
                                 ClientMessageKind::Resume, ClientMessageKind::Ping}) {
    run.ask(kind, 0);
  }
  run.drain();
  TimeUs now = 0;
  std::size_t turn = 0;
  for (std::size_t at = 0; at < stream.size(); at += chunk) {
    run.client.receive(stream.subspan(at, std::min(chunk, stream.size() - at)));
    run.drain();
    now += kMicrosPerSecond;
    run.client.update(now);
    run.drain();
    run.ask(static_cast<ClientMessageKind>(turn++ % kClientMessageKindCount), now);
    run.drain();
  }
  run.check_sent();
  return 0;
}
