#include "control/app/session_view.h"

#include <algorithm>

namespace igms::control {

size_t SessionView::present_models() const {
  return static_cast<size_t>(std::count_if(models.begin(), models.end(),
                                           [](const SessionModel& m) { return !m.removed; }));
}

void ViewBoard::Publish(SessionView view) {
  {
    std::lock_guard lock(mutex_);
    view_ = std::move(view);
  }
  changed_.notify_all();
}

SessionView ViewBoard::Get() const {
  std::lock_guard lock(mutex_);
  return view_;
}

bool ViewBoard::WaitFor(const std::function<bool(const SessionView&)>& pred,
                        std::chrono::milliseconds timeout, SessionView* last) const {
  std::unique_lock lock(mutex_);
  const bool met = changed_.wait_for(lock, timeout, [&] { return pred(view_); });
  if (last) *last = view_;
  return met;
}

}  // namespace igms::control
