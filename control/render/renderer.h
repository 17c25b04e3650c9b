// Draws a DrawList (draw_list.h) with OpenGL 3.3 core into whatever framebuffer is bound: the
// window's, or an offscreen target (offscreen.h). For each eye, in its viewport:
//   1. the video, undistorted by the eye's lens when it has one and shifted by the overlay
//      offset;
//   2. the models, solid (Lambert-shaded towards the eye, depth-tested) or as wireframes
//      (a box's edges, a cylinder's caps and silhouette generators), keyed by the thesis's
//      rule: what is no brighter than key_level is transparent;
//   3. the 3D pointer (a cross) and the marks, always on top;
//   4. the heads-up text.
// The graphical camera is the eye's P through geometry::MakeGlCamera, so a world point lands
// on P's pixel, scaled to the viewport (Cooke, sections 3.3 and 4.2).
//
// One Renderer per GL context; create, draw and destroy it with that context current.
#pragma once

#include <array>
#include <memory>

#include "common/base/result.h"
#include "control/render/draw_list.h"

namespace igms::control::render {

struct Viewport {
  int x = 0, y = 0;  // lower left, GL window coordinates
  int width = 0, height = 0;
};

class Renderer {
 public:
  // Needs a current OpenGL 3.3 core context; an error names the shader that failed.
  static Result<std::unique_ptr<Renderer>> Make();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Draws one eye into `viewport` of the bound framebuffer. `mask` limits the colour
  // channels written (anaglyph: red for the left eye, green and blue for the right).
  void DrawEye(const DrawList& list, int eye, const Viewport& viewport,
               std::array<bool, 3> mask = {true, true, true});
  // Clears the whole bound framebuffer to black.
  void Clear(int width, int height);

  // Segments of a cylinder's polygon (96: the area-matched polygon departs from the circle
  // by under 0.0003 of its radius).
  int cylinder_segments = 96;

  struct Impl;

 private:
  explicit Renderer(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// The HUD's text as an image (RGBA, premultiplied by nothing: alpha 0 where there is no
// text), the size of the viewport. Exposed for tests.
cv::Mat RenderHudImage(const DrawList& list, int width, int height);

}  // namespace igms::control::render
