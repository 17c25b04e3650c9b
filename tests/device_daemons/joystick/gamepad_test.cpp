#include "device_daemons/joystick/gamepad.h"

#include <gtest/gtest.h>
#include <linux/joystick.h>

namespace igms::devices {
namespace {

void Send(GamepadDecoder& d, const std::string& bytes) {
  d.Feed(reinterpret_cast<const uint8_t*>(bytes.data()), bytes.size());
}

TEST(Gamepad, DefaultMappingGivesTheFlyBoxReading) {
  GamepadDecoder d;
  // The state reported on opening, then changes.
  std::string init;
  for (uint8_t axis = 0; axis < 6; ++axis)
    init += EncodeJsEvent(10, 0, JS_EVENT_AXIS | JS_EVENT_INIT, axis);
  for (uint8_t b = 0; b < 11; ++b) init += EncodeJsEvent(10, 0, JS_EVENT_BUTTON | JS_EVENT_INIT, b);
  Send(d, init);
  EXPECT_EQ(d.events(), 17u);
  EXPECT_EQ(d.ignored(), 3u);  // axis 4, buttons 9 and 10: not in the default mapping
  Send(d, EncodeJsEvent(20, -32767, JS_EVENT_AXIS, 1));  // left stick pushed away
  Send(d, EncodeJsEvent(21, 16384, JS_EVENT_AXIS, 0));   // and half right
  Send(d, EncodeJsEvent(22, -32767, JS_EVENT_AXIS, 3));  // right stick left
  Send(d, EncodeJsEvent(23, 32767, JS_EVENT_AXIS, 2));   // left analogue trigger
  Send(d, EncodeJsEvent(24, -32768, JS_EVENT_AXIS, 5));  // beyond -32767: clamped
  Send(d, EncodeJsEvent(25, 1, JS_EVENT_BUTTON, 0));     // trigger
  Send(d, EncodeJsEvent(26, 1, JS_EVENT_BUTTON, 3));     // FlyBox button 3
  Send(d, EncodeJsEvent(27, 1, JS_EVENT_BUTTON, 8));     // FlyBox button 8
  const JoystickState& s = d.state();
  EXPECT_DOUBLE_EQ(s.x(), 1.0);
  EXPECT_NEAR(s.y(), 0.5, 1e-4);
  EXPECT_DOUBLE_EQ(s.twist(), -1.0);
  EXPECT_DOUBLE_EQ(s.lever0(), 1.0);
  EXPECT_DOUBLE_EQ(s.lever1(), -1.0);
  EXPECT_TRUE(s.trigger());
  EXPECT_EQ(s.buttons(), (1u << 2) | (1u << 7));
  EXPECT_EQ(d.last_event_ms(), 27u);
  Send(d, EncodeJsEvent(30, 0, JS_EVENT_BUTTON, 3));
  EXPECT_EQ(d.state().buttons(), 1u << 7);
  // Inputs the mapping does not use, and unknown types, are counted and change nothing.
  Send(d, EncodeJsEvent(31, 1, JS_EVENT_BUTTON, 12));
  Send(d, EncodeJsEvent(32, 500, JS_EVENT_AXIS, 7));
  Send(d, EncodeJsEvent(33, 1, 0x40, 0));
  EXPECT_EQ(d.ignored(), 6u);
  EXPECT_EQ(d.state().buttons(), 1u << 7);
}

TEST(Gamepad, RecordsSplitAcrossReadsAndResets) {
  GamepadDecoder d;
  const std::string e =
      EncodeJsEvent(5, 32767, JS_EVENT_AXIS, 0) + EncodeJsEvent(6, 1, JS_EVENT_BUTTON, 1);
  for (char c : e) Send(d, std::string(1, c));  // byte by byte
  EXPECT_EQ(d.events(), 2u);
  EXPECT_DOUBLE_EQ(d.state().y(), 1.0);
  EXPECT_EQ(d.state().buttons(), 1u);
  Send(d, e.substr(0, 5));  // half a record, then the device is reopened
  d.Reset();
  EXPECT_EQ(d.state().buttons(), 0u);
  Send(d, EncodeJsEvent(7, 1, JS_EVENT_BUTTON, 2));
  EXPECT_EQ(d.state().buttons(), 2u);
}

TEST(Gamepad, MappingIsOverridableAndChecked) {
  GamepadMapping m;
  m.axes = {0, -1, -1, -1, 0};  // one device axis drives x and lever1; the rest unmapped
  m.invert = {false, false, false, false, true};
  m.trigger = 5;
  m.buttons = {0, 1, 2, 3, 4, -1, -1, -1};
  std::string error;
  ASSERT_TRUE(m.Check(&error)) << error;
  GamepadDecoder d(m);
  Send(d, EncodeJsEvent(1, 16384, JS_EVENT_AXIS, 0) + EncodeJsEvent(2, 1, JS_EVENT_BUTTON, 5) +
              EncodeJsEvent(3, 1, JS_EVENT_BUTTON, 0) + EncodeJsEvent(4, 500, JS_EVENT_AXIS, 1));
  EXPECT_NEAR(d.state().x(), 0.5, 1e-4);
  EXPECT_NEAR(d.state().lever1(), -0.5, 1e-4);
  EXPECT_DOUBLE_EQ(d.state().y(), 0.0);
  EXPECT_TRUE(d.state().trigger());
  EXPECT_EQ(d.state().buttons(), 1u);
  m.trigger = 2;  // also button 3
  EXPECT_FALSE(m.Check(&error));
  EXPECT_NE(error.find("trigger"), std::string::npos);
  m.trigger = 5;
  m.buttons[5] = 1;  // used twice
  EXPECT_FALSE(m.Check(&error));
  m.buttons[5] = -1;
  m.axes[0] = 256;
  EXPECT_FALSE(m.Check(&error));
}

}  // namespace
}  // namespace igms::devices
