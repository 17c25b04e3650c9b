// What the window draws, as plain data with no OpenGL in it: each eye's video and graphical
// camera, the models, the pointer, the marks and the heads-up text. The window builds one per
// frame from the session's view (control/window/view_from_session.h); tests and benchmarks
// build their own. Cooke, *Interactive Graphical Model Building using Virtual Reality*,
// sections 2.3 and 4.2: the graphical cameras match the real ones, so the graphics register
// on the video.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "common/geometry/camera.h"

namespace igms::control::render {

// One eye: the video behind it and the graphical camera in front of it.
struct EyeView {
  // The camera's 3x4 matrix at the pose the video was taken at; its ideal pixels are the
  // viewport's pixels (IGMS convention: (0,0) is the centre of the top-left pixel).
  geometry::Matrix34 P = geometry::Matrix34::Zero();
  geometry::ImageSize size{512, 480};
  // 8-bit grey or BGR, `size` (another size is stretched over it); empty: black.
  cv::Mat video;
  // Changes whenever `video` does (a frame's sequence), so an unchanged frame is not
  // uploaded again; 0: upload on every draw.
  uint64_t video_id = 0;
  // A real lens (K, dist): the video is undistorted as it is drawn, so the graphics of the
  // ideal camera P register on it.
  std::optional<geometry::Lens> lens;
};

// A solid to draw (the object server's models; the simulated site's truth in benchmarks).
struct DrawModel {
  enum class Kind { kBox, kCylinder };
  Kind kind = Kind::kBox;
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  // Box: its axes as columns and its size along them. Cylinder: the axis is axis (unit),
  // with radius and height.
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d size = Eigen::Vector3d::Ones();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double radius = 0.5;
  double height = 1.0;
  Eigen::Vector3f color{0.2f, 0.9f, 0.3f};  // linear RGB in [0, 1]
  // A box's texture patch: `texture` (8-bit grey or BGR) holds the pixels `texture_rect` of
  // an image taken by the camera `texture_P`; it goes on the face that camera saw most
  // squarely, mapped through texture_P, and the other faces stay flat. Empty: none.
  cv::Mat texture;
  cv::Rect texture_rect;
  geometry::Matrix34 texture_P = geometry::Matrix34::Zero();
};

enum class HudLevel { kInfo, kWarning, kError };
struct HudLine {
  std::string text;
  HudLevel level = HudLevel::kInfo;
};

struct DrawList {
  std::array<EyeView, 2> eyes;  // left, right
  std::vector<DrawModel> models;
  bool wireframe = false;
  // Solids shaded towards the eye; false: each in its flat colour (a coverage mask, for
  // measuring registration).
  bool lit = true;
  std::optional<Eigen::Vector3d> pointer;
  std::vector<Eigen::Vector3d> marks;
  double pointer_size = 1.0;      // world units, each arm of the pointer's cross
  std::vector<HudLine> hud;       // top left, one line each
  std::string banner;             // a centred warning across the top (a lost video server)
  std::vector<std::string> help;  // bottom left, shown when not empty
  // The thesis's keyer: graphics no brighter than key_level (0-255, of the brightest
  // channel) are transparent, so black shows the video; alpha below 1 blends the rest.
  int key_level = 0;
  float graphics_alpha = 1.0f;
  // The video's offset against the graphics, pixels (VideoService's overlay u/v offset).
  Eigen::Vector2i video_offset = Eigen::Vector2i::Zero();
  // Depth range of the graphical cameras, world units along the optical axis.
  double near = 1.0;
  double far = 5000.0;
};

// A model's triangles and lines, in world coordinates: what the renderer uploads. Exposed for
// tests (the wireframe of a cylinder depends on the eye: its silhouette generators).
struct Mesh {
  std::vector<Eigen::Vector3f> triangles;  // three per triangle
  std::vector<Eigen::Vector3f> normals;    // one per triangle vertex
  std::vector<Eigen::Vector3f> lines;      // two per segment
};
// The solid's faces (cylinders with `segments` sides; each triangle counter-clockwise seen
// from outside, so back faces can be culled) and its outline as seen from `eye_center`: a
// box's 12 edges; a cylinder's two caps and its two silhouette generators.
void AppendModel(const DrawModel& model, const Eigen::Vector3d& eye_center, int segments,
                 Mesh* mesh);
// The two triangles of the box face its texture camera saw most squarely (facing it), for
// the texture patch; false when the model has no texture or is not a box.
bool TexturedFace(const DrawModel& model, std::vector<Eigen::Vector3f>* triangles);

}  // namespace igms::control::render
