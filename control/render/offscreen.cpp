#include "control/render/offscreen.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "control/render/gl.h"

namespace igms::control::render {
namespace {

std::string EglError(const char* what) {
  char code[16];
  std::snprintf(code, sizeof(code), "0x%04x", eglGetError());
  return std::string(what) + " failed (EGL error " + code + ")";
}

}  // namespace

struct OffscreenContext::Impl {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLContext context = EGL_NO_CONTEXT;
  ~Impl() {
    if (display != EGL_NO_DISPLAY) {
      eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      if (context != EGL_NO_CONTEXT) eglDestroyContext(display, context);
      eglTerminate(display);
    }
  }
};

Result<std::unique_ptr<OffscreenContext>> OffscreenContext::Make() {
  auto impl = std::make_unique<Impl>();
  // The surfaceless platform needs no X server, no GPU and no device file.
  auto get_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_display) return ErrorMessage{"EGL has no eglGetPlatformDisplayEXT"};
  impl->display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (impl->display == EGL_NO_DISPLAY) {
    return ErrorMessage{EglError("eglGetPlatformDisplayEXT(surfaceless)")};
  }
  EGLint major = 0, minor = 0;
  if (!eglInitialize(impl->display, &major, &minor)) {
    impl->display = EGL_NO_DISPLAY;
    return ErrorMessage{EglError("eglInitialize")};
  }
  if (!eglBindAPI(EGL_OPENGL_API)) return ErrorMessage{EglError("eglBindAPI(OpenGL)")};
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION,
                               3,
                               EGL_CONTEXT_MINOR_VERSION,
                               3,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                               EGL_NONE};
  // No config: the context draws only into framebuffer objects (EGL_KHR_no_config_context).
  impl->context = eglCreateContext(impl->display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
  if (impl->context == EGL_NO_CONTEXT) {
    return ErrorMessage{EglError("eglCreateContext(OpenGL 3.3 core)")};
  }
  if (!eglMakeCurrent(impl->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl->context)) {
    return ErrorMessage{EglError("eglMakeCurrent")};
  }
  return std::unique_ptr<OffscreenContext>(new OffscreenContext(std::move(impl)));
}

OffscreenContext::OffscreenContext(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
OffscreenContext::~OffscreenContext() = default;

void OffscreenContext::MakeCurrent() {
  eglMakeCurrent(impl_->display, EGL_NO_SURFACE, EGL_NO_SURFACE, impl_->context);
}

std::string OffscreenContext::renderer_name() const {
  const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return name ? name : "";
}

Result<std::unique_ptr<RenderTarget>> RenderTarget::Make(int width, int height, int samples) {
  if (width <= 0 || height <= 0) return ErrorMessage{"a render target needs a positive size"};
  std::unique_ptr<RenderTarget> t(new RenderTarget());
  t->width_ = width;
  t->height_ = height;
  GLint max_samples = 1;
  glGetIntegerv(GL_MAX_SAMPLES, &max_samples);
  t->samples_ = std::clamp(samples, 1, std::max(1, static_cast<int>(max_samples)));
  glGenFramebuffers(1, &t->draw_fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, t->draw_fbo_);
  glGenRenderbuffers(1, &t->colour_);
  glBindRenderbuffer(GL_RENDERBUFFER, t->colour_);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, t->samples_ > 1 ? t->samples_ : 0, GL_RGBA8,
                                   width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, t->colour_);
  glGenRenderbuffers(1, &t->depth_);
  glBindRenderbuffer(GL_RENDERBUFFER, t->depth_);
  glRenderbufferStorageMultisample(GL_RENDERBUFFER, t->samples_ > 1 ? t->samples_ : 0,
                                   GL_DEPTH_COMPONENT24, width, height);
  glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, t->depth_);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    return ErrorMessage{"the render target's framebuffer is incomplete"};
  }
  if (t->samples_ > 1) {
    glGenFramebuffers(1, &t->resolve_fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, t->resolve_fbo_);
    glGenRenderbuffers(1, &t->resolve_colour_);
    glBindRenderbuffer(GL_RENDERBUFFER, t->resolve_colour_);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                              t->resolve_colour_);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, t->draw_fbo_);
  return t;
}

RenderTarget::~RenderTarget() {
  glDeleteFramebuffers(1, &draw_fbo_);
  glDeleteRenderbuffers(1, &colour_);
  glDeleteRenderbuffers(1, &depth_);
  if (resolve_fbo_) glDeleteFramebuffers(1, &resolve_fbo_);
  if (resolve_colour_) glDeleteRenderbuffers(1, &resolve_colour_);
}

void RenderTarget::Bind() { glBindFramebuffer(GL_FRAMEBUFFER, draw_fbo_); }

cv::Mat RenderTarget::Read() {
  if (samples_ > 1) {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, draw_fbo_);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, resolve_fbo_);
    glBlitFramebuffer(0, 0, width_, height_, 0, 0, width_, height_, GL_COLOR_BUFFER_BIT,
                      GL_NEAREST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, resolve_fbo_);
  } else {
    glBindFramebuffer(GL_READ_FRAMEBUFFER, draw_fbo_);
  }
  cv::Mat pixels = ReadPixels(width_, height_);
  glBindFramebuffer(GL_FRAMEBUFFER, draw_fbo_);
  return pixels;
}

cv::Mat ReadPixels(int width, int height) {
  cv::Mat bgr(height, width, CV_8UC3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_BGR, GL_UNSIGNED_BYTE, bgr.data);
  cv::Mat top_first;
  cv::flip(bgr, top_first, 0);  // GL's rows run from the bottom
  return top_first;
}

Result<bool> SavePng(const cv::Mat& image, const std::string& path) {
  std::error_code ec;
  const auto parent = std::filesystem::path(path).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  std::vector<uchar> png;
  try {
    // Encoded as PNG whatever the file's name ends with.
    if (!cv::imencode(".png", image, png)) return ErrorMessage{path + ": could not encode a PNG"};
  } catch (const cv::Exception& e) {
    return ErrorMessage{path + ": " + e.what()};
  }
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  if (!out) return ErrorMessage{path + ": could not write the PNG file"};
  return true;
}

}  // namespace igms::control::render
