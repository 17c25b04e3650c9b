#include "device_daemons/joystick/gamepad.h"

#include <linux/joystick.h>

#include <algorithm>
#include <cstring>
#include <set>

namespace igms::devices {

static_assert(sizeof(js_event) == kJsEventSize, "struct js_event is 8 bytes");

bool GamepadMapping::Check(std::string* error) const {
  const auto in_range = [](int i) { return i >= -1 && i <= 255; };
  for (int a : axes) {
    if (!in_range(a)) {
      *error = "gamepad axis " + std::to_string(a) + " is outside -1..255";
      return false;
    }
  }
  std::set<int> used;
  for (int b : buttons) {
    if (!in_range(b) || (b >= 0 && !used.insert(b).second)) {
      *error = "gamepad button " + std::to_string(b) + " is outside -1..255 or used twice";
      return false;
    }
  }
  if (!in_range(trigger) || (trigger >= 0 && used.count(trigger))) {
    *error = "gamepad trigger " + std::to_string(trigger) + " is outside -1..255 or also a button";
    return false;
  }
  return true;
}

GamepadDecoder::GamepadDecoder(GamepadMapping mapping) : mapping_(mapping) {}

void GamepadDecoder::Reset() {
  partial_size_ = 0;
  state_ = JoystickState();
}

size_t GamepadDecoder::Feed(const uint8_t* data, size_t size) {
  size_t applied = 0;
  while (size > 0) {
    const size_t take = std::min(size, kJsEventSize - partial_size_);
    std::memcpy(partial_ + partial_size_, data, take);
    partial_size_ += take;
    data += take;
    size -= take;
    if (partial_size_ < kJsEventSize) break;
    js_event e;
    std::memcpy(&e, partial_, sizeof e);
    partial_size_ = 0;
    Apply(e.time, e.value, e.type, e.number);
    ++applied;
  }
  return applied;
}

void GamepadDecoder::Apply(uint32_t time_ms, int16_t value, uint8_t type, uint8_t number) {
  ++events_;
  last_event_ms_ = time_ms;
  const uint8_t kind = type & ~JS_EVENT_INIT;
  if (kind == JS_EVENT_AXIS) {
    const auto it = std::find(mapping_.axes.begin(), mapping_.axes.end(), number);
    if (it == mapping_.axes.end()) {
      ++ignored_;
      return;
    }
    // One device axis may drive several FlyBox axes.
    for (size_t i = 0; i < mapping_.axes.size(); ++i) {
      if (mapping_.axes[i] != number) continue;
      double v = std::clamp(value / 32767.0, -1.0, 1.0);
      if (mapping_.invert[i]) v = -v;
      switch (i) {
        case GamepadMapping::kX:
          state_.set_x(v);
          break;
        case GamepadMapping::kY:
          state_.set_y(v);
          break;
        case GamepadMapping::kTwist:
          state_.set_twist(v);
          break;
        case GamepadMapping::kLever0:
          state_.set_lever0(v);
          break;
        default:
          state_.set_lever1(v);
          break;
      }
    }
  } else if (kind == JS_EVENT_BUTTON) {
    const bool pressed = value != 0;
    if (number == mapping_.trigger) {
      state_.set_trigger(pressed);
      return;
    }
    const auto it = std::find(mapping_.buttons.begin(), mapping_.buttons.end(), number);
    if (it == mapping_.buttons.end()) {
      ++ignored_;
      return;
    }
    const uint32_t bit = 1u << (it - mapping_.buttons.begin());
    state_.set_buttons(pressed ? state_.buttons() | bit : state_.buttons() & ~bit);
  } else {
    ++ignored_;
  }
}

std::string EncodeJsEvent(uint32_t time_ms, int16_t value, uint8_t type, uint8_t number) {
  js_event e{time_ms, value, type, number};
  return std::string(reinterpret_cast<const char*>(&e), sizeof e);
}

}  // namespace igms::devices
