#pragma once
/// One valid request of each kind a client sends on the control channel, for the tests and the
/// fuzz target of the control client (tests/proto/control_client_test.cpp,
/// tests/fuzz/control_client_fuzz.cpp).

#include <string>

#include "ricochet/proto/control_states.h"
#include "ricochet/wire/control.pb.h"

namespace ricochet::proto::test {

inline wire::ClientMessage request_of(ClientMessageKind kind) {
  wire::ClientMessage m;
  switch (kind) {
    case ClientMessageKind::Register:
      m.mutable_register_account()->set_username("ada");
      m.mutable_register_account()->set_password("lovelace1");
      break;
    case ClientMessageKind::Login:
      m.mutable_login()->set_username("ada");
      m.mutable_login()->set_password("lovelace1");
      break;
    case ClientMessageKind::Resume:
      m.mutable_resume()->set_session_token(std::string(64, 'a'));
      break;
    case ClientMessageKind::ListMatches:
      m.mutable_list_matches();
      break;
    case ClientMessageKind::CreateMatch:
      m.mutable_create_match()->set_name("duel");
      break;
    case ClientMessageKind::JoinMatch:
      m.mutable_join_match()->set_match_id(1);
      break;
    case ClientMessageKind::LeaveMatch:
      m.mutable_leave_match();
      break;
    case ClientMessageKind::Chat:
      m.mutable_chat()->set_text("gl hf");
      break;
    case ClientMessageKind::Ping:
      m.mutable_ping()->set_client_time_us(42);
      break;
    case ClientMessageKind::Logout:
      m.mutable_logout();
      break;
    case ClientMessageKind::FindMatch:
      m.mutable_find_match()->set_mode("ffa");
      break;
  }
  return m;
}

}  // namespace ricochet::proto::test
