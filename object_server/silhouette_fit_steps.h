// The steps of the silhouette fit (silhouette_fit.h), each a function of its own so it can be
// tested alone. FitSilhouette() runs, per outer pass:
//  1. ProjectOutline: the model's outline points into each view and their convex hull.
//  2. MeasureSilhouetteEdges (and MeasureInnerEdges): the outline sampled every pixel and the
//     sub-pixel image edge measured along its normal, within the pass's SearchRange.
//  3. RefineParameters: Levenberg-Marquardt steps on the Huber-weighted distances from the
//     measured points to the outline (OutlineResiduals).
//  4. OutlineSettled: a pass that did not move the outline ends the passes.
// then FinishFit: the final statistics and the covariance on the last measurements.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "common/geometry/camera.h"
#include "object_server/image_ops.h"
#include "object_server/silhouette_fit.h"

namespace igms::object {

// The model's outline points projected into one view and the indices of their convex hull.
struct ViewOutline {
  std::vector<Eigen::Vector2d> px;
  std::vector<int> hull;      // outline indices, counter-clockwise
  std::vector<int> position;  // outline index -> position in hull, or -1
};
// False when a point is behind (or on the focal plane of) the camera, or the hull has under 3
// points.
bool ProjectOutline(const std::vector<Eigen::Vector3d>& points,
                    const geometry::ProjectiveCamera& camera, ViewOutline& out);

// An edge measurement and the outline point that starts the hull segment it was sampled on:
// the closest segment is searched from there, as the model moves little between steps.
struct Measurement {
  int view;
  Eigen::Vector2d point;
  int hint;
  int a = -1, b = -1;  // an inner edge's outline points; -1 for the silhouette
};

// The outline sampled every pixel, away from corners sharper than 30 degrees: each sample's
// point, outward normal, the outline index starting its hull segment and the outline's
// curvature there (1/px, from the turn at the segment's ends). Empty for under 3 hull points.
struct OutlineSamples {
  std::vector<Eigen::Vector2d> points, normals;
  std::vector<int> segment;
  std::vector<double> curvature;
};
OutlineSamples SampleOutline(const ViewOutline& outline);

// The edge search either side of the outline in pass `outer` (from 0): search_px first, then
// narrower as the fit closes in.
double SearchRange(int outer, double search_px);

// The silhouette's edge in view `view` at each of the outline's samples, measured along the
// normal within `range` (EdgeAlongNormal). A blurred curved edge's gradient peak lies inside
// the true outline by about blur^2 * curvature / 2 (a disc of radius R: sigma^2 / 2R), so each
// measurement is moved back out by that much (options.edge_blur_px). `sampled` gets the
// number of samples. The search stops at the view's region (FitView::region), and an edge
// turning from the outline by more than options.max_edge_angle_deg is left out.
std::vector<Measurement> MeasureSilhouetteEdges(const ViewOutline& outline, int view,
                                                const FitView& fit_view, double range,
                                                const FitOptions& options, int* sampled);
// The same with no region.
std::vector<Measurement> MeasureSilhouetteEdges(const ViewOutline& outline, int view,
                                                const Gradients& gradients, double range,
                                                const FitOptions& options, int* sampled);

// Samples each inner edge every pixel along its chain, away from its ends (where it meets
// the silhouette and the corners blur), and measures the nearest edge across it. An edge
// whose surfaces are narrower than its min_width_px in this view is skipped: a neighbouring
// edge lies within the search and could be taken.
void MeasureInnerEdges(const std::vector<InnerEdge>& edges, const ViewOutline& outline, int view,
                       const FitView& fv, double range, double min_gradient,
                       std::vector<Measurement>& ms);

// The robust cost of one residual: Huber up to `outlier`, then flat, so moving away from
// edges never pays; and the weight of a residual in a step (0 beyond `outlier`).
double RobustCost(double residual, double huber, double outlier);
double RobustWeight(double residual, double huber, double outlier);

// Residuals of measurements against the model's outlines, and optionally their Jacobian:
// analytic from each measurement's closest hull segment, through the projection, down to the
// outline points, whose derivatives with respect to the parameters are taken numerically
// (a handful of cheap outline evaluations instead of one full residual pass per parameter).
// At most kMaxFitParams parameters (a cylinder's and a box's are 7), so the per-point
// Jacobians live on the stack.
constexpr int kMaxFitParams = 8;
class OutlineResiduals {
 public:
  // `step`: the finite-difference step per parameter (world units).
  OutlineResiduals(const OutlineFn& outline, const std::array<FitView, 2>& views,
                   const Eigen::VectorXd& step, double region_weight = 0)
      : outline_(outline), views_(views), step_(step), region_weight_(region_weight) {}

  // The outline in both views; false when it does not project (ProjectOutline).
  bool Outlines(const Eigen::VectorXd& x, std::array<ViewOutline, 2>& o) const;
  // Signed distances (pixels, positive outside) of `ms` from the outlines at x. Hints of `ms`
  // are updated to the closest segments found. False when the outline does not project.
  // With a region_weight, `r` goes on past ms.size() with one row per outline point of each
  // view with a region: how far the point lies beyond it (0 inside), times
  // sqrt(region_weight), so its square is the point's cost.
  bool Residuals(const Eigen::VectorXd& x, std::vector<Measurement>& ms, Eigen::VectorXd& r,
                 Eigen::MatrixXd* J) const;

 private:
  OutlineFn outline_;
  std::array<FitView, 2> views_;
  Eigen::VectorXd step_;
  double region_weight_ = 0;
  mutable std::vector<Eigen::Vector3d> pts_;
};

// Up to options.inner_iterations Levenberg-Marquardt steps on the measurements' robust cost
// (residuals beyond `outlier` carry no weight), from x; a step that gains almost nothing ends
// them. Hints of `ms` follow the accepted steps.
void RefineParameters(const OutlineResiduals& residuals, const FitOptions& options, double outlier,
                      std::vector<Measurement>& ms, Eigen::VectorXd& x);

// Whether no outline point moved farther than `settled_px` between two projections of it.
bool OutlineSettled(const std::array<ViewOutline, 2>& before,
                    const std::array<ViewOutline, 2>& after, double settled_px);

// The outcome at x on the last measurements: per view the RMS residual, the measurements kept
// (within outlier_px) and what was measured; the covariance from the weighted residuals (each
// point's error at least min_sigma_px and shared by correlated_samples neighbours); the
// fitted outline. False, with `out` untouched, when x does not project.
bool FinishFit(const OutlineResiduals& residuals, const Eigen::VectorXd& x,
               std::vector<Measurement>& ms, const FitOptions& options, FitOutcome* out);

}  // namespace igms::object
