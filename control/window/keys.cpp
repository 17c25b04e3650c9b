#include "control/window/keys.h"

#include <GLFW/glfw3.h>

namespace igms::control {

const int kDriveKeys[6] = {GLFW_KEY_L, GLFW_KEY_J,       GLFW_KEY_I,
                           GLFW_KEY_K, GLFW_KEY_PAGE_UP, GLFW_KEY_PAGE_DOWN};

namespace {
KeyAction Cmd(CommandKind kind) {
  KeyAction a;
  a.action = WindowAction::kCommand;
  a.command = kind;
  return a;
}
KeyAction Offset(int du, int dv) {
  KeyAction a;
  a.action = WindowAction::kOffset;
  a.offset = {du, dv};
  return a;
}
KeyAction Act(WindowAction action) {
  KeyAction a;
  a.action = action;
  return a;
}
}  // namespace

KeyAction MapKey(int key, int mods) {
  const int step = (mods & GLFW_MOD_SHIFT) ? 10 : 1;
  switch (key) {
    case GLFW_KEY_F:
      return Cmd(CommandKind::kFreeze);
    case GLFW_KEY_U:
      return Cmd(CommandKind::kUnfreeze);
    case GLFW_KEY_R:
      return Cmd(CommandKind::kRange);
    case GLFW_KEY_SPACE:
    case GLFW_KEY_ENTER:
    case GLFW_KEY_KP_ENTER:
      return Cmd(CommandKind::kMark);
    case GLFW_KEY_BACKSPACE:
      return Cmd(CommandKind::kUnmark);
    case GLFW_KEY_X:
      return Cmd(CommandKind::kRemovePoints);
    case GLFW_KEY_B:
      return Cmd(CommandKind::kIdentifyBox);
    case GLFW_KEY_C:
      return Cmd(CommandKind::kIdentifyCylinder);
    case GLFW_KEY_W:
      return Cmd(CommandKind::kToggleWireframe);
    case GLFW_KEY_DELETE:
      return Cmd(CommandKind::kRemoveModel);
    case GLFW_KEY_Z:
      return Cmd(CommandKind::kUndo);
    case GLFW_KEY_H:
    case GLFW_KEY_F1:
      return Act(WindowAction::kToggleHelp);
    case GLFW_KEY_P:
    case GLFW_KEY_PRINT_SCREEN:
      return Act(WindowAction::kScreenshot);
    case GLFW_KEY_TAB:
      return Act(WindowAction::kNextStereo);
    case GLFW_KEY_ESCAPE:
      return Act(WindowAction::kQuit);
    case GLFW_KEY_LEFT:
      return Offset(-step, 0);
    case GLFW_KEY_RIGHT:
      return Offset(step, 0);
    case GLFW_KEY_UP:
      return Offset(0, -step);
    case GLFW_KEY_DOWN:
      return Offset(0, step);
    default:
      return {};
  }
}

KeyAction MapMouseButton(int button) {
  KeyAction a;
  if (button == GLFW_MOUSE_BUTTON_LEFT) a = Cmd(CommandKind::kMark);
  if (button == GLFW_MOUSE_BUTTON_RIGHT) a = Cmd(CommandKind::kUnmark);
  a.source = CommandSource::kMouse;
  return a;
}

}  // namespace igms::control
