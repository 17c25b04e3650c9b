#include "control/window/window.h"

// GLFW after the GL prototypes, and told not to include a GL header of its own.
#include "control/render/gl.h"
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdlib>
#include <deque>
#include <map>

#include "common/base/environment.h"
#include "control/render/offscreen.h"
#include "control/window/keys.h"

namespace igms::control {
namespace {

// GLFW is process-wide: initialised with the first window, ended with the last.
int glfw_users = 0;

void OnGlfwError(int code, const char* text) { spdlog::debug("GLFW {}: {}", code, text); }

constexpr render::StereoMode kCycle[] = {render::StereoMode::kSideBySide,
                                         render::StereoMode::kAnaglyph, render::StereoMode::kLeft,
                                         render::StereoMode::kRight};

}  // namespace

bool DisplayAvailable() {
  return !EnvironmentVariable("DISPLAY").value_or("").empty() ||
         !EnvironmentVariable("WAYLAND_DISPLAY").value_or("").empty();
}

struct Window::Impl {
  calibration::StereoCalibration calibration;
  WindowOptions options;
  GLFWwindow* window = nullptr;
  std::unique_ptr<render::OffscreenContext> offscreen;
  std::unique_ptr<render::RenderTarget> target;
  std::unique_ptr<render::Renderer> renderer;
  render::StereoMode stereo = render::StereoMode::kSideBySide;
  bool quad_buffer = false;
  std::string notice;
  ViewExtras extras;
  std::map<uint64_t, cv::Mat> textures;  // boxes' patches, decoded once
  render::DrawList last;

  // Events from GLFW's callbacks, taken by Poll.
  std::deque<KeyAction> actions;
  double scroll = 0;
  int64_t scroll_until_ns = 0;
  double scroll_direction = 0;
  bool drive_was_moving = false;

  ~Impl() {
    if (window) glfwMakeContextCurrent(window);
    if (offscreen) offscreen->MakeCurrent();
    renderer.reset();
    target.reset();
    offscreen.reset();
    if (window) {
      glfwDestroyWindow(window);
      if (--glfw_users == 0) glfwTerminate();
    }
  }

  geometry::ImageSize EyeSize() const { return calibration.left.image_size; }

  geometry::ImageSize WindowSize() const {
    const auto frame =
        render::FrameSize(quad_buffer ? render::StereoMode::kLeft : stereo, EyeSize());
    return {static_cast<int>(std::lround(frame.width * options.scale)),
            static_cast<int>(std::lround(frame.height * options.scale))};
  }

  geometry::ImageSize FramebufferSize() const {
    if (target) return {target->width(), target->height()};
    int w = 0, h = 0;
    glfwGetFramebufferSize(window, &w, &h);
    return {w, h};
  }

  static Impl* Of(GLFWwindow* w) { return static_cast<Impl*>(glfwGetWindowUserPointer(w)); }

  void InstallCallbacks() {
    glfwSetWindowUserPointer(window, this);
    glfwSetKeyCallback(window, [](GLFWwindow* w, int key, int, int action, int mods) {
      if (action == GLFW_PRESS || (action == GLFW_REPEAT && key >= GLFW_KEY_RIGHT &&
                                   key <= GLFW_KEY_UP)) {  // arrows repeat
        const KeyAction a = MapKey(key, mods);
        if (a.action != WindowAction::kNone) Of(w)->actions.push_back(a);
      }
    });
    glfwSetMouseButtonCallback(window, [](GLFWwindow* w, int button, int action, int) {
      if (action != GLFW_PRESS) return;
      const KeyAction a = MapMouseButton(button);
      if (a.action != WindowAction::kNone) Of(w)->actions.push_back(a);
    });
    glfwSetScrollCallback(window, [](GLFWwindow* w, double, double dy) { Of(w)->scroll += dy; });
  }

  void Resize() {
    if (!window) {
      const auto size = WindowSize();
      auto t = render::RenderTarget::Make(size.width, size.height, options.samples);
      if (t.ok()) target = std::move(*t);
      return;
    }
    const auto size = WindowSize();
    glfwSetWindowSize(window, size.width, size.height);
  }
};

Result<std::unique_ptr<Window>> Window::Open(const calibration::StereoCalibration& calibration,
                                             WindowOptions options) {
  auto impl = std::make_unique<Impl>();
  impl->calibration = calibration;
  impl->options = options;
  impl->stereo = options.stereo;
  impl->extras.show_help = options.help;
  impl->extras.textures = &impl->textures;
  if (!(options.scale > 0)) return ErrorMessage{"the window's scale must be positive"};

  if (options.offscreen) {
    auto context = render::OffscreenContext::Make();
    if (!context.ok()) return ErrorMessage{"offscreen rendering: " + context.error()};
    impl->offscreen = std::move(*context);
    if (impl->stereo == render::StereoMode::kQuadBuffer) {
      impl->notice = "quad-buffer stereo needs a window: side by side offscreen";
      impl->stereo = render::StereoMode::kSideBySide;
    }
    const auto size = impl->WindowSize();
    auto target = render::RenderTarget::Make(size.width, size.height, options.samples);
    if (!target.ok()) return ErrorMessage{target.error()};
    impl->target = std::move(*target);
  } else {
    glfwSetErrorCallback(OnGlfwError);
    if (glfw_users == 0 && !glfwInit()) {
      return ErrorMessage{"GLFW could not start (no display? DISPLAY is " +
                          EnvironmentVariable("DISPLAY").value_or("unset") +
                          "): use --no-window, or run under xvfb-run"};
    }
    ++glfw_users;
    auto hints = [&](bool stereo) {
      glfwDefaultWindowHints();
      glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
      glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
      glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
      glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
      glfwWindowHint(GLFW_SAMPLES, options.samples > 1 ? options.samples : 0);
      glfwWindowHint(GLFW_VISIBLE, options.visible ? GLFW_TRUE : GLFW_FALSE);
      glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
      glfwWindowHint(GLFW_STEREO, stereo ? GLFW_TRUE : GLFW_FALSE);
    };
    if (impl->stereo == render::StereoMode::kQuadBuffer) {
      impl->quad_buffer = true;
      hints(true);
      const auto size = impl->WindowSize();
      impl->window =
          glfwCreateWindow(size.width, size.height, options.title.c_str(), nullptr, nullptr);
      if (!impl->window) {
        impl->quad_buffer = false;
        impl->stereo = render::StereoMode::kSideBySide;
        impl->notice =
            "quad-buffer stereo: the OpenGL driver offers no stereo visual; side by side instead";
        spdlog::warn("{}", impl->notice);
      }
    }
    if (!impl->window) {
      hints(false);
      const auto size = impl->WindowSize();
      impl->window =
          glfwCreateWindow(size.width, size.height, options.title.c_str(), nullptr, nullptr);
    }
    if (!impl->window) {
      if (--glfw_users == 0) glfwTerminate();
      return ErrorMessage{"no OpenGL 3.3 core window could be opened"};
    }
    glfwMakeContextCurrent(impl->window);
    glfwSwapInterval(options.vsync ? 1 : 0);
    impl->InstallCallbacks();
  }
  auto renderer = render::Renderer::Make();
  if (!renderer.ok()) return ErrorMessage{renderer.error()};
  impl->renderer = std::move(*renderer);
  spdlog::info("window: {} stereo, {}x{}, {}", render::StereoModeName(impl->stereo),
               impl->FramebufferSize().width, impl->FramebufferSize().height,
               reinterpret_cast<const char*>(glGetString(GL_RENDERER)));
  return std::unique_ptr<Window>(new Window(std::move(impl)));
}

Window::Window(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Window::~Window() = default;

WindowInput Window::Poll(int64_t now_ns) {
  WindowInput in;
  Impl& d = *impl_;
  if (!d.window) return in;
  glfwPollEvents();
  in.quit = glfwWindowShouldClose(d.window);
  while (!d.actions.empty()) {
    const KeyAction a = d.actions.front();
    d.actions.pop_front();
    switch (a.action) {
      case WindowAction::kCommand: {
        in.commands.push_back(Command{a.command, a.source, now_ns});
        break;
      }
      case WindowAction::kQuit:
        in.quit = true;
        break;
      case WindowAction::kToggleHelp:
        d.extras.show_help = !d.extras.show_help;
        break;
      case WindowAction::kScreenshot:
        in.screenshot = true;
        break;
      case WindowAction::kNextStereo: {
        if (d.quad_buffer) break;
        size_t i = 0;
        while (i < std::size(kCycle) && kCycle[i] != d.stereo) ++i;
        d.stereo = kCycle[(i + 1) % std::size(kCycle)];
        d.Resize();
        break;
      }
      case WindowAction::kOffset:
        in.offset_move += a.offset;
        break;
      case WindowAction::kNone:
        break;
    }
  }
  // The wheel drives the pointer in depth: a tenth of a second at full deflection a notch.
  if (d.scroll != 0) {
    d.scroll_direction = d.scroll > 0 ? 1.0 : -1.0;
    d.scroll_until_ns = now_ns + static_cast<int64_t>(std::abs(d.scroll) * 100'000'000);
    d.scroll = 0;
  }
  const bool slow = glfwGetKey(d.window, GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
                    glfwGetKey(d.window, GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
  PointerDrive drive =
      DriveFromKeys([&](int key) { return glfwGetKey(d.window, key) == GLFW_PRESS; }, slow, now_ns);
  if (now_ns < d.scroll_until_ns) drive.forward += d.scroll_direction;
  const bool moving = drive.right != 0 || drive.up != 0 || drive.forward != 0;
  if (moving || d.drive_was_moving) in.drive = drive;
  d.drive_was_moving = moving;
  return in;
}

void Window::SetFrame(StereoFrame frame) { impl_->extras.frame = std::move(frame); }

void Window::SetVideo(bool lost, const video::OverlaySettings& overlay) {
  impl_->extras.video_lost = lost;
  impl_->extras.key_level = overlay.key_level();
  impl_->extras.video_offset = {overlay.u_offset_px(), overlay.v_offset_px()};
}

Result<bool> Window::Draw(const SessionView& view, const std::optional<std::string>& png_path) {
  Impl& d = *impl_;
  if (d.window) glfwMakeContextCurrent(d.window);
  if (d.offscreen) d.offscreen->MakeCurrent();
  d.extras.stereo = std::string(
      render::StereoModeName(d.quad_buffer ? render::StereoMode::kQuadBuffer : d.stereo));
  d.last = ViewFromSession(view, d.calibration, d.extras);
  if (!d.notice.empty()) d.last.hud.push_back({d.notice, render::HudLevel::kWarning});
  const auto size = d.FramebufferSize();
  if (size.width <= 0 || size.height <= 0) return true;  // minimised
  if (d.target) {
    d.target->Bind();
    render::DrawStereo(*d.renderer, d.last, d.stereo, size.width, size.height);
  } else if (d.quad_buffer) {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDrawBuffer(GL_BACK_LEFT);
    d.renderer->Clear(size.width, size.height);
    d.renderer->DrawEye(d.last, 0, {0, 0, size.width, size.height});
    glDrawBuffer(GL_BACK_RIGHT);
    d.renderer->Clear(size.width, size.height);
    d.renderer->DrawEye(d.last, 1, {0, 0, size.width, size.height});
    glDrawBuffer(GL_BACK);
  } else {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    render::DrawStereo(*d.renderer, d.last, d.stereo, size.width, size.height);
  }
  Result<bool> saved = true;
  if (png_path) {
    cv::Mat pixels;
    if (d.target) {
      pixels = d.target->Read();
    } else {
      glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
      glReadBuffer(d.quad_buffer ? GL_BACK_LEFT : GL_BACK);
      pixels = render::ReadPixels(size.width, size.height);
    }
    saved = render::SavePng(pixels, *png_path);
  }
  if (d.window) glfwSwapBuffers(d.window);
  // Offscreen, the frame is drawn when Draw returns, as a window's is once swapped (the
  // benchmarks time frames by it; a screenshot has waited for its pixels already).
  if (d.target && !png_path) glFinish();
  return saved;
}

render::StereoMode Window::stereo() const {
  return impl_->quad_buffer ? render::StereoMode::kQuadBuffer : impl_->stereo;
}

geometry::ImageSize Window::frame_size() const { return impl_->FramebufferSize(); }
const std::string& Window::notice() const { return impl_->notice; }
const render::DrawList& Window::last_list() const { return impl_->last; }

}  // namespace igms::control
