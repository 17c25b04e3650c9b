#include "control/render/stereo.h"

namespace igms::control::render {

std::string_view StereoModeName(StereoMode mode) {
  switch (mode) {
    case StereoMode::kSideBySide:
      return "side-by-side";
    case StereoMode::kAnaglyph:
      return "anaglyph";
    case StereoMode::kQuadBuffer:
      return "quad-buffer";
    case StereoMode::kLeft:
      return "left";
    case StereoMode::kRight:
      return "right";
  }
  return "?";
}

std::optional<StereoMode> ParseStereoMode(std::string_view name) {
  for (StereoMode m : {StereoMode::kSideBySide, StereoMode::kAnaglyph, StereoMode::kQuadBuffer,
                       StereoMode::kLeft, StereoMode::kRight}) {
    if (name == StereoModeName(m)) return m;
  }
  if (name == "mono") return StereoMode::kLeft;
  return std::nullopt;
}

std::string StereoModeNames() { return "side-by-side, anaglyph, quad-buffer, left, right, mono"; }

geometry::ImageSize FrameSize(StereoMode mode, geometry::ImageSize eye) {
  if (mode == StereoMode::kSideBySide) return {2 * eye.width, eye.height};
  return eye;
}

void DrawStereo(Renderer& renderer, const DrawList& list, StereoMode mode, int width, int height) {
  renderer.Clear(width, height);
  switch (mode) {
    case StereoMode::kSideBySide: {
      const int half = width / 2;
      renderer.DrawEye(list, 0, {0, 0, half, height});
      renderer.DrawEye(list, 1, {half, 0, width - half, height});
      break;
    }
    case StereoMode::kAnaglyph:
      renderer.DrawEye(list, 0, {0, 0, width, height}, {true, false, false});
      renderer.DrawEye(list, 1, {0, 0, width, height}, {false, true, true});
      break;
    case StereoMode::kQuadBuffer:  // the window draws each buffer; here, the left eye
    case StereoMode::kLeft:
      renderer.DrawEye(list, 0, {0, 0, width, height});
      break;
    case StereoMode::kRight:
      renderer.DrawEye(list, 1, {0, 0, width, height});
      break;
  }
}

}  // namespace igms::control::render
