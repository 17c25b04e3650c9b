// Epipolar geometry of two cameras given by their projection matrices (ideal pixels).
//
// The fundamental matrix F maps a pixel x of camera `from` to its epipolar line l = F x in
// camera `to`: every world point seen at x projects onto l, so x_to^T F x_from = 0.
// Lines are (a, b, c) with a u + b v + c = 0, normalised so that a^2 + b^2 = 1; then
// a u + b v + c is the signed distance of pixel (u, v) from the line, in pixels.
//
// The thesis restricts stereo matching to the part of the epipolar line that corresponds to
// the operator's depth +/- 3 inches (Cooke, section 3.6): EpipolarSegment gives that part.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "common/base/result.h"
#include "common/geometry/camera.h"

namespace igms::geometry {

// F with x_to^T F x_from = 0, scaled to unit Frobenius norm. Built from F = [e']_x P' P^+
// (Hartley & Zisserman 9.2.2). The two cameras must have distinct, finite centres; otherwise
// F is zero.
Eigen::Matrix3d FundamentalMatrix(const Matrix34& from, const Matrix34& to);

// The epipolar line in `to` of ideal pixel `pixel` of `from`, normalised (a^2 + b^2 = 1).
// nullopt when the pixel is the epipole (the line is undefined) or F is zero.
std::optional<Eigen::Vector3d> EpipolarLine(const Eigen::Matrix3d& F, const Eigen::Vector2d& pixel);

// Signed distance in pixels of `pixel` from a normalised line.
double LineDistance(const Eigen::Vector3d& line, const Eigen::Vector2d& pixel);

// The epipole of `from` in `to`: the image of from's centre. nullopt when it is at infinity
// (parallel cameras).
std::optional<Eigen::Vector2d> Epipole(const Matrix34& from, const Matrix34& to);

struct EpipolarSegment {
  Eigen::Vector2d near;  // the image in `to` of the ray point at depth_min
  Eigen::Vector2d far;   // the image in `to` of the ray point at depth_max
  Eigen::Vector3d near_world;
  Eigen::Vector3d far_world;
};

// The part of pixel's epipolar line in `to` that holds the images of the points of pixel's
// ray (in `from`) whose depth along from's optical axis lies in [depth_min, depth_max].
// Ideal pixels. Fails (with the reason) when the window is empty or not finite,
// when depth_min is not positive, when the ray is parallel to from's focal plane, or when a
// point of the window lies on or behind to's focal plane (its image would wrap through
// infinity).
Result<EpipolarSegment> ComputeEpipolarSegment(const ProjectiveCamera& from,
                                               const ProjectiveCamera& to,
                                               const Eigen::Vector2d& pixel, double depth_min,
                                               double depth_max);

}  // namespace igms::geometry
