// Small helpers the session's source files share (session*.cpp); not part of its interface.
#pragma once

#include <string>

#include "control/session/session.h"

namespace igms::control::session_detail {

inline int Index(Peer peer) { return static_cast<int>(peer); }

inline std::string ErrorText(const CallError& e) {
  return ErrorCode_Name(e.code) + (e.message.empty() ? "" : ": " + e.message);
}

inline bool LinkGood(devices::LinkState s) {
  return s == devices::CONNECTED || s == devices::REPLAYING;
}

inline ViewerOrientation OrientationOfReading(const devices::ViewerState& r) {
  return {r.yaw_deg(), r.pitch_deg(), r.roll_deg()};
}

}  // namespace igms::control::session_detail
