// The graphical camera: OpenGL matrices that draw the world exactly as a projection matrix P
// sees it, so graphics overlay the video (Cooke, sections 3.3 and 4.2: the thesis matched
// CimStation's cameras to the decomposition by hand; here the match is exact, skew and
// principal-point offset included).
//
// Pipeline (fixed-function or a shader doing gl_Position = projection * view * world):
//   eye  = view * world         OpenGL eye frame: x right, y up, looking down -z
//   clip = projection * eye      then NDC = clip.xyz / clip.w
//   window = viewport(0, 0, width, height) of the NDC, y from the bottom
// With glViewport(0, 0, width, height) a world point lands at window (x_w, y_w) with
//   u = x_w - 0.5,  v = height - y_w - 0.5
// which is P's ideal pixel (IGMS convention: (0,0) is the centre of the top-left pixel).
// Matrices are column-vector convention; pass projection.data() / view.data() (Eigen is
// column-major, as glLoadMatrixd and glUniformMatrix4fv(..., GL_FALSE, ...) expect).
// Depth: near and far are distances along the optical axis in world units; NDC z runs
// from -1 at near to +1 at far, as glFrustum's.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "common/base/result.h"
#include "common/geometry/camera.h"

namespace igms::geometry {

struct GlCamera {
  Eigen::Matrix4d projection = Eigen::Matrix4d::Identity();
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  double fovy_degrees = 0;  // vertical field of view of the image rows
  double fovx_degrees = 0;
  double aspect = 0;  // width / height of the view volume (fovx against fovy)
  // Principal point minus the image centre, pixels (u right, v down).
  Eigen::Vector2d principal_offset = Eigen::Vector2d::Zero();
};

// An error when P is degenerate, the size is not positive, or not 0 < near < far.
Result<GlCamera> MakeGlCamera(const Matrix34& P, ImageSize size, double near, double far);

// Where OpenGL draws a world point with these matrices, in IGMS pixels (the inverse of the
// viewport mapping above); nullopt behind the eye. For tests and overlays checks.
std::optional<Eigen::Vector2d> GlPixel(const GlCamera& gl, ImageSize size,
                                       const Eigen::Vector3d& world);

}  // namespace igms::geometry
