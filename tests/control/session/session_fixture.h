// The session's test fixture: a session made with the thesis calibration, events sent with
// stamps, and the effects that come out read by kind. The tests are in session_*_test.cpp,
// one file per part of the state machine (Cooke, section 2.4, figure 2-5).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "control/session/cues.h"
#include "control/session/session.h"
#include "tests/control/session/thesis_calibration.h"

namespace igms::control {

inline constexpr int64_t kMs = 1'000'000;

template <class T>
std::vector<T> All(const Effects& effects) {
  std::vector<T> out;
  for (const Effect& e : effects)
    if (const T* t = std::get_if<T>(&e)) out.push_back(*t);
  return out;
}

template <class T>
bool Has(const Effects& effects) {
  return !All<T>(effects).empty();
}

inline std::vector<std::string> Sounds(const Effects& effects) {
  std::vector<std::string> keys;
  for (const auto& s : All<PlaySoundEffect>(effects)) keys.push_back(s.key);
  return keys;
}

inline std::vector<devices::OperatorState> States(const Effects& effects) {
  std::vector<devices::OperatorState> out;
  for (const auto& s : All<SetOperatorStateEffect>(effects)) out.push_back(s.state);
  return out;
}

inline std::string Notices(const Effects& effects) {
  std::string text;
  for (const auto& n : All<NoticeEffect>(effects)) text += n.text + "\n";
  return text;
}

class SessionTest : public ::testing::Test {
 protected:
  void SetUp() override { Make(SessionOptions{}); }

  void Make(const SessionOptions& options) {
    calibration_ = testing::ThesisCalibration();
    std::string why;
    session_ = Session::Make(options, calibration_, &why);
    ASSERT_TRUE(session_) << why;
  }

  Effects Send(const Event& e) { return session_->Handle(e); }

  StartEvent AllUp() {
    StartEvent start;
    int port = 7300;
    for (Peer p : kAllPeers)
      start.peers.push_back({p, "127.0.0.1:" + std::to_string(port++), true, ""});
    start.now_ns = now_;
    return start;
  }

  // Starts with every peer up and lets the welcome play.
  void Start() {
    Send(AllUp());
    now_ += 2000 * kMs;
    Send(TickEvent{now_});
    ASSERT_EQ(session_->mode(), Mode::kVerification);
  }

  Effects Command(CommandKind kind, CommandSource source = CommandSource::kKeyboard) {
    now_ += 10 * kMs;
    return Send(CommandEvent{{kind, source, now_}, now_});
  }

  Effects Viewer(double yaw, double pitch = 0, double roll = 0, bool left = false,
                 bool right = false) {
    now_ += 14 * kMs;
    devices::ViewerState v;
    v.mutable_stamp()->set_sequence(++viewer_sequence_);
    v.mutable_stamp()->set_receive_monotonic_ns(now_);
    v.set_yaw_deg(yaw);
    v.set_pitch_deg(pitch);
    v.set_roll_deg(roll);
    v.set_button_left(left);
    v.set_button_right(right);
    return Send(ViewerReading{v, now_});
  }

  Effects Platform(bool moving, const PlatformTicks& at = {}) {
    now_ += 20 * kMs;
    devices::PlatformState p;
    p.mutable_stamp()->set_sequence(++platform_sequence_);
    p.set_yaw_ticks(at.yaw);
    p.set_pitch_ticks(at.pitch);
    p.set_moving(moving);
    return Send(PlatformReading{p, now_});
  }

  Effects Joystick(double x, double y, double twist, uint32_t buttons, bool trigger,
                   int64_t step_ns = 20 * kMs) {
    now_ += step_ns;
    devices::JoystickState j;
    j.mutable_stamp()->set_sequence(++joystick_sequence_);
    j.mutable_stamp()->set_receive_monotonic_ns(now_);
    j.set_x(x);
    j.set_y(y);
    j.set_twist(twist);
    j.set_buttons(buttons);
    j.set_trigger(trigger);
    return Send(JoystickReading{j, now_});
  }

  Effects Voice(devices::VoiceCommand c, uint64_t sequence) {
    now_ += 10 * kMs;
    devices::VoiceState v;
    v.set_command(c);
    v.mutable_stamp()->set_sequence(sequence);
    return Send(VoiceReading{v, now_});
  }

  video::GrabResponse GrabAt(uint64_t frame_id, double pan_rad) {
    video::GrabResponse g;
    g.set_frame_id(frame_id);
    g.mutable_pose()->add_joints_rad(pan_rad);
    g.mutable_pose()->add_joints_rad(0);
    g.mutable_pose()->add_joints_rad(0);
    g.mutable_pose()->set_from_platform(true);
    return g;
  }

  // Freezes (by keyboard), lets the platform settle and answers the grab at `pan_rad`.
  void FreezeAndGrab(uint64_t frame_id = 41, double pan_rad = 0.0) {
    Command(CommandKind::kFreeze);
    Platform(false);
    const Effects e = Platform(false);
    const auto grabs = All<GrabEffect>(e);
    ASSERT_EQ(grabs.size(), 1u) << Notices(e);
    now_ += 30 * kMs;
    Send(GrabReply{grabs[0].call, GrabAt(frame_id, pan_rad), now_});
    ASSERT_EQ(session_->mode(), Mode::kModelBuilding);
  }

  // Four marks by the trigger, the pointer moved between them.
  void FourMarks() {
    for (int i = 0; i < 4; ++i) {
      Joystick(0, i % 2 ? 1 : -1, i < 2 ? 1 : -1, 0, false);
      Joystick(0, 0, 0, 0, false, 200 * kMs);
      Joystick(0, 0, 0, 0, true);
      Joystick(0, 0, 0, 0, false);
    }
    ASSERT_EQ(session_->marks().size(), 4u);
  }

  // Identifies as a cylinder by voice; the Locate call.
  LocateEffect Identify() {
    Send(VoiceSubscribed{voice_sequence_, now_});
    const Effects e = Voice(devices::VOICE_CYLINDER, ++voice_sequence_);
    const auto calls = All<LocateEffect>(e);
    EXPECT_EQ(calls.size(), 1u) << Notices(e);
    return calls.empty() ? LocateEffect{} : calls[0];
  }

  object::LocateResponse Found(const Eigen::Vector3d& center, double radius = 1.0,
                               double height = 6.0) {
    object::LocateResponse r;
    r.set_found(true);
    r.set_type(object::OBJECT_TYPE_CYLINDER);
    *r.mutable_cylinder()->mutable_center() = ToVec3(center);
    *r.mutable_cylinder()->mutable_axis() = ToVec3(Eigen::Vector3d::UnitZ());
    r.mutable_cylinder()->set_radius(radius);
    r.mutable_cylinder()->set_height(height);
    return r;
  }

  // A model stored at `center` through a whole freeze, marks and identify.
  void BuildModelAt(const Eigen::Vector3d& center) {
    FourMarks();
    const LocateEffect call = Identify();
    now_ += 50 * kMs;
    Send(LocateReply{call.call, Found(center), now_});
    ASSERT_EQ(session_->mode(), Mode::kModelBuilding);
  }

  calibration::StereoCalibration calibration_;
  std::unique_ptr<Session> session_;
  int64_t now_ = 1'000'000'000'000;
  uint64_t viewer_sequence_ = 0, platform_sequence_ = 0, joystick_sequence_ = 0;
  uint64_t voice_sequence_ = 0;
};

}  // namespace igms::control
