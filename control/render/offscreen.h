// Rendering without a display: an OpenGL 3.3 core context from EGL with no surface (Mesa's
// surfaceless platform; llvmpipe where there is no GPU), and framebuffers to draw into and
// read back. Tests, benchmarks and the control client's screenshots without a window use it.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>

#include "common/base/result.h"

namespace igms::control::render {

class OffscreenContext {
 public:
  // Creates the context and makes it current on the calling thread. An error says what EGL
  // refused (no EGL library, no surfaceless platform, no 3.3 core context).
  static Result<std::unique_ptr<OffscreenContext>> Make();
  ~OffscreenContext();
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;

  void MakeCurrent();
  // GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  std::string renderer_name() const;

  struct Impl;

 private:
  explicit OffscreenContext(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// A colour and depth framebuffer of its own, multisampled when `samples` > 1 (clamped to
// what the driver offers). Needs a current context.
class RenderTarget {
 public:
  static Result<std::unique_ptr<RenderTarget>> Make(int width, int height, int samples = 1);
  ~RenderTarget();
  RenderTarget(const RenderTarget&) = delete;
  RenderTarget& operator=(const RenderTarget&) = delete;

  void Bind();  // draws go here until another framebuffer is bound
  // The pixels (resolved when multisampled): 8-bit BGR, top row first.
  cv::Mat Read();
  int width() const { return width_; }
  int height() const { return height_; }
  int samples() const { return samples_; }

 private:
  RenderTarget() = default;
  int width_ = 0, height_ = 0, samples_ = 1;
  unsigned draw_fbo_ = 0, colour_ = 0, depth_ = 0;
  unsigned resolve_fbo_ = 0, resolve_colour_ = 0;
};

// The bound read framebuffer's pixels in (0, 0, width, height): 8-bit BGR, top row first.
cv::Mat ReadPixels(int width, int height);

// Writes an image as a PNG file; an error names the file.
Result<bool> SavePng(const cv::Mat& image, const std::string& path);

}  // namespace igms::control::render
