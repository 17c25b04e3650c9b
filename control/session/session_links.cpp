// The session's health: servers and device daemons coming and going, and bringing the
// platform back to where the operator looks when its link returns.
#include "control/session/cues.h"
#include "control/session/session.h"
#include "control/session/session_internal.h"

namespace igms::control {

using session_detail::Index;
using session_detail::LinkGood;

// ---- health ----

void Session::On(const PeerUpEvent& e) {
  const int i = Index(e.peer);
  if (peer_up_[i]) return;
  peer_up_[i] = true;
  if (mode_ == Mode::kStarting) {
    for (Peer p : kAllPeers)
      if (IsRequired(p) && !peer_up(p)) return;
    return Begin(e.now_ns);
  }
  Notice(NoticeLevel::kInfo, Address(e.peer) + " is back");
  Play(cues::kServerBack);
  switch (e.peer) {
    case Peer::kPlatform:
      PlatformBack("the platform daemon is back");
      break;
    case Peer::kVoice:
      out_.push_back(SetOperatorStateEffect{OperatorStateOf(mode_)});
      break;
    case Peer::kJoystick:
      joystick_.Reset();
      break;
    case Peer::kViewer:
      buttons_.Reset();
      break;
    default:
      break;
  }
}

void Session::On(const PeerDownEvent& e) {
  const int i = Index(e.peer);
  if (!peer_up_[i]) return;
  peer_up_[i] = false;
  Play(cues::kServerLost);  // after marking it down: the sound server's own loss is silent
  Notice(IsRequired(e.peer) ? NoticeLevel::kError : NoticeLevel::kWarning,
         "lost " + Address(e.peer) + (e.why.empty() ? "" : ": " + e.why) + "; reconnecting");
  if (e.peer == Peer::kPlatform) {
    // Its answer will not come; the platform is commanded afresh when it is back.
    orientation_call_ = 0;
    pending_.reset();
    last_sent_.reset();
    // The daemon may still count the lost connection as the holder (a half-dead one is
    // noticed only at its idle timeout): the reconnected session takes control back.
    if (in_control_) take_control_ = true;
    in_control_ = false;
  }
}

void Session::On(const DeviceLinkEvent& e) {
  const int i = Index(e.peer);
  const bool good = LinkGood(e.state);
  if (good == link_good_[i]) return;
  link_good_[i] = good;
  const std::string what = std::string(PeerName(e.peer)) + " device " +
                           devices::LinkState_Name(e.state) +
                           (e.message.empty() ? "" : ": " + e.message);
  if (good) {
    Notice(NoticeLevel::kInfo, what);
    Play(cues::kDeviceBack);
  } else {
    Notice(NoticeLevel::kWarning, what);
    Play(cues::kDeviceLost);
  }
}

void Session::PlatformBack(const std::string& why) {
  // A restarted platform daemon has a new zero: put the platform where the session had it.
  orientation_call_ = 0;
  pending_.reset();
  last_sent_.reset();
  std::optional<PlatformTicks> where;
  if (frozen_) {
    where = to_platform_.TicksOf(frozen_->joints);
  } else if (target_) {
    where = target_;
  }
  if (!where) return;
  target_ = where;
  Notice(NoticeLevel::kWarning, why + ": putting the platform back where the session had it (" +
                                    std::to_string(where->yaw) + ", " +
                                    std::to_string(where->pitch) + ", " +
                                    std::to_string(where->roll) + " ticks)");
  CommandPlatform(*where, true);
}

}  // namespace igms::control
