// The pinhole camera of the thesis (Cooke, "Interactive Graphical Model Building using
// Virtual Reality", sections 3.1-3.3): a 3x4 projection matrix P, optionally followed by lens
// distortion in OpenCV's model.
//
// Conventions, used everywhere in IGMS:
//  - World frame: the site's (the optical table), z up, in the calibration's units (inches
//    for the thesis's testbed).
//  - Pixels: (0, 0) is the centre of the top-left pixel, u to the right, v down. This is also
//    OpenCV's convention for sub-pixel coordinates (cornerSubPix, projectPoints).
//  - P maps homogeneous world points to homogeneous ideal (undistorted) pixels, any scale,
//    for the camera platform at its zero pose (all encoders at zero). Lens distortion, when
//    a camera has it, is applied after P as in OpenCV's model:
//        ideal = P * X;  x = K^-1 * ideal;  observed = K * distort(x)
//    so a camera with distortion also carries the intrinsic matrix K that defines the
//    normalised coordinates x. Without a lens, ideal and observed pixels are the same.
//  - "Depth" is the signed distance along the optical axis, positive in front of the camera.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

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

  Eigen::Vector3d At(double t) const { return origin + t * direction; }
};

// Intrinsics and distortion of a real lens (from a chessboard calibration, OpenCV's model).
// K is upper triangular with K(2,2) = 1; dist follows OpenCV's order (see distortion.h).
struct Lens {
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  std::vector<double> dist;
};

class ProjectiveCamera {
 public:
  ProjectiveCamera() = default;
  ProjectiveCamera(const Matrix34& P, ImageSize size);
  // A camera with lens distortion. The lens's coefficients must pass CheckDistortion and K
  // must be invertible (programmer errors: std::invalid_argument).
  ProjectiveCamera(const Matrix34& P, ImageSize size, Lens lens);

  const Matrix34& P() const { return P_; }
  ImageSize image_size() const { return size_; }
  const std::optional<Lens>& lens() const { return lens_; }
  // True when the lens has non-zero distortion coefficients.
  bool has_distortion() const;

  // Ideal pixel of a world point, or nullopt when the point is on the camera's focal plane.
  std::optional<Eigen::Vector2d> Project(const Eigen::Vector3d& world) const;
  // Observed (distorted) pixel of a world point: Project, then Distort.
  std::optional<Eigen::Vector2d> ProjectObserved(const Eigen::Vector3d& world) const;
  // Ideal pixel to observed pixel (identity without distortion).
  Eigen::Vector2d Distort(const Eigen::Vector2d& ideal) const;
  // Observed pixel to ideal pixel (identity without distortion); nullopt where the lens model
  // cannot be inverted (far outside the image for strong barrel distortion).
  std::optional<Eigen::Vector2d> Undistort(const Eigen::Vector2d& observed) const;

  // Signed depth along the optical axis (positive in front of the camera), in world units:
  // Hartley & Zisserman's depth with P's scale removed, so it is independent of P's scale.
  double Depth(const Eigen::Vector3d& world) const;
  // The camera centre: the right null vector of P. Infinite (non-finite entries) when P's
  // left 3x3 block is singular, which a loaded calibration never is.
  Eigen::Vector3d Center() const;
  // Unit vector along the optical axis, pointing into the scene.
  Eigen::Vector3d ViewDirection() const;
  // The ray through ideal pixel (u, v), pointing into the scene.
  Ray PixelRay(const Eigen::Vector2d& pixel) const;
  bool InImage(const Eigen::Vector2d& pixel, double margin = 0.0) const;

 private:
  Matrix34 P_ = Matrix34::Zero();
  ImageSize size_;
  std::optional<Lens> lens_;
};

}  // namespace igms::geometry
