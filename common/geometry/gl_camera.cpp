#include "common/geometry/gl_camera.h"

#include <Eigen/Geometry>
#include <cmath>

#include "common/geometry/decomposition.h"

namespace igms::geometry {

Result<GlCamera> MakeGlCamera(const Matrix34& P, ImageSize size, double near, double far) {
  if (size.width <= 0 || size.height <= 0) {
    return ErrorMessage{"image size must be positive"};
  }
  if (!(near > 0) || !(far > near) || !std::isfinite(far)) {
    return ErrorMessage{"clipping planes must satisfy 0 < near < far"};
  }
  const auto rq = DecomposeRq(P);
  if (!rq.ok()) return ErrorMessage{rq.error()};
  const double W = size.width, H = size.height;
  GlCamera gl;
  // OpenCV's camera frame (x right, y down, z forward) to OpenGL's eye frame.
  Eigen::Matrix4d flip = Eigen::Matrix4d::Identity();
  flip(1, 1) = flip(2, 2) = -1;
  Eigen::Matrix4d camera_from_world = Eigen::Matrix4d::Identity();
  camera_from_world.topLeftCorner<3, 3>() = rq->R;
  camera_from_world.topRightCorner<3, 1>() = -rq->R * rq->center;
  gl.view = flip * camera_from_world;
  // Rows from u = (fx X + s Y)/Z + cx, v = fy Y/Z + cy with X = x_e, Y = -y_e, Z = -z_e, and
  // pixel centres at window coordinates u + 0.5, H - v - 0.5.
  const double fx = rq->fx(), fy = rq->fy(), s = rq->skew(), cx = rq->cx(), cy = rq->cy();
  Eigen::Matrix4d& p = gl.projection;
  p.setZero();
  p(0, 0) = 2 * fx / W;
  p(0, 1) = -2 * s / W;
  p(0, 2) = 1 - 2 * (cx + 0.5) / W;
  p(1, 1) = 2 * fy / H;
  p(1, 2) = 2 * (cy + 0.5) / H - 1;
  p(2, 2) = -(far + near) / (far - near);
  p(2, 3) = -2 * far * near / (far - near);
  p(3, 2) = -1;
  gl.fovy_degrees = 2 * std::atan(H / (2 * fy)) * 180 / M_PI;
  gl.fovx_degrees = 2 * std::atan(W / (2 * fx)) * 180 / M_PI;
  gl.aspect = (W / fx) / (H / fy);
  gl.principal_offset = Eigen::Vector2d(cx - (W - 1) / 2, cy - (H - 1) / 2);
  return gl;
}

std::optional<Eigen::Vector2d> GlPixel(const GlCamera& gl, ImageSize size,
                                       const Eigen::Vector3d& world) {
  const Eigen::Vector4d clip = gl.projection * gl.view * world.homogeneous();
  if (!(clip.w() > 0)) return std::nullopt;
  const double ndc_x = clip.x() / clip.w(), ndc_y = clip.y() / clip.w();
  const double xw = (ndc_x + 1) / 2 * size.width, yw = (ndc_y + 1) / 2 * size.height;
  return Eigen::Vector2d(xw - 0.5, size.height - yw - 0.5);
}

}  // namespace igms::geometry
