// How the two eyes reach the operator (issue: the control client's window):
//   side-by-side  left eye in the left half, right in the right half (head-mounted and 3D
//                 displays; the thesis's BOOM2C took one channel per eye, section 2.1.3)
//   anaglyph      left in red, right in green and blue, for any monitor (the thesis's own
//                 check of camera matching, section 4.2, was red over blue)
//   quad-buffer   OpenGL's left and right back buffers, where the driver offers them
//   left, right   one eye (mono)
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "common/geometry/camera.h"
#include "control/render/renderer.h"

namespace igms::control::render {

enum class StereoMode { kSideBySide, kAnaglyph, kQuadBuffer, kLeft, kRight };

std::string_view StereoModeName(StereoMode mode);  // "side-by-side", "anaglyph", ...
// Accepts the names above and "mono" (= left).
std::optional<StereoMode> ParseStereoMode(std::string_view name);
// The names, for messages: "side-by-side, anaglyph, quad-buffer, left, right, mono".
std::string StereoModeNames();

// The frame's size for eyes of `eye` size: twice as wide side by side.
geometry::ImageSize FrameSize(StereoMode mode, geometry::ImageSize eye);

// Draws both eyes into the bound framebuffer of `width` x `height` for every mode but
// quad-buffer (the window selects each back buffer and draws one eye full size).
void DrawStereo(Renderer& renderer, const DrawList& list, StereoMode mode, int width, int height);

}  // namespace igms::control::render
