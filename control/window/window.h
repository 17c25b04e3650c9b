// The operator's window (Cooke, *Interactive Graphical Model Building using Virtual Reality*,
// sections 2.1.1, 2.3 and 2.4): each camera's live video with the geometric database drawn
// over it by the camera's calibrated matrix, in stereo, and the keyboard and mouse as the
// session's devices. GLFW and OpenGL 3.3 core; offscreen (EGL, no display) with the same
// drawing for screenshots where there is no display.
//
// The window belongs to the thread that opens it (GLFW's main thread): that thread polls it,
// hands it frames and draws it. docs/window.md has the key map and the stereo modes.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "common/calibration/calibration_file.h"
#include "control/app/session_view.h"
#include "control/render/stereo.h"
#include "control/window/view_from_session.h"
#include "igms/video.pb.h"

namespace igms::control {

struct WindowOptions {
  render::StereoMode stereo = render::StereoMode::kSideBySide;
  double scale = 1.0;      // window pixels per image pixel
  bool visible = true;     // false: a hidden window (tests)
  bool offscreen = false;  // true: no window at all, EGL (draws for screenshots only)
  std::string title = "IGMS";
  int samples = 4;  // multisampling of the graphics' edges
  bool vsync = true;
  bool help = false;  // the help overlay at start
};

// What the operator did since the last Poll.
struct WindowInput {
  std::vector<Command> commands;      // keys and mouse buttons, in order
  std::optional<PointerDrive> drive;  // while a drive key is held, and once on release
  Eigen::Vector2i offset_move = Eigen::Vector2i::Zero();  // arrows: move the video
  bool quit = false;                                      // Esc or the window closed
  bool screenshot = false;                                // P
};

// Whether a window system is there to open a window on (DISPLAY or WAYLAND_DISPLAY set).
bool DisplayAvailable();

class Window {
 public:
  // Opens the window, sized to the calibration's image size times options.scale (twice as
  // wide side by side). Quad-buffer stereo the driver does not offer falls back to side by
  // side with a message (notice()). An error says why no window opened.
  static Result<std::unique_ptr<Window>> Open(const calibration::StereoCalibration& calibration,
                                              WindowOptions options);
  ~Window();
  Window(const Window&) = delete;
  Window& operator=(const Window&) = delete;

  // Events since the last call; `now_ns` stamps commands and drives (ControlApp::NowNs).
  WindowInput Poll(int64_t now_ns);
  // The video pair to draw behind the graphics (the newest live pair).
  void SetFrame(StereoFrame frame);
  // The video server's state and overlay settings.
  void SetVideo(bool lost, const video::OverlaySettings& overlay);
  // Draws the view and shows it; with `png_path`, also writes what was drawn as a PNG file.
  Result<bool> Draw(const SessionView& view, const std::optional<std::string>& png_path = {});

  render::StereoMode stereo() const;
  // The frame's size in pixels (the framebuffer's).
  geometry::ImageSize frame_size() const;
  // A message for the operator about the setup (the quad-buffer fallback); empty if none.
  const std::string& notice() const;
  // The draw list of the last Draw (tests).
  const render::DrawList& last_list() const;

  struct Impl;

 private:
  explicit Window(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace igms::control
