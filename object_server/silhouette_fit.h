// Fitting a convex solid's silhouette to both images at once.
//
// A model is a parameter vector and a function giving 3D points whose projections' convex
// hull is the solid's silhouette (cap circles of a cylinder, corners of a box). Each outer
// iteration projects the model into each view, samples its outline every pixel (skipping
// sharp corners, where edges are blurred), and measures the sub-pixel image edge along the
// outline's normal (image_ops.h: EdgeAlongNormal). The inner iterations move the parameters
// by Levenberg-Marquardt to bring the outlines onto the measured edge points (residual: the
// signed distance, in pixels, from each measured point to the projected outline), with
// Huber weights so stray edges (table holes, a neighbour) pull little. Edges inside the
// silhouette (a box's face boundaries) can join the fit: they fix the depth a silhouette
// alone leaves to a thin side strip.
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "common/geometry/camera.h"
#include "object_server/image_ops.h"

namespace igms::object {

using OutlineFn = std::function<std::vector<Eigen::Vector3d>(const Eigen::VectorXd&)>;

// An edge inside the silhouette between two surfaces a camera sees (a box's front and top,
// a pipe's end cap and its side): a chain of outline points (two for a straight edge);
// c1 and c2 are points of each surface away from it, so the surfaces' widths in the image
// (their distances from the line through the chain's ends) say whether the edge stands
// clear of its neighbours.
struct InnerEdge {
  std::vector<int> chain;
  int c1, c2;
  double min_width_px = 4;  // narrower surfaces: the edge is not measured in that view
};
// The inner edges seen from a camera centre, for parameters x.
using InnerEdgesFn =
    std::function<std::vector<InnerEdge>(const Eigen::VectorXd& x, const Eigen::Vector3d& centre)>;

struct FitView {
  FitView() = default;
  FitView(const geometry::ProjectiveCamera* c, const Gradients* g,
          std::vector<Eigen::Vector2d> r = {})
      : camera(c), gradients(g), region(std::move(r)) {}
  const geometry::ProjectiveCamera* camera = nullptr;
  const Gradients* gradients = nullptr;
  // Where the object's outline can lie in this view (a convex polygon, counter-clockwise in
  // u-v; empty: anywhere). The search for the outline's edge stops at its border: an edge
  // beyond it is a neighbour's (a pipe resting on a block), however much outermost.
  std::vector<Eigen::Vector2d> region;
  // Where a known solid in front hides the object (convex polygons, counter-clockwise): the
  // outline there is not measured and not counted, and an edge found there is not the
  // object's.
  std::vector<std::vector<Eigen::Vector2d>> hidden;
  // A pipe's side shading up to its limbs moves the blurred edge's gradient peak inside the
  // true silhouette: a silhouette edge measured on a hull segment between the outline's two
  // halves (a cylinder's rims, CylinderOutline: its limbs) is moved out by this (pixels).
  double limb_shift_px = 0;
  // Per outline point: the hull segment starting there moved out by this (pixels), for the
  // edge's own blur with a thin face beside it (BoxFaceShifts). Empty: none.
  std::vector<double> segment_shift_px;
};

// Whether p lies inside one of the polygons.
bool InsideAny(const std::vector<std::vector<Eigen::Vector2d>>& polygons, const Eigen::Vector2d& p);

struct FitOptions {
  double search_px = 4.0;     // first outer iteration's search range; later ones use half
  double min_gradient = 6.0;  // edges weaker than this are not measured
  // The edges' total blur (the camera's and the gradient's smoothing, as one Gaussian's
  // sigma, pixels): a curved outline's measured edge is corrected for it. 0: no correction.
  double edge_blur_px = 0.0;
  int outer_iterations = 5;
  int first_outer = 0;  // continuing an earlier fit: its passes already made
  // FitFromStarts: the runner-up of the short fits also runs to the end when the best ends
  // scoring (FitScore) above this.
  double runner_up_above = 0.0;
  int inner_iterations = 6;
  // An edge whose gradient turns from the outline's normal by more than this (degrees) is
  // not measured; 90: any.
  double max_edge_angle_deg = 90;
  double huber_px = 0.5;
  double outlier_px = 2.0;  // measurements farther than this after a pass are dropped
  // The covariance: edge points one pixel apart do not err independently (blur, the same
  // shading, a sliver's two edges read as one), and the residuals of a clean image
  // understate the edges' real error. Each point's error is taken as at least
  // min_sigma_px, and as shared by correlated_samples neighbours.
  double min_sigma_px = 0.4;
  double correlated_samples = 10;
  // The silhouette's edges can all sit off the true outline the same way: a shaded pipe's
  // limb, darkening towards it, reads inside its outline. No number of samples averages that
  // away, so the covariance takes in a shift of this many pixels all round (inner edges,
  // between two of the object's faces, stay put).
  double outline_shift_px = 0.1;
  // The views' regions (FitView::region) bound the outline itself, not only the edge search:
  // each outline point beyond its view's region costs region_weight / 2 times the square of
  // its distance outside (pixels), with no cut-off, so a model cannot grow past the marks
  // where no edge holds it (a block's side run along the pipe it carries). 0: the search
  // alone.
  double region_weight = 0;
  Eigen::VectorXd step;  // finite-difference step per parameter (world units)
};

struct FitOutcome {
  bool ok = false;
  std::string error;
  Eigen::VectorXd params;
  Eigen::MatrixXd covariance;  // of params, from the weighted residuals
  std::array<double, 2> rms_px{0, 0};
  std::array<int, 2> used{0, 0};        // measurements kept in the final pass, per view
  std::array<int, 2> sampled{0, 0};     // outline samples, per view
  std::array<int, 2> inner_used{0, 0};  // inner-edge measurements kept, per view
  // For a person to look at (debug images): per view the fitted outline and the edge points
  // measured in the final pass, each with whether it counted (within outlier_px).
  std::array<std::vector<Eigen::Vector2d>, 2> outline;
  std::array<std::vector<Eigen::Vector2d>, 2> measured;
  std::array<std::vector<bool>, 2> inlier;
};

// With `inner`, the edges it names are measured too (the nearest edge across each, not the
// outermost) and fitted as lines; the outline statistics (used, sampled, rms) stay the
// silhouette's alone.
FitOutcome FitSilhouette(const OutlineFn& outline, const Eigen::VectorXd& initial,
                         const std::array<FitView, 2>& views, const FitOptions& options,
                         const InnerEdgesFn& inner = {});

// Convex hull (counter-clockwise in the u-v plane) of 2D points; exposed for tests.
std::vector<Eigen::Vector2d> ConvexHull(std::vector<Eigen::Vector2d> points);
// Signed distance from p to a convex counter-clockwise polygon: positive outside.
double SignedDistance(const std::vector<Eigen::Vector2d>& hull, const Eigen::Vector2d& p);

}  // namespace igms::object
