// The pinhole camera of the thesis (Cooke, "Interactive Graphical Model Building using
// Virtual Reality", sections 3.1-3.3): a 3x4 projection matrix P.
//
// Conventions, used everywhere in IGMS:
//  - World frame: the site's (the optical table), z up, in the calibration's units (inches
//    for the thesis's testbed).
//  - Pixels: (0, 0) is the centre of the top-left pixel, u to the right, v down.
//  - P maps homogeneous world points to homogeneous ideal (undistorted) pixels, any scale,
//    for the camera platform at its zero pose (all encoders at zero). Lens distortion, when
//    a camera has it, is applied after P as in OpenCV's model.
#pragma once

#include <Eigen/Core>
#include <optional>

namespace igms::geometry {

using Matrix34 = Eigen::Matrix<double, 3, 4>;

struct ImageSize {
  int width = 0;
  int height = 0;
};

// A ray from the camera centre through a pixel: points are origin + t * direction, t > 0
// in front of the camera. direction is unit length.
struct Ray {
  Eigen::Vector3d origin;
  Eigen::Vector3d direction;
};

class ProjectiveCamera {
 public:
  ProjectiveCamera() = default;
  ProjectiveCamera(const Matrix34& P, ImageSize size);

  const Matrix34& P() const { return P_; }
  ImageSize image_size() const { return size_; }

  // Pixel of a world point, or nullopt when the point is on the camera's focal plane.
  std::optional<Eigen::Vector2d> Project(const Eigen::Vector3d& world) const;
  // Signed depth along the optical axis (positive in front of the camera), in world units
  // when P's left 3x3 block has its last row scaled to unit length.
  double Depth(const Eigen::Vector3d& world) const;
  // The camera centre: the right null vector of P.
  Eigen::Vector3d Center() const;
  // The ray through pixel (u, v), pointing into the scene.
  Ray PixelRay(const Eigen::Vector2d& pixel) const;
  bool InImage(const Eigen::Vector2d& pixel, double margin = 0.0) const;

 private:
  Matrix34 P_ = Matrix34::Zero();
  ImageSize size_;
};

}  // namespace igms::geometry
