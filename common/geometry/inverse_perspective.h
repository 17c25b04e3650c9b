// Inverse perspective (Cooke, section 3.5): the world line that projects to one pixel.
//
// A pixel (U, V) of a camera P constrains a world point X to two planes, the thesis's
// equations 3.10 and 3.11 written for any scale of P:
//     plane_u = P.row(0) - U P.row(2)      (a1, b1, c1, d1)
//     plane_v = P.row(1) - V P.row(2)      (a2, b2, c2, d2)
// each as (a, b, c, d) with a x + b y + c z + d = 0. Their intersection is the pixel's ray
// (direction n1 x n2, equation 3.26); the point of it at a given height z0 is equations 3.28
// and 3.29. ProjectiveCamera::PixelRay gives the same line through the camera centre, oriented
// into the scene; these functions exist because the thesis's object location works in them.
// Pixels here are ideal (undistorted) ones.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <utility>

#include "common/geometry/camera.h"

namespace igms::geometry {

// The two planes of equations 3.10 and 3.11, in that order.
std::pair<Eigen::Vector4d, Eigen::Vector4d> PixelPlanes(const Matrix34& P,
                                                        const Eigen::Vector2d& pixel);

// The line where the two planes meet: a point on it (the one nearest the world origin) and
// the unit direction n1 x n2 (equation 3.26), oriented into the scene of the camera P.
// nullopt when the planes are parallel (P degenerate).
std::optional<Ray> LineFromPlanes(const Matrix34& P, const Eigen::Vector2d& pixel);

// The point of the pixel's ray at height z = z0 (equations 3.28 and 3.29). nullopt when the
// ray is horizontal (a1 b2 - b1 a2 vanishes relative to the plane normals), where no single
// point has that height.
std::optional<Eigen::Vector3d> PointAtHeight(const Matrix34& P, const Eigen::Vector2d& pixel,
                                             double z0);

// The point of the ray at signed depth `depth` along the camera's optical axis
// (ProjectiveCamera::Depth of the result equals `depth`). nullopt when the ray is parallel
// to the focal plane.
std::optional<Eigen::Vector3d> PointAtDepth(const ProjectiveCamera& camera,
                                            const Eigen::Vector2d& pixel, double depth);

}  // namespace igms::geometry
