#include "device_daemons/platform/platform_control.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <ctime>

namespace igms::devices {
namespace {

constexpr const char* kHowToTake =
    "set take_control in the request to take it over (igms-control --take-control, "
    "igmsctl call ... --take-control)";

std::string UtcNow() {
  const std::time_t now = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&now, &tm);
  char text[16];
  std::strftime(text, sizeof text, "%H:%M:%S UTC", &tm);
  return text;
}

}  // namespace

void PlatformControl::ForgetClosedLocked() const {
  if (holder_ && !holder_->connected()) {
    spdlog::info("platform: {} disconnected; control of the platform is free", holder_->Describe());
    holder_.reset();
  }
  std::erase_if(displaced_, [](const Displaced& d) { return !d.client.connected(); });
}

net::Status PlatformControl::Claim(const net::Caller& caller, bool take) {
  std::lock_guard lock(mutex_);
  ForgetClosedLocked();
  if (holder_ && holder_->SameConnection(caller)) return net::Status::Ok();
  if (!holder_ || take) {
    if (holder_) {
      spdlog::warn("platform: {} took control from {}", caller.Describe(), holder_->Describe());
      displaced_.push_back({*holder_, caller.Describe(), UtcNow()});
    } else {
      spdlog::info("platform: {} has control", caller.Describe());
    }
    std::erase_if(displaced_, [&](const Displaced& d) { return d.client.SameConnection(caller); });
    holder_ = caller;
    return net::Status::Ok();
  }
  const auto was = std::find_if(displaced_.begin(), displaced_.end(), [&](const Displaced& d) {
    return d.client.SameConnection(caller);
  });
  std::string message;
  if (was != displaced_.end()) {
    message = was->by + " took control of the platform from this client at " + was->when;
    if (was->by != holder_->Describe()) message += "; " + holder_->Describe() + " has it now";
  } else {
    message = "the platform is controlled by " + holder_->Describe();
  }
  return net::Status::Error(igms::PERMISSION_DENIED, message + "; " + kHowToTake);
}

std::string PlatformControl::Holder() const {
  std::lock_guard lock(mutex_);
  ForgetClosedLocked();
  return holder_ ? holder_->Describe() : "";
}

}  // namespace igms::devices
