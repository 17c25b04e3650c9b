// The solids the locator fits, as parameter vectors the silhouette fit moves: their outline
// points (whose projections' convex hull is the silhouette) and the edges inside the
// silhouette a camera sees (silhouette_fit.h).
//
// Cylinder: the centres of its two end caps (6) and its radius (1). Box: its centre (3), its
// size along its own axes (3) and its yaw about the world's vertical (1): a block stands on
// the table, and the thesis's block is the yaw-0 case (Cooke, section 3.8.2).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "object_server/silhouette_fit.h"

namespace igms::object {

constexpr int kCapPoints = 64;  // outline points around each end of a cylinder

// Point i is around the end at the first centre for i < kCapPoints, then around the second.
std::vector<Eigen::Vector3d> CylinderOutline(const Eigen::VectorXd& x);
// The rim of an end cap a camera at `centre` sees, where the pipe's side is seen too.
std::vector<InnerEdge> CylinderInnerEdges(const Eigen::VectorXd& x, const Eigen::Vector3d& centre);

Eigen::Matrix3d BoxRotation(double yaw);
// Corner i has bit k set when its coordinate k along the box's own axes is +size/2.
std::vector<Eigen::Vector3d> BoxOutline(const Eigen::VectorXd& x);
// The box's edges between two faces a camera at `centre` sees.
std::vector<InnerEdge> BoxInnerEdges(const Eigen::VectorXd& x, const Eigen::Vector3d& centre);
// The same box with its yaw in (-45, 45] degrees and positive sizes.
Eigen::VectorXd CanonicalBox(Eigen::VectorXd x);

// The yaw (degrees) of a box standing on the table, from its rotation's columns.
double StandingBoxYawDeg(const Eigen::Matrix3d& rotation);
// How far a found yaw (degrees) is from a standing box's true rotation, modulo the quarter
// turn that swaps a box's x and y sizes: 0 to 45 degrees.
double BoxYawErrorDeg(double found_yaw_deg, const Eigen::Matrix3d& true_rotation);

// Whether `p` lies inside the solid `x` (a cylinder's parameters, or a box's).
bool InsideSolid(bool cylinder, const Eigen::VectorXd& x, const Eigen::Vector3d& p);
// The share of solid a's volume that lies inside solid b, from a grid of points through a.
// Two solids cannot share volume: one that lies mostly in another is the same object.
double ShareInside(bool a_cylinder, const Eigen::VectorXd& a, bool b_cylinder,
                   const Eigen::VectorXd& b);

}  // namespace igms::object
