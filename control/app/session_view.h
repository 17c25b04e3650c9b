// What the operator's display shows of the session, as a value: the app publishes one after
// every event it hands the session, and the window and the script player read it from their
// own threads. Reading it never blocks the session for longer than a copy.
#pragma once

#include <Eigen/Core>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "control/session/session.h"

namespace igms::control {

struct NoticeLine {
  NoticeLevel level = NoticeLevel::kInfo;
  std::string text;
  uint64_t number = 0;  // counts every notice of the run, from 1
};

struct SessionView {
  uint64_t version = 0;  // counts the events handled
  Mode mode = Mode::kStarting;
  bool peer_up[8] = {};
  bool wireframe = false;
  std::optional<ViewerOrientation> viewer;
  std::optional<Eigen::Vector3d> pointer;
  std::vector<Eigen::Vector3d> marks;
  std::vector<SessionModel> models;  // removed ones included, flagged
  std::optional<FrozenView> frozen;
  double range = 0.0;
  // The daemon's stamp (receive_monotonic_ns: CLOCK_MONOTONIC when its serial bytes came)
  // of the newest joystick reading the session has handled: the latency figures' probe.
  int64_t joystick_stamp_ns = 0;
  uint64_t ranges_taken = 0;  // replies to RangerService.Range, echo or not
  std::string failure_detail;
  uint64_t locates_failed = 0;
  uint64_t models_stored = 0;  // committed to the database by this run
  std::optional<PlatformTicks> platform_target;
  // The grammar the voice daemon last acknowledged (VoiceService.SetOperatorState): a word
  // said before it follows the mode is judged by the old grammar.
  std::optional<devices::OperatorState> voice_grammar;
  std::deque<NoticeLine> notices;  // the newest kKeptNotices
  std::optional<int> exit_code;    // set once the session has ended

  static constexpr size_t kKeptNotices = 64;
  size_t present_models() const;
};

// The newest SessionView, and a way to wait until it satisfies a condition.
class ViewBoard {
 public:
  void Publish(SessionView view);
  SessionView Get() const;
  // Waits until `pred(view)` holds or `timeout` passes; the last view seen either way.
  bool WaitFor(const std::function<bool(const SessionView&)>& pred,
               std::chrono::milliseconds timeout, SessionView* last = nullptr) const;

 private:
  mutable std::mutex mutex_;
  mutable std::condition_variable changed_;
  SessionView view_;
};

}  // namespace igms::control
