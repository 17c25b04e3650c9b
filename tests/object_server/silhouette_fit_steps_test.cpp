// Each step of the silhouette fit (object_server/silhouette_fit_steps.h) on its own, on small
// synthetic images whose edges are known to a small fraction of a pixel: a flat square plate
// facing a stereo pair, and a disc. Then the whole fit on the same images, and its failures.
#include "object_server/silhouette_fit_steps.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>

#include "object_server/locate_steps.h"
#include "tests/object_server/rig_camera.h"

namespace igms::object {
namespace {

using testing::RigCamera;

// A square plate facing the cameras at y = 40: parameters (centre x, centre z, half side).
std::vector<Eigen::Vector3d> PlateOutline(const Eigen::VectorXd& p) {
  const double h = p[2];
  return {Eigen::Vector3d(p[0] - h, 40, p[1] - h), Eigen::Vector3d(p[0] + h, 40, p[1] - h),
          Eigen::Vector3d(p[0] + h, 40, p[1] + h), Eigen::Vector3d(p[0] - h, 40, p[1] + h)};
}

// A light convex polygon (image pixels) on a dark background, each pixel the polygon's share
// of it (drawn 8 times finer, then averaged), so its edges sit where the polygon's do.
cv::Mat DrawPolygon(const std::vector<Eigen::Vector2d>& polygon, cv::Size size = {256, 192}) {
  constexpr int kFine = 8, kShift = 4;
  cv::Mat fine(size.height * kFine, size.width * kFine, CV_8U, cv::Scalar(40));
  std::vector<cv::Point> points;
  points.reserve(polygon.size());
  for (const auto& p : polygon)  // pixel u spans [u - 0.5, u + 0.5)
    points.emplace_back(
        static_cast<int>(std::lround(((p.x() + 0.5) * kFine - 0.5) * (1 << kShift))),
        static_cast<int>(std::lround(((p.y() + 0.5) * kFine - 0.5) * (1 << kShift))));
  cv::fillConvexPoly(fine, points, cv::Scalar(200), cv::LINE_8, kShift);
  cv::Mat image;
  cv::resize(fine, image, size, 0, 0, cv::INTER_AREA);
  return image;
}

std::vector<Eigen::Vector2d> Circle(const Eigen::Vector2d& centre, double radius, int n) {
  std::vector<Eigen::Vector2d> out;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * M_PI * i / n;
    out.push_back(centre + radius * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return out;
}

// A view outline straight from image points, already a convex polygon in the hull's order
// (counter-clockwise with v taken as pointing up: Cross > 0 at every corner).
ViewOutline OutlineOf(const std::vector<Eigen::Vector2d>& points) {
  ViewOutline o;
  o.px = points;
  for (size_t i = 0; i < points.size(); ++i) {
    o.hull.push_back(static_cast<int>(i));
    o.position.push_back(static_cast<int>(i));
  }
  return o;
}

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Edge measurements on the outline of a plate with parameters p, every third sample.
std::vector<Measurement> PlateEdges(const Eigen::VectorXd& p,
                                    const std::array<geometry::ProjectiveCamera, 2>& cameras) {
  std::vector<Measurement> ms;
  for (int v = 0; v < 2; ++v) {
    ViewOutline o;
    EXPECT_TRUE(ProjectOutline(PlateOutline(p), cameras[v], o));
    const OutlineSamples s = SampleOutline(o);
    for (size_t i = 0; i < s.points.size(); i += 3) ms.push_back({v, s.points[i], s.segment[i]});
  }
  return ms;
}

// Rows `first` on of the Jacobian J at x against central differences of the residuals.
void ExpectCentralDifferences(const OutlineResiduals& residuals, const Eigen::VectorXd& x,
                              const std::vector<Measurement>& ms, const Eigen::MatrixXd& J,
                              Eigen::Index first, double tolerance) {
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    Eigen::VectorXd xp = x, xm = x;
    xp[k] += 1e-5;
    xm[k] -= 1e-5;
    Eigen::VectorXd rp, rm;
    std::vector<Measurement> mp = ms, mm = ms;
    ASSERT_TRUE(residuals.Residuals(xp, mp, rp, nullptr));
    ASSERT_TRUE(residuals.Residuals(xm, mm, rm, nullptr));
    ASSERT_EQ(rp.size(), J.rows());
    for (Eigen::Index i = first; i < J.rows(); ++i)
      EXPECT_NEAR(J(i, k), (rp[i] - rm[i]) / 2e-5, tolerance) << i << " " << k;
  }
}

// The plate rendered in both cameras, with the fit's views on it.
class PlateScene : public ::testing::Test {
 protected:
  void SetUp() override {
    truth_.resize(3);
    truth_ << 0.5, 1.0, 3.0;
    for (int v = 0; v < 2; ++v) {
      std::vector<Eigen::Vector2d> corners;
      for (const auto& X : PlateOutline(truth_)) corners.push_back(*cameras_[v].Project(X));
      images_[v] = DrawPolygon(corners);
      gradients_[v] = Gradients(images_[v], cv::Rect(0, 0, 256, 192), 1.0);
      views_[v] = FitView{&cameras_[v], &gradients_[v]};
    }
    options_.search_px = 6;
    options_.edge_blur_px = 0;  // straight edges: nothing to correct
  }
  // Edge measurements exactly on the true plate's outline, every few pixels along each side.
  std::vector<Measurement> TrueEdges() const { return PlateEdges(truth_, cameras_); }
  // Each view's region: the true plate's outline.
  void BoundByTruth() {
    for (int v = 0; v < 2; ++v) {
      ViewOutline o;
      ASSERT_TRUE(ProjectOutline(PlateOutline(truth_), cameras_[v], o));
      views_[v].region = o.px;
    }
  }

  const std::array<geometry::ProjectiveCamera, 2> cameras_ = {RigCamera(-3), RigCamera(3)};
  std::array<cv::Mat, 2> images_;
  std::array<Gradients, 2> gradients_;
  std::array<FitView, 2> views_;
  const OutlineFn plate_ = PlateOutline;
  Eigen::VectorXd truth_;
  FitOptions options_;
};

// --- 1. Projection ---

TEST_F(PlateScene, ProjectOutlineGivesACounterClockwiseHull) {
  ViewOutline o;
  ASSERT_TRUE(ProjectOutline(PlateOutline(truth_), cameras_[0], o));
  ASSERT_EQ(o.px.size(), 4u);
  ASSERT_EQ(o.hull.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    const Eigen::Vector2d& a = o.px[o.hull[i]];
    const Eigen::Vector2d& b = o.px[o.hull[(i + 1) % 4]];
    const Eigen::Vector2d& c = o.px[o.hull[(i + 2) % 4]];
    EXPECT_GT(Cross(b - a, c - b), 0);
    EXPECT_EQ(o.position[o.hull[i]], static_cast<int>(i));
  }
  // The plate's centre (0.5, 1) from x = -3 at 40 in: 35 px right of and 10 px above the
  // image centre; its side, 6 in, is 60 px.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : o.px) mean += p / 4;
  EXPECT_NEAR(mean.x(), 127.5 + 35, 1e-9);
  EXPECT_NEAR(mean.y(), 95.5 - 10, 1e-9);
  EXPECT_NEAR((o.px[1] - o.px[0]).norm(), 60, 1e-9);
}

TEST_F(PlateScene, ProjectOutlineRefusesPointsBehindTheCameraAndFlatOutlines) {
  ViewOutline o;
  std::vector<Eigen::Vector3d> points = PlateOutline(truth_);
  points[2].y() = -1;
  EXPECT_FALSE(ProjectOutline(points, cameras_[0], o));
  Eigen::VectorXd line = truth_;
  line[2] = 0;  // all four corners at one point
  EXPECT_FALSE(ProjectOutline(PlateOutline(line), cameras_[0], o));
}

// --- 2. Sampling and measuring ---

TEST(SilhouetteSteps, SampleOutlineSkipsSharpCornersAndPointsOutward) {
  // A 20 px square, in the hull's order.
  const ViewOutline square = OutlineOf({{100, 100}, {120, 100}, {120, 120}, {100, 120}});
  const OutlineSamples s = SampleOutline(square);
  // Samples every pixel of each side, none within 1.5 px of a corner: 2 .. 18 of 20.
  EXPECT_EQ(s.points.size(), 4u * 17);
  ASSERT_EQ(s.normals.size(), s.points.size());
  ASSERT_EQ(s.segment.size(), s.points.size());
  const Eigen::Vector2d centre(110, 110);
  for (size_t i = 0; i < s.points.size(); ++i) {
    EXPECT_NEAR(s.normals[i].norm(), 1, 1e-12);
    EXPECT_NEAR(s.normals[i].dot(s.points[i] - centre), 10, 1e-9);  // on the side, outward
    EXPECT_GE((s.points[i] - square.px[s.segment[i]]).norm(), 1.5);
  }
  EXPECT_TRUE(SampleOutline(OutlineOf({{0, 0}, {10, 0}})).points.empty());
}

TEST(SilhouetteSteps, SampleOutlineOfACircleHasItsCurvature) {
  const OutlineSamples s = SampleOutline(OutlineOf(Circle({100, 100}, 20, 64)));
  EXPECT_NEAR(static_cast<double>(s.points.size()), 2 * M_PI * 20, 2.0);  // no corner skipped
  for (const double k : s.curvature) EXPECT_NEAR(k, 1.0 / 20, 0.001);
}

TEST(SilhouetteSteps, TheSearchNarrowsPassByPass) {
  EXPECT_DOUBLE_EQ(SearchRange(0, 6), 6);
  EXPECT_DOUBLE_EQ(SearchRange(1, 6), 3.6);
  EXPECT_DOUBLE_EQ(SearchRange(2, 6), 2.4);
  EXPECT_DOUBLE_EQ(SearchRange(4, 6), 2.4);
  EXPECT_DOUBLE_EQ(SearchRange(1, 2), 2);    // never under 2 px in the second pass
  EXPECT_DOUBLE_EQ(SearchRange(2, 2), 1.5);  // nor 1.5 px later
}

TEST(SilhouetteSteps, MeasureSilhouetteEdgesFindsADiscsEdgeAndCorrectsItForBlur) {
  const Eigen::Vector2d centre(128, 96);
  const cv::Mat image = DrawPolygon(Circle(centre, 30, 256));
  const Gradients grad(image, cv::Rect(0, 0, 256, 192), 1.0);
  const ViewOutline inside = OutlineOf(Circle(centre, 28, 64));  // 2 px inside the edge
  FitOptions options;
  options.min_gradient = 6;
  int sampled = 0;
  const auto sharp = MeasureSilhouetteEdges(inside, 1, grad, 4, options, &sampled);
  EXPECT_NEAR(sampled, 2 * M_PI * 28, 2.0);
  ASSERT_EQ(static_cast<int>(sharp.size()), sampled);  // every sample finds the edge
  double mean = 0;
  for (const auto& m : sharp) {
    EXPECT_EQ(m.view, 1);
    EXPECT_EQ(m.a, -1);
    mean += (m.point - centre).norm() / static_cast<double>(sharp.size());
  }
  // The gradient peak of a blurred disc's edge lies inside it by about sigma^2 / 2R.
  EXPECT_NEAR(mean, 30 - 1.0 / 60, 0.1);

  // With the blur known, each measurement moves out by blur^2 * curvature / 2.
  options.edge_blur_px = 1.2;
  const auto corrected = MeasureSilhouetteEdges(inside, 1, grad, 4, options, &sampled);
  ASSERT_EQ(corrected.size(), sharp.size());
  for (size_t i = 0; i < sharp.size(); ++i)
    EXPECT_NEAR((corrected[i].point - centre).norm() - (sharp[i].point - centre).norm(),
                0.5 * 1.44 / 28, 0.002);

  // The edge 2 px away is beyond a 1 px search: nothing measured.
  EXPECT_TRUE(MeasureSilhouetteEdges(inside, 1, grad, 1, options, &sampled).empty());
  // Nor on an image without edges.
  const cv::Mat blank(192, 256, CV_8U, cv::Scalar(90));
  EXPECT_TRUE(MeasureSilhouetteEdges(inside, 1, Gradients(blank, cv::Rect(0, 0, 256, 192), 1.0), 4,
                                     options, &sampled)
                  .empty());
}

TEST_F(PlateScene, AKnownSolidInFrontHidesItsPartOfTheOutline) {
  ViewOutline o;
  ASSERT_TRUE(ProjectOutline(PlateOutline(truth_), cameras_[0], o));
  int sampled = 0;
  const auto all = MeasureSilhouetteEdges(o, 0, views_[0], 3.0, options_, &sampled);
  double top = 1e18, bottom = -1e18;
  for (const auto& p : o.px) {
    top = std::min(top, p.y());
    bottom = std::max(bottom, p.y());
  }
  const double mid = 0.5 * (top + bottom);
  // A solid in front over the plate's upper half: nothing measured or counted there.
  FitView hidden = views_[0];
  hidden.hidden = {{{-10, -10}, {300, -10}, {300, mid}, {-10, mid}}};  // as ConvexHull turns
  int sampled_hidden = 0;
  const auto seen = MeasureSilhouetteEdges(o, 0, hidden, 3.0, options_, &sampled_hidden);
  EXPECT_GT(seen.size(), 10u);
  EXPECT_LT(seen.size(), all.size());
  EXPECT_LT(sampled_hidden, sampled);
  EXPECT_EQ(all.size() - seen.size(), static_cast<size_t>(sampled - sampled_hidden));
  for (const auto& m : seen) EXPECT_GT(m.point.y(), mid - 1e-9);
}

TEST(SilhouetteSteps, MeasureInnerEdgesFindsTheEdgeBetweenTwoFaces) {
  // Two faces side by side inside one silhouette, meeting at u = 101.25 (fine pixel 814,
  // as DrawPolygon maps them).
  cv::Mat fine(192 * 8, 256 * 8, CV_8U, cv::Scalar(30));
  cv::rectangle(fine, cv::Rect(480, 160, 814 - 480, 800), cv::Scalar(120), cv::FILLED);
  cv::rectangle(fine, cv::Rect(814, 160, 320, 800), cv::Scalar(200), cv::FILLED);
  cv::Mat image;
  cv::resize(fine, image, {256, 192}, 0, 0, cv::INTER_AREA);
  const Gradients grad(image, cv::Rect(0, 0, 256, 192), 1.0);
  const geometry::ProjectiveCamera camera = RigCamera(0);
  const FitView view{&camera, &grad};
  // The edge predicted at u = 100 from v = 40 to 80; a point of each face either side.
  ViewOutline o;
  o.px = {{100, 40}, {100, 80}, {80, 60}, {120, 60}, {101, 60}};
  InnerEdge edge{{0, 1}, 2, 3};
  std::vector<Measurement> ms;
  MeasureInnerEdges({edge}, o, 0, view, 3, 6, ms);
  // Every pixel along it, 3 px clear of each end.
  ASSERT_EQ(ms.size(), 35u);
  for (const auto& m : ms) {
    EXPECT_EQ(m.a, 0);
    EXPECT_EQ(m.b, 1);
    EXPECT_NEAR(m.point.x(), 101.25, 0.1);
  }
  // A face narrower than the edge's min_width_px in the image: not measured.
  ms.clear();
  InnerEdge narrow{{0, 1}, 4, 3};  // face 1 px wide
  MeasureInnerEdges({narrow}, o, 0, view, 3, 6, ms);
  EXPECT_TRUE(ms.empty());
  // An edge under 10 px long: not measured.
  o.px[1] = Eigen::Vector2d(100, 48);
  MeasureInnerEdges({edge}, o, 0, view, 3, 6, ms);
  EXPECT_TRUE(ms.empty());
}

// --- 3. Refining ---

TEST(SilhouetteSteps, TheRobustCostIsHuberThenFlat) {
  EXPECT_DOUBLE_EQ(RobustCost(0.4, 0.5, 2), 0.5 * 0.16);
  EXPECT_DOUBLE_EQ(RobustCost(-1.5, 0.5, 2), 0.5 * (1.5 - 0.25));
  EXPECT_DOUBLE_EQ(RobustCost(9, 0.5, 2), RobustCost(2, 0.5, 2));
  EXPECT_DOUBLE_EQ(RobustWeight(-0.4, 0.5, 2), 1);
  EXPECT_DOUBLE_EQ(RobustWeight(1.0, 0.5, 2), 0.5);
  EXPECT_DOUBLE_EQ(RobustWeight(2.5, 0.5, 2), 0);
}

TEST_F(PlateScene, ResidualsAreSignedDistancesWithTheirJacobian) {
  const OutlineResiduals residuals(plate_, views_, Eigen::VectorXd::Constant(3, 1e-4));
  std::array<ViewOutline, 2> o;
  ASSERT_TRUE(residuals.Outlines(truth_, o));
  // The plate's right side in the left view, and points 2 px outside and 1 px inside it.
  const Eigen::Vector2d mid = 0.5 * (o[0].px[1] + o[0].px[2]);
  std::vector<Measurement> ms = {{0, mid + Eigen::Vector2d(2, 0), 1},
                                 {0, mid - Eigen::Vector2d(1, 0), 1},
                                 {1, 0.5 * (o[1].px[0] + o[1].px[1]), 0}};
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  ASSERT_TRUE(residuals.Residuals(truth_, ms, r, &J));
  ASSERT_EQ(r.size(), 3);
  EXPECT_NEAR(r[0], 2, 1e-9);
  EXPECT_NEAR(r[1], -1, 1e-9);
  EXPECT_NEAR(r[2], 0, 1e-9);
  // The Jacobian against central differences of the residuals.
  ASSERT_EQ(J.rows(), 3);
  ASSERT_EQ(J.cols(), 3);
  ExpectCentralDifferences(residuals, truth_, ms, J, 0, 1e-3);
  // Moving the plate 0.1 in to the right (1 px at 40 in) brings its side 1 px nearer the
  // outside point.
  Eigen::VectorXd moved = truth_;
  moved[0] += 0.1;
  ASSERT_TRUE(residuals.Residuals(moved, ms, r, nullptr));
  EXPECT_NEAR(r[0], 1, 1e-9);
  // Behind the camera there is nothing to measure against.
  const auto behind = [](const Eigen::VectorXd& p) {
    auto points = PlateOutline(p);
    for (auto& X : points) X.y() = -40;
    return points;
  };
  const OutlineResiduals away(OutlineFn(behind), views_, Eigen::VectorXd::Constant(3, 1e-4));
  EXPECT_FALSE(away.Residuals(truth_, ms, r, nullptr));
}

TEST_F(PlateScene, RefineParametersBringsTheOutlineOntoItsEdges) {
  const OutlineResiduals residuals(plate_, views_, Eigen::VectorXd::Constant(3, 1e-4));
  std::vector<Measurement> ms = TrueEdges();
  Eigen::VectorXd x = truth_;
  x[0] += 0.15;  // 1.5 px off
  x[1] -= 0.1;
  x[2] += 0.05;
  options_.inner_iterations = 10;
  RefineParameters(residuals, options_, 3.0, ms, x);
  EXPECT_NEAR(x[0], truth_[0], 1e-4);
  EXPECT_NEAR(x[1], truth_[1], 1e-4);
  EXPECT_NEAR(x[2], truth_[2], 1e-4);
  // Measurements beyond the outlier bound carry no weight: from 1.5 px off with a 1 px bound
  // nothing moves.
  Eigen::VectorXd y = truth_;
  y[2] += 0.15;  // every side 1.5 px outside its edge
  const Eigen::VectorXd before = y;
  ms = TrueEdges();
  RefineParameters(residuals, options_, 1.0, ms, y);
  EXPECT_EQ(y, before);
}

TEST_F(PlateScene, TheRegionAddsARowPerOutlinePointWithItsJacobian) {
  // Regions: the true plate's outline in each view. A plate 0.2 in larger (2 px a side) has
  // every corner beyond them.
  BoundByTruth();
  const double weight = 9;
  const OutlineResiduals residuals(plate_, views_, Eigen::VectorXd::Constant(3, 1e-4), weight);
  std::vector<Measurement> ms = TrueEdges();
  const auto measured = static_cast<Eigen::Index>(ms.size());
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  // Inside: a row per corner and view, each 0.
  ASSERT_TRUE(residuals.Residuals(truth_, ms, r, &J));
  ASSERT_EQ(r.size(), measured + 8);
  EXPECT_LT(r.tail(8).cwiseAbs().maxCoeff(), 1e-9);
  // Beyond: each corner 2 px out along both u and v, so 2 sqrt(2) px from the region's corner,
  // times sqrt(weight).
  Eigen::VectorXd larger = truth_;
  larger[2] += 0.2;
  ASSERT_TRUE(residuals.Residuals(larger, ms, r, &J));
  for (Eigen::Index i = measured; i < r.size(); ++i)
    EXPECT_NEAR(r[i], 3 * 2 * std::sqrt(2.0), 0.05) << i;
  ExpectCentralDifferences(residuals, larger, ms, J, measured, 1e-2);
}

TEST_F(PlateScene, TheRegionHoldsTheOutlineAgainstEdgesBeyondIt) {
  // Edges of a plate 0.3 in (3 px a side) larger than the region allows.
  Eigen::VectorXd larger = truth_;
  larger[2] += 0.3;
  const std::vector<Measurement> edges = PlateEdges(larger, cameras_);
  options_.inner_iterations = 20;
  // No region: the fit follows the edges.
  {
    const OutlineResiduals residuals(plate_, views_, Eigen::VectorXd::Constant(3, 1e-4));
    std::vector<Measurement> ms = edges;
    Eigen::VectorXd x = truth_;
    RefineParameters(residuals, options_, 4.0, ms, x);
    EXPECT_NEAR(x[2], larger[2], 0.01);
  }
  // The true plate's outline as the region, strongly weighted: the outline stays within a
  // small fraction of a pixel of it.
  BoundByTruth();
  const OutlineResiduals residuals(plate_, views_, Eigen::VectorXd::Constant(3, 1e-4), 100);
  std::vector<Measurement> ms = edges;
  Eigen::VectorXd x = truth_;
  RefineParameters(residuals, options_, 4.0, ms, x);
  EXPECT_NEAR(x[2], truth_[2], 0.02);
  EXPECT_NEAR(x[0], truth_[0], 0.02);
  EXPECT_NEAR(x[1], truth_[1], 0.02);
}

TEST(SilhouetteSteps, OutlineSettledComparesEveryPoint) {
  std::array<ViewOutline, 2> a;
  a[0] = OutlineOf({{0, 0}, {10, 0}, {10, 10}});
  a[1] = OutlineOf({{5, 5}, {15, 5}, {15, 15}});
  std::array<ViewOutline, 2> b = a;
  EXPECT_TRUE(OutlineSettled(a, b, 0.01));
  b[1].px[2].x() += 0.009;
  EXPECT_TRUE(OutlineSettled(a, b, 0.01));
  b[1].px[2].x() += 0.002;
  EXPECT_FALSE(OutlineSettled(a, b, 0.01));
}

TEST_F(PlateScene, FinishFitCountsOnlyMeasurementsWithinTheOutlierBound) {
  const OutlineResiduals residuals(plate_, views_, Eigen::VectorXd::Constant(3, 1e-4));
  std::vector<Measurement> ms = TrueEdges();
  const size_t exact = ms.size();
  std::array<int, 2> per_view{0, 0};
  for (const auto& m : ms) ++per_view[m.view];
  // Three strays 3 px outside the left view's top side (outlier_px is 2).
  ViewOutline o;
  ASSERT_TRUE(ProjectOutline(PlateOutline(truth_), cameras_[0], o));
  for (double t : {0.3, 0.5, 0.7}) {
    const Eigen::Vector2d p = o.px[2] + t * (o.px[3] - o.px[2]);
    ms.push_back({0, p + Eigen::Vector2d(0, -3), 2});
  }
  FitOutcome out;
  ASSERT_TRUE(FinishFit(residuals, truth_, ms, options_, &out));
  EXPECT_EQ(out.used[0], per_view[0]);
  EXPECT_EQ(out.used[1], per_view[1]);
  EXPECT_NEAR(out.rms_px[0], 0, 1e-9);
  EXPECT_NEAR(out.rms_px[1], 0, 1e-9);
  EXPECT_EQ(out.measured[0].size() + out.measured[1].size(), exact + 3);
  EXPECT_EQ(std::count(out.inlier[0].begin(), out.inlier[0].end(), false), 3);
  EXPECT_EQ(out.outline[0].size(), 4u);
  // The covariance: each point's error at least min_sigma_px, shared by 10 neighbours (the
  // plate's centre does not move when its outline shifts all round).
  ASSERT_EQ(out.covariance.rows(), 3);
  EXPECT_TRUE(out.covariance.allFinite());
  EXPECT_GT(out.covariance(0, 0), 0);
  options_.min_sigma_px = 0.8;
  FitOutcome wider;
  ASSERT_TRUE(FinishFit(residuals, truth_, ms, options_, &wider));
  EXPECT_NEAR(wider.covariance(0, 0), 4 * out.covariance(0, 0), 1e-6 * wider.covariance(0, 0));
  // A plate shrunk to a point has no outline: no outcome.
  Eigen::VectorXd point = truth_;
  point[2] = 0;
  FitOutcome none;
  EXPECT_FALSE(FinishFit(residuals, point, ms, options_, &none));
  EXPECT_TRUE(none.measured[0].empty());
}

TEST_F(PlateScene, TheCovarianceTakesInTheOutlineShiftedAllRound) {
  const OutlineResiduals residuals(plate_, views_, Eigen::VectorXd::Constant(3, 1e-4));
  const std::vector<Measurement> ms = TrueEdges();
  FitOutcome without, with;
  options_.outline_shift_px = 0;
  std::vector<Measurement> m0 = ms, m1 = ms;
  ASSERT_TRUE(FinishFit(residuals, truth_, m0, options_, &without));
  options_.outline_shift_px = 0.1;
  ASSERT_TRUE(FinishFit(residuals, truth_, m1, options_, &with));
  // Every side 0.1 px out: at depth 40 and focal length 400 px the half-size grows by 0.01,
  // the centre stays.
  const Eigen::MatrixXd added = with.covariance - without.covariance;
  EXPECT_NEAR(std::sqrt(added(2, 2)), 0.01, 1e-4);
  EXPECT_NEAR(added(0, 0), 0, 1e-9);
  EXPECT_NEAR(added(1, 1), 0, 1e-9);
}

TEST_F(PlateScene, ADirectionNoEdgeHoldsComesOutUnknown) {
  const OutlineResiduals residuals(plate_, views_, Eigen::VectorXd::Constant(3, 1e-4));
  // Only the plate's upright sides measured: they give its centre across and its size, and
  // nothing holds its height in the picture (as a pipe resting on a block hides its top).
  std::vector<Measurement> sides;
  for (const Measurement& m : TrueEdges()) {
    ViewOutline o;
    ASSERT_TRUE(ProjectOutline(PlateOutline(truth_), cameras_[m.view], o));
    double u0 = 1e18, u1 = -1e18;
    for (const auto& p : o.px) {
      u0 = std::min(u0, p.x());
      u1 = std::max(u1, p.x());
    }
    if (std::min(std::abs(m.point.x() - u0), std::abs(m.point.x() - u1)) < 1e-6) sides.push_back(m);
  }
  ASSERT_GT(sides.size(), 20u);
  FitOutcome out;
  ASSERT_TRUE(FinishFit(residuals, truth_, sides, options_, &out));
  EXPECT_LT(std::sqrt(out.covariance(0, 0)), 0.05);
  EXPECT_LT(std::sqrt(out.covariance(2, 2)), 0.05);
  EXPECT_GT(std::sqrt(out.covariance(1, 1)), 50.0);
}

// --- The whole fit ---

TEST_F(PlateScene, FitSilhouetteFindsThePlateInBothImages) {
  Eigen::VectorXd start = truth_;
  start[0] -= 0.3;  // 3 px off, within the first pass's search
  start[1] += 0.2;
  start[2] -= 0.2;
  const FitOutcome f = FitSilhouette(plate_, start, views_, options_);
  ASSERT_TRUE(f.ok) << f.error;
  EXPECT_NEAR(f.params[0], truth_[0], 0.01);
  EXPECT_NEAR(f.params[1], truth_[1], 0.01);
  EXPECT_NEAR(f.params[2], truth_[2], 0.01);
  EXPECT_LT(f.rms_px[0], 0.1);
  EXPECT_LT(f.rms_px[1], 0.1);
  EXPECT_GT(f.used[0], 0.9 * f.sampled[0]);
  EXPECT_GT(f.used[1], 0.9 * f.sampled[1]);
}

TEST_F(PlateScene, FitSilhouetteSaysWhyItFailed) {
  EXPECT_EQ(FitSilhouette(plate_, Eigen::VectorXd(), views_, options_).error,
            "a model needs 1 to 8 parameters");
  const OutlineFn behind = [](const Eigen::VectorXd& p) {
    auto points = PlateOutline(p);
    for (auto& X : points) X.y() = -40;
    return points;
  };
  EXPECT_EQ(FitSilhouette(behind, truth_, views_, options_).error,
            "the model went behind a camera");
  // 20 px clear of the plate in both views: nothing to measure within the search.
  Eigen::VectorXd lost = truth_;
  lost[0] += 8;
  lost[1] += 4;
  const FitOutcome f = FitSilhouette(plate_, lost, views_, options_);
  EXPECT_FALSE(f.ok);
  EXPECT_EQ(f.error, "too few edge points along the model's outline");
}

// Two plates side by side, each fitted perfectly from a start near it: with a plausibility
// test the fit it accepts wins, whichever start comes first and whatever the scores.
TEST(SilhouetteSteps, FitFromStartsPrefersAPlausibleFit) {
  const std::array<geometry::ProjectiveCamera, 2> cameras = {RigCamera(-3), RigCamera(3)};
  Eigen::VectorXd a(3), b(3);
  a << -4, 0, 2;
  b << 4, 0, 2;
  std::array<cv::Mat, 2> images;
  std::array<Gradients, 2> gradients;
  std::array<FitView, 2> views;
  for (int v = 0; v < 2; ++v) {
    std::array<std::vector<Eigen::Vector2d>, 2> corners;
    for (const auto& X : PlateOutline(a)) corners[0].push_back(*cameras[v].Project(X));
    for (const auto& X : PlateOutline(b)) corners[1].push_back(*cameras[v].Project(X));
    cv::max(DrawPolygon(corners[0]), DrawPolygon(corners[1]), images[v]);
    gradients[v] = Gradients(images[v], cv::Rect(0, 0, 256, 192), 1.0);
    views[v] = FitView{&cameras[v], &gradients[v]};
  }
  FitOptions fit;
  fit.search_px = 6;
  Eigen::VectorXd near_a = a, near_b = b;
  near_a += Eigen::Vector3d(0.1, -0.1, 0.05);
  near_b += Eigen::Vector3d(-0.1, 0.1, -0.05);
  const OutlineFn outline = PlateOutline;
  for (const bool want_right : {true, false}) {
    const PlausibleFn plausible = [&](const FitOutcome& f) {
      return (f.params[0] > 0) == want_right;
    };
    for (const auto& starts : {std::vector<Eigen::VectorXd>{near_a, near_b},
                               std::vector<Eigen::VectorXd>{near_b, near_a}}) {
      const FitOutcome f = FitFromStarts(outline, {}, starts, views, fit, plausible);
      ASSERT_TRUE(f.ok) << f.error;
      EXPECT_NEAR(f.params[0], want_right ? b[0] : a[0], 0.05);
      EXPECT_NEAR(f.params[2], 2, 0.05);
    }
  }
}

}  // namespace
}  // namespace igms::object
