// The steps of the locator (locate.h), each a function of its own so it can be tested alone.
// Locate() runs them in this order; the numbers are those of the pipeline in locate.h, the
// sections those of Cooke, "Interactive Graphical Model Building using Virtual Reality"
// (1993).
//
//  0. PrepareImages: both images grey and in ideal pixels, of the calibration's size.
//  1. MarkRegion: the marks' quadrilateral in the left image and their depth (3.6, 3.8).
//  2. FindBoundary, CheckBoundary: the object's strong edges inside the grown marked region
//     (3.8.1).
//  3. MatchObject, NarrowByRange, CheckMatch, TriangulateMatch: the object's patch
//     matched into the right image along the epipolar segment of the marks' depth range (3.6,
//     equation 3.30) and triangulated (3.7).
//  4. CylinderStarts / BoxStarts, then FitCylinder / FitBox: starting models from the
//     boundary at the matched depth (3.8.1, 3.8.2), fitted to both images' edges
//     (silhouette_fit.h).
//  5. CheckBothViews: the fit must explain both images.
//  Then CylinderFromFit / BoxFromFit (with BoxTextureRect) give the result, and CheckRange
//  holds the located solid against the ultrasonic range (2.1.5).
//
// A step that can stop the locator says why with a StepFailure: the reason code of the
// result and a detail for a person.
#pragma once

#include <Eigen/Core>
#include <array>
#include <functional>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/geometry/camera.h"
#include "object_server/image_ops.h"
#include "object_server/locate.h"
#include "object_server/silhouette_fit.h"

namespace igms::object {

struct StepFailure {
  Failure reason = Failure::kNone;
  std::string detail;
};

// A step's output, or why the locator stops there.
template <typename T>
class StepResult {
 public:
  StepResult(T value) : value_(std::move(value)) {}                  // NOLINT: implicit on purpose
  StepResult(StepFailure failure) : failure_(std::move(failure)) {}  // NOLINT
  bool ok() const { return value_.has_value(); }
  const T& operator*() const { return *value_; }
  const T* operator->() const { return &*value_; }
  const StepFailure& failure() const { return failure_; }

 private:
  std::optional<T> value_;
  StepFailure failure_;
};

// `v` in fixed notation with `precision` decimals, for the details.
std::string FormatFixed(double v, int precision = 2);

// The point on pixel p's ray at left-camera depth d.
Eigen::Vector3d PointOnPixelRay(const geometry::ProjectiveCamera& camera, const Eigen::Vector2d& p,
                                double depth);

// 0. Both images, grey and undistorted into ideal pixels (P maps to ideal pixels; the lens
// acts after it, as in OpenCV's model), with their cameras. Fails (bad input) when an image
// is empty, neither 8-bit grey nor BGR, or not of its camera's size.
struct StereoPair {
  cv::Mat left, right;
  const geometry::ProjectiveCamera* left_camera = nullptr;
  const geometry::ProjectiveCamera* right_camera = nullptr;
};
StepResult<StereoPair> PrepareImages(const LocateInput& in);

// 1. The marks in the left image: their convex hull is the operator's segmentation (3.8),
// their mean left-camera depth the depth estimate (trusted to the depth tolerance, 3.6).
// Fails when a mark is not finite (bad input), behind a camera or off to infinity in the left
// image, when the hull bounds under 16 square pixels (degenerate) or when less than half of
// it lies inside the left image.
struct MarkedRegion {
  std::vector<cv::Point2f> hull;  // counter-clockwise in the image, 3 or 4 points
  double depth = 0;               // mean left-camera depth of the marks
};
StepResult<MarkedRegion> MarkRegion(const LocateInput& in);

// The options of a pass whose gradient floor is the left image's noise over the marks
// (NoiseSigma): LocateOptions::retry_noise_gradient times its sigma, no lower than
// retry_min_edge_gradient. Nullopt when that pass is off, the marks do not hold, or the floor
// is no lower than min_edge_gradient.
std::optional<LocateOptions> NoiseFloorOptions(const LocateInput& in, const StereoPair& pair,
                                               LocateOptions options);

// 2. The left image's rectangle the boundary and its edge search need: `rect` grown by the
// edge search and the boundary's margin, within the image.
int RegionPad(const LocateOptions& options);
cv::Rect GrowRect(const cv::Rect& rect, int pad, const cv::Rect& image);
// The polygon grown outward from its vertices' mean by `by` pixels at every vertex (the thesis
// searches up to 15 px outward from the marks, 3.8.1: an outline the marks graze stays
// whole).
std::vector<cv::Point2f> GrowPolygon(const std::vector<cv::Point2f>& polygon, double by);
// The pixels of the largest 8-connected set among `pixels`, each grown by a pixel first (so
// gaps of up to two pixels are bridged).
std::vector<cv::Point> LargestConnected(const std::vector<cv::Point>& pixels);
// The object's boundary: the strong edge pixels inside the grown marked region (and on the
// edge map, when given), then of those the largest connected set, as the thesis follows the
// boundary from the marks (3.8.1): a neighbour's edge grazed by the margin must not widen
// its outline.
struct Boundary {
  std::vector<cv::Point2f> region;  // the grown marked region
  std::vector<cv::Point> pixels;
  double strongest = 0;  // the strongest gradient inside the region, grey levels per pixel
};
Boundary FindBoundary(const Gradients& left_gradients, const MarkedRegion& marks,
                      const cv::Mat& edge_map, const LocateOptions& options);
// Fails when the boundary is empty (no edge near the marks) or has fewer pixels than
// min_boundary_share of the marks' perimeter (edge count mismatch).
std::optional<StepFailure> CheckBoundary(const Boundary& boundary, const MarkedRegion& marks,
                                         const LocateOptions& options);

// The known solids (LocateInput::known) that can hide the object: those whose nearest point
// lies nearer to the left camera than the marks' depth plus half the depth tolerance, with
// their silhouette in each view grown by hidden_grow_px. A known solid whose left silhouette
// holds the marked region's centre is the object itself, modelled again, and is left out, as
// is one that does not project into both views (or lands over 1e5 px out).
struct KnownInFront {
  std::string name;
  std::array<std::vector<Eigen::Vector2d>, 2> outline;  // convex, counter-clockwise
};
std::vector<KnownInFront> KnownSolidsInFront(const LocateInput& in, const MarkedRegion& marks,
                                             const LocateOptions& options);
// The left image's pixels not behind a known solid (255), and not off the edge map when one
// is given: the boundary's candidates. Empty when nothing is in front and there is no map.
cv::Mat VisibleEdgeMask(const std::vector<KnownInFront>& in_front, const cv::Mat& edge_map,
                        cv::Size image_size);
// The names of the known solids in front of part of the marked region (its hull), for the
// operator: what may hide the object. Empty when none.
std::string NamesInFront(const std::vector<KnownInFront>& in_front,
                         const std::vector<cv::Point2f>& hull);

// 3. The object's patch in the left image (its boundary's rectangle and a 3 px margin) and
// the range of left-camera depths its match is searched over: the marks' depth +/- the
// tolerance, never nearer than half the marks' depth.
struct DepthSearch {
  Eigen::Vector2d centre;  // of the boundary's rectangle, left image
  cv::Rect patch;
  double near = 0, far = 0;
  // The patch's pixels within match_band_px of a boundary pixel (8-bit, the patch's size):
  // the object's own edges and what lies just beside them. Empty when match_band_px is 0.
  cv::Mat band;
};
DepthSearch ObjectDepthSearch(const std::vector<cv::Point>& boundary, double mark_depth,
                              const LocateOptions& options);
// The patch matched into the right image by the smallest SSD (3.6, equation 3.30) along the
// epipolar segment of left-camera depths near..far. When the whole patch leaves the right
// image at every depth, the part of it that stays in at every depth is matched (at least 8 px
// each way); not ok when the segment does not project or that part is smaller. `banded`:
// the search's band of the patch alone.
SsdMatch MatchBetweenDepths(const StereoPair& pair, const DepthSearch& search, double near,
                            double far, bool banded = false);
// The match over the search's depth range. Fails (match over threshold) when there is none:
// the search region leaves the right image. A whole patch correlating under min_match_zncc
// is matched again on its band alone (a thin object beside another at another depth, the
// patch mostly the other's): that match is taken when it reaches min_match_zncc.
StepResult<SsdMatch> MatchObject(const StereoPair& pair, const DepthSearch& search,
                                 const LocateOptions& options);
// With a range, the match searched again around the range's depth (the beam's axis point at
// the range, when it falls inside the marked region and agrees with the marks' depth); kept
// unless it matches clearly worse than `match` (then the beam met something else). Fills
// `check`'s used, measured and constrained; returns the match to go on with.
SsdMatch NarrowByRange(const LocateInput& in, const StereoPair& pair, const DepthSearch& search,
                       const Boundary& boundary, double mark_depth, const SsdMatch& match,
                       const LocateOptions& options, RangeCheck* check);
// Fails (match over threshold) when the match's normalised cross-correlation is under
// min_match_zncc.
std::optional<StepFailure> CheckMatch(const SsdMatch& match, const LocateOptions& options);
// Midpoint triangulation of a left and a right pixel, or nullopt when their rays are
// parallel.
std::optional<Eigen::Vector3d> TriangulateMidpoint(const geometry::ProjectiveCamera& left_camera,
                                                   const Eigen::Vector2d& left_pixel,
                                                   const geometry::ProjectiveCamera& right_camera,
                                                   const Eigen::Vector2d& right_pixel);
// The match's 3D point by midpoint triangulation (Cooke, 3.7: only a starting depth, so the
// simplest), or nullopt when the rays are parallel.
std::optional<Eigen::Vector3d> TriangulateMatch(const StereoPair& pair, const DepthSearch& search,
                                                const SsdMatch& match);
// The right image's rectangle the fit's edge search needs: the patch moved by the match, grown
// like the left's.
cv::Rect RightRegion(const DepthSearch& search, const SsdMatch& match, int pad,
                     const cv::Rect& image);

// Where the object's outline can lie, per view (FitView::region): in the left image the
// marked region grown by boundary_grow_px, as the marks bound the object snugly (3.8); in
// the right image what the rays through that region's corners meet between left-camera
// depths near and far. Empty regions (no bound) when a point does not project.
std::array<std::vector<Eigen::Vector2d>, 2> OutlineRegions(const MarkedRegion& marks,
                                                           const StereoPair& pair, double near,
                                                           double far,
                                                           const LocateOptions& options);

// 4. Starting models. A cylinder (3.8.1) from the boundary's smallest rotated rectangle: its
// long side the axis, its short side the diameter at the matched depth (`depth`, of the front
// surface). Its silhouette's ends lie beyond the cap centres by up to the radius, depending
// on the view: the caps start halfway. A pipe lying towards the cameras has its ends at
// different depths, which one depth for both cannot start from: each end's patch is matched
// into the right image on its own (within the marks' depth range, widened by the pipe's
// length across the view) and, when the two ends' depths differ by more than the radius, that
// tilted cylinder is a second start.
// With the left image's gradients, one more start from the boundary's limb pixels alone
// (those whose gradient follows its dominant orientation): a pipe raised on blocks without the
// blocks' edges. With `raised` too, into it, starts for a pipe raised on something: from the
// upper limb alone (the limb line nearest the image's top) with a lower limb at three guessed
// depths below it, for a raised pipe whose lower limb the blocks or the background hide from
// the boundary; and from the boundary's upper half and upper two thirds alone
// (kRaisedPipeShares), for a pipe lying on a block whose outline merges with the block's (a
// pipe pointing at the cameras shows no limb line), unless `with_upper_part` is off. And,
// into `crossing`, a pipe leaning across the block it rests on, at any tilt: from the pixels
// along two lines at each of the boundary's two strongest orientations (whichever of the pipe
// and the block dominates it), each with its tilted start too.
struct RaisedPipeStarts {
  bool with_upper_part = true;
  std::vector<Eigen::VectorXd> upper_limb;
  std::vector<Eigen::VectorXd> upper_part;
  std::vector<Eigen::VectorXd> crossing;  // a pipe leaning across a block, any tilt
};
std::vector<Eigen::VectorXd> CylinderStarts(const StereoPair& pair,
                                            const std::vector<cv::Point>& boundary, double depth,
                                            const DepthSearch& search, const LocateOptions& options,
                                            const Gradients* gradients = nullptr,
                                            RaisedPipeStarts* raised = nullptr);
// The cylinder start stretched along its image axis to fill the marked rectangle (shrunk by
// `margin`, world units, and the radius): the part of a pipe against a dark background has
// the strongest edges, and the boundary can stop where its background changes. nullopt when
// it would not grow.
std::optional<Eigen::VectorXd> CylinderStretchedToMarks(const Eigen::VectorXd& start,
                                                        const MarkedRegion& marks,
                                                        const geometry::ProjectiveCamera& camera,
                                                        double margin);
// A cylinder fit collapsed onto one limb (under min_radius_px: the other limb gave the fit no
// edge it kept, as on a raised pipe over a dark gap): the pipes that limb bounds, their axis
// moved off it across the view (perpendicular to the axis and the line of sight from the
// camera) to either side by their radius, with radii of kLimbRadiusShares of the marks'
// extent that way. Empty when the fit has no axis or looks along it.
inline constexpr std::array<double, 3> kLimbRadiusShares = {0.15, 0.25, 0.35};
std::vector<Eigen::VectorXd> PipesBesideLimb(const Eigen::VectorXd& collapsed,
                                             const std::array<Eigen::Vector3d, 4>& marks,
                                             const geometry::ProjectiveCamera& camera);
// A block (3.8.2), world-axis-aligned: the boundary back-projected onto its front plane at
// `depth` gives the two extents across the view; the one along the view starts as their
// mean. That depth is the least seen (a side face's strip, a sliver of the top), so two more
// starts take 0.4 and 1.8 times it.
// With the left image's gradients, three more starts from the boundary between the block's
// outermost vertical edges, when those lie inside it: a block under a pipe without the
// pipe's ends. Then, for each yaw over 5 degrees its horizontal edges show
// (HorizontalEdgeYaws, at most two), a turned start from each of those boundaries: its near
// bottom corner at the boundary's lowest pixel, its bottom edges receding along the yaw to the
// boundary's sides and its far top corner at the boundary's top. FitBox fits these turned.
// With `if_poor` too, into it, the boundary between the vertical edges turned by each of
// kInnerTurnsDeg (+-18 and +-36 degrees), for FitBox to try when the world-aligned fit is
// poor: where something beside the block widens its boundary (a pipe's end resting on it),
// the boundary's edges give the block's yaw poorly.
std::vector<Eigen::VectorXd> BoxStarts(const geometry::ProjectiveCamera& left_camera,
                                       const std::vector<cv::Point>& boundary, double depth,
                                       const Gradients* gradients = nullptr,
                                       std::vector<Eigen::VectorXd>* if_poor = nullptr);
// The yaws of a block's horizontal edges, folded into [-45, 45) degrees (radians out): each
// boundary pixel's edge back-projected to the horizontal direction that projects along it at
// `depth`. The peaks of a gradient-weighted histogram in 2-degree bins, strongest first, at
// least 10 degrees apart and at least 0.75 of the strongest; at most `count`. Edges near the
// image's vertical say nothing (a block's vertical edges, a horizontal one pointing at the
// camera) and are left out.
std::vector<double> HorizontalEdgeYaws(const geometry::ProjectiveCamera& left_camera,
                                       const std::vector<cv::Point>& boundary, double depth,
                                       const Gradients& gradients, int count);
// The three starts from the given boundary pixels alone.
std::vector<Eigen::VectorXd> BoxStartsFrom(const geometry::ProjectiveCamera& left_camera,
                                           const std::vector<cv::Point>& boundary, double depth);
// The fit's settings from the locator's, given the boundary's strongest gradient and the
// images' width (0: the reference camera's; see LocateOptions::sigma_width_power).
FitOptions FitSettings(const LocateOptions& options, double strongest, int image_width = 0);
// How well a fit explains both images: the views' RMS residuals (times residual_scale) plus
// twice the share of outline samples without an edge; lower is better, 1e18 for a failed fit.
double FitScore(const FitOutcome& fit, double residual_scale = 1.0);
// The residual_scale that puts an image's residuals in the reference camera's pixels
// (LocateOptions::score_reference_width_px, score_width_power).
double ScoreResidualScale(const LocateOptions& options, int image_width);
// Of several starts, the one that explains both images best after two passes goes on to the
// rest of the passes (one start: all passes at once).
// With `plausible`, a fit it accepts is preferred to any it refuses, whatever their scores
// (a pipe's half against a dark background explains its edges better than the whole pipe,
// but leaves the marks' lower half empty).
using PlausibleFn = std::function<bool(const FitOutcome&)>;
// A box fit that kept a depth: one that flattened the box explained nothing (the turned box's
// faces drawn as one). A failed fit has no parameters to look at.
bool IsSolid(const FitOutcome& o);
// Whether fit a goes before fit b: a plausible one first, then the lower FitScore.
bool BetterFit(const FitOutcome& a, const FitOutcome& b, const PlausibleFn& plausible);
// With no start, a failed fit: "no starting model to fit from".
FitOutcome FitFromStarts(const OutlineFn& outline, const InnerEdgesFn& inner,
                         const std::vector<Eigen::VectorXd>& starts,
                         const std::array<FitView, 2>& views, const FitOptions& fit,
                         const PlausibleFn& plausible = {});
FitOutcome FitCylinder(const std::vector<Eigen::VectorXd>& starts,
                       const std::array<FitView, 2>& views, const FitOptions& fit,
                       const LocateOptions& options, const PlausibleFn& plausible = {});
// A world-aligned box (the thesis's block, 3.8.2) as a function of its first six parameters,
// its yaw held at 0: the seven parameters, its outline, and `inner` (when given) on them.
Eigen::VectorXd WithZeroYaw(const Eigen::VectorXd& p6);
struct AlignedBox {
  OutlineFn outline;
  InnerEdgesFn inner;
};
AlignedBox AlignedBoxModel(const InnerEdgesFn& inner);
// The thesis's block first: world-aligned (yaw held at 0), which the faces' edges pin down
// well. Only when its outline misses the edges (or it came out flat) is the box turned:
// from five yaws and the starts `if_poor` (BoxStarts), kept when it explains the images
// clearly better (a turned box seen nearly face-on can trade yaw against depth and fit about
// as well, wrongly).
FitOutcome FitBox(const std::vector<Eigen::VectorXd>& starts, const std::array<FitView, 2>& views,
                  const FitOptions& fit, const LocateOptions& options,
                  const PlausibleFn& plausible = {},
                  const std::vector<Eigen::VectorXd>& if_poor = {});

// A fitted pipe's side as one image shades it: the mean grey level across the side (bins
// evenly spread in the sine of the angle round the axis, clear of the limbs by 2 px; the
// middle 60% of the length; not where a known solid hides it), fitted three ways, residuals
// weighted by each bin's sample count: flat (its mean); round, as a Lambertian side under
// distant lights shades (a constant and the first two harmonics of the angle); and creased, as
// two flat faces of a block meeting. Not measured when the side is under 12 px across (8 px
// with `half_pixel_bins`: bins half a pixel wide there) or 6 px long.
struct SideShading {
  bool measured = false;
  int bins = 0;
  double flat_rss = 0, smooth_rss = 0, step_rss = 0;
  double mean = 0, smooth_range = 0;  // the mean grey level; the smooth fit's max - min
  // The best crease's place across the side (the sine of its angle round the axis, -1 to 1
  // along the axis crossed with the direction toward the camera) and its step in grey levels.
  double step_sine = 0, step_contrast = 0;
};
SideShading MeasureSideShading(const cv::Mat& image, const geometry::ProjectiveCamera& camera,
                               const Eigen::VectorXd& params,
                               const std::vector<std::vector<Eigen::Vector2d>>& hidden,
                               bool half_pixel_bins = true);
// A fitted pipe's two limbs in one image: each one's grey levels outward from the fitted limb line,
// every 0.25 px from -inside to +outside, averaged along the middle 60% of the side, and where
// the fit's edge search (EdgeAlongNormal over min_gradient) finds it on the same lines
// (pixels, outward positive). nullopt for a limb mostly hidden, out of view, or whose edge the
// search finds on under 6 lines.
struct LimbProfile {
  double r_px = 0, inside = 0, outside = 0;
  std::vector<double> grey;
  double peak = 0;
};
std::array<std::optional<LimbProfile>, 2> LimbProfiles(
    const cv::Mat& image, const geometry::ProjectiveCamera& camera, const Gradients& gradients,
    const Eigen::VectorXd& params, const std::vector<std::vector<Eigen::Vector2d>>& hidden,
    double min_gradient);
// How far outside where the edge search finds them the limbs' silhouette lies (pixels, mean
// over the limbs): a Lambertian side's shade changes fastest at its limb, seen edge on, and
// the blurred step's gradient peaks inside it. Each profile is fitted as a step from the
// side's shade (a constant and the cosine and sine of the angle round the axis) to the
// background, through one Gaussian camera blur shared by all the limbs. A limb counts when its
// step is clear: at least min_step grey levels, within 2 px of the search's edge, and the
// model explaining its profile to 2% of the step (RMS); nullopt when none is.
std::optional<double> LimbEdgeShift(const std::vector<LimbProfile>& limbs, double min_step);

// A found pipe (`f`, its result in `res`) fitted again for its last pass with its
// limbs' edges moved out by LimbEdgeShift over the limbs LimbProfiles gives in both views
// (at most LocateOptions::max_limb_shading_px): its radius goes into `res`; its axis, ends,
// sigmas and everything the checks judged stay the first fit's.
void RefineLimbsForShading(const StereoPair& pair, const std::array<FitView, 2>& views,
                           const FitOptions& fit, const LocateOptions& opt, const FitOutcome& f,
                           CylinderResult* res);

// Whether q lies inside the image, with a pixel to spare for the interpolation, and outside
// every `hidden` polygon: a sample that can be read.
bool SeenInImage(const cv::Mat& image, const std::vector<std::vector<Eigen::Vector2d>>& hidden,
                 const Eigen::Vector2d& q);
// A found block's silhouette edges beside a seen face at most max_face_px wide in the image:
// blurred together with the face's other edge, the outer edge's gradient peak moves off the
// true outline (outward beside a face brighter than the one beyond it). Per outline point
// (BoxOutline's corners), how far out of where the edge search finds it the hull segment
// starting there lies: each such edge's grey-level profile, averaged along its middle 60%,
// fitted as the face between the next face's shade and the background's through a Gaussian
// blur (0.5-1.3 px); 0 where the step is not clear (8 grey levels, misfit 5% of it).
std::vector<double> BoxFaceShifts(const cv::Mat& image, const geometry::ProjectiveCamera& camera,
                                  const Gradients& gradients, const Eigen::VectorXd& x,
                                  const std::vector<std::vector<Eigen::Vector2d>>& hidden,
                                  double min_gradient, double max_face_px);
// A found block fitted again for its last pass with those edges moved (each by at most
// LocateOptions::max_face_shading_px): its parameters replace the fit's; its covariance and
// everything the checks judged stay the first fit's.
void RefineBoxForFaces(const StereoPair& pair, const std::array<FitView, 2>& views,
                       const FitOptions& fit, const LocateOptions& opt, FitOutcome* f);

// How a fitted pipe's side shades in both images: creased when in both a crease between two
// flat faces explains it `crease_gain` times better than the smooth fit; flat when in both it
// is creased or the smooth fit explains it less than `flat_side_gain` times better than its
// mean does; clearly round when in both the smooth fit explains it at least `round_side_gain`
// times better; faintly round when round, but in either image under `faint_round_side_gain`
// times better; round otherwise; unmeasured when an image cannot tell (MeasureSideShading).
// Even when in both neither the smooth fit nor the crease explains it `even_side_gain` times
// better than its mean does: no shading at all (one face seen square on).
enum class SideShape { kUnmeasured, kRound, kClearlyRound, kFlat, kCreased, kEven, kFaintlyRound };
SideShape ClassifySide(const StereoPair& pair, const Eigen::VectorXd& params,
                       const std::array<FitView, 2>& views, const LocateOptions& options);

// Where two faces of a fitted block meet as the images shade it: across the block, its
// shading steps (a crease explains it face_crease_gain times better than its mean, by at
// least min_face_crease_step grey levels) in both images at the same place (to
// face_crease_agree of its half width). The crease's offset across the view from the block's
// centre (along the horizontal perpendicular to the line of sight from the left camera: up
// cross toward the camera); nullopt when none is seen.
std::optional<double> FaceCrease(const StereoPair& pair, const Eigen::VectorXd& box,
                                 const std::array<FitView, 2>& views, const LocateOptions& opt);
// Whether the block's vertical edge nearest `eye` stands at that crease (to face_crease_agree
// of its half width): a block fitted as one face where the images show two does not.
bool EdgeAtCrease(const Eigen::VectorXd& box, double crease, const Eigen::Vector3d& eye,
                  const LocateOptions& opt);
// Blocks turned so that their nearest vertical edge stands at that crease, in front of the
// fitted block's extent across the view and as high: the face left of the crease at each of
// kCreaseTurnsDeg to the view, the other square to it, each spanning its side of the extent.
inline constexpr std::array<double, 3> kCreaseTurnsDeg = {30.0, 45.0, 60.0};
std::vector<Eigen::VectorXd> CreaseStarts(const Eigen::VectorXd& box, double crease,
                                          const Eigen::Vector3d& camera_centre);

// Whether the background changes across a pipe's axis beside its end (`end`, the axis's image
// direction `dir`, its radius in pixels): an edge along the axis within a few pixels of the
// end, just outside either limb, over min_gradient. The table's far edge behind an upright
// pipe: the pipe turns to the background's shade there, and its outline may stop there too.
bool BackgroundChangesBeside(const Gradients& gradients, const Eigen::Vector2d& end,
                             const Eigen::Vector2d& dir, double radius_px, double min_gradient);
// Whether a pipe's fitted foot (its lower end) lies where the background changes beside it in
// the left image: the table's far edge may hold it there.
bool FootAtBackgroundChange(const std::array<FitView, 2>& views, const FitOptions& fit,
                            const FitOutcome& f);

// A fitted pipe's end that no edge holds (its sigma along the axis at least
// LocateOptions::unheld_end_sigma: a foot of the table's shade, a cap against the dark) moved
// to where its limbs end in both images (the limb edges the fit kept, walked out from their
// middle; the views must agree to limb_end_agree_px), and its sigma along the axis set from
// limb_end_sigma_px: the silhouette's ends (Cooke, 3.8.1). Not where the background beside
// the limbs' end changes along the axis by more than fit.min_gradient: the limbs may stop
// there because the pipe turns to the background's shade. The outline is drawn again; the
// fit's edge counts are left as they were.
void EndsFromLimbs(const std::array<FitView, 2>& views, const FitOptions& fit,
                   const LocateOptions& opt, FitOutcome* f);
// An upright pipe's foot fitted more than LocateOptions::floor_sink below the site's floor
// (LocateOptions::floor_height) moved up along its axis onto the floor, and measured there
// to floor_sink along the axis. Nothing stands in the floor: the fit drew the foot down where
// the table's shade or pattern gave no edge to stop it, the marks lying below it. A foot from
// there up to pipe_floor_gap above the floor stands on it, and the floor measures it to
// pipe_floor_gap along the axis (a Kalman update of the fit, so a foot held by its edges
// moves little): a foot of the table's shade, or behind what stands in front, no edge holds,
// and its length came out unknown. The outline is drawn again; the fit's edge counts are left
// as they were.
void FootOnFloor(const std::array<FitView, 2>& views, const LocateOptions& opt, FitOutcome* f);
// Fails (fit failed) when a found box's size, or a found pipe's length, has a sigma over
// max_box_size_sigma (the images leave it open), or the pipe is shorter than its radius.
std::optional<StepFailure> CheckBoxSizesDetermined(const BoxResult& box, const LocateOptions& opt);
std::optional<StepFailure> CheckCylinderLengthDetermined(const CylinderResult& c,
                                                         const LocateOptions& opt);

// A fitted block whose silhouette sides' edges, walked up from their middle in both images,
// stop short of its top (the second-highest of the four under LocateOptions::box_side_reach
// of its height, and 3 px or more below it): the same block with its top there. A pipe
// resting on the block, its end rising above it, carries the fit's top up to its own, along
// no edge of the block's sides; a neighbour's edge in line with one side can carry that side
// on up. Sides a known solid in front hides in part are not counted. nullopt when the sides
// run to the top or say nothing (no edge half way up one of them).
std::optional<Eigen::VectorXd> TopFromSides(const std::array<FitView, 2>& views,
                                            const FitOptions& fit, const LocateOptions& opt,
                                            const FitOutcome& f);

// 5. Which parts of the fitted outline should show an edge, per view: sampled every pixel
// along it (away from its corners), a sample counts when it lies inside the image and the
// grey levels either side of it differ enough for the fit's edge detector to see a step
// there (against the image's own noise, estimated from it). Of those, how many have an edge
// within a pixel and a half. Parts hidden by an object in front (its surface runs across
// the outline) and parts against a background of the object's own shade show no step and do
// not count against the fit.
struct OutlineSupport {
  int samples = 0;         // along the outline
  int outside = 0;         // beyond the image's edge
  int hidden = 0;          // inside, behind a known solid (FitView::hidden)
  int contrasted = 0;      // inside, with a step the detector can see
  int edged = 0;           // of those, with an edge on the outline
  double noise_sigma = 0;  // the image's noise near the object, grey levels
  // Per side of the outline, by its outward normal (image left, right, top, bottom): the
  // samples in the image and not hidden, and those with an edge on the outline, whatever the
  // step across it. Counted only when asked for (an edge searched at every sample).
  std::array<int, 4> side_samples{0, 0, 0, 0};
  std::array<int, 4> side_edged{0, 0, 0, 0};
};
// A side with fewer samples than this in a view is too short to judge there.
constexpr int kMinSideSamples = 8;
OutlineSupport MeasureOutlineSupport(const std::vector<Eigen::Vector2d>& outline,
                                     const cv::Mat& image, const Gradients& gradients,
                                     const FitOptions& fit,
                                     const std::vector<std::vector<Eigen::Vector2d>>& hidden = {},
                                     bool per_side = true);
// FitScore with the share without an edge taken, as CheckBothViews takes it, of the samples
// that should show one (OutlineSupport::contrasted, both views together): an outline against
// a background of the object's own shade, hidden by an object in front or beyond the image
// does not count against the fit. Without such samples, FitScore's share of all of them.
double SupportedFitScore(const FitOutcome& fit, const std::array<OutlineSupport, 2>& support,
                         double residual_scale = 1.0);
// Fails (occluded) when more than max_outside_share of either view's outline lies beyond the
// image or less than min_contrast_share of it shows a step (something in front hides it, or
// it blends into what lies behind): the model would rest on a part of the object.
std::optional<StepFailure> CheckOutlineVisible(const std::array<OutlineSupport, 2>& support,
                                               const LocateOptions& options);
// Fails (fit failed) when the fitted outline in the left image leaves more than
// max_mark_gap of the marks' bounding rectangle empty on a side, or runs beyond it by more
// than max_beyond_marks_px: the marks bound the object snugly.
// With `left_empty`, says whether it failed for a side left empty.
std::optional<StepFailure> CheckWithinMarks(const std::vector<Eigen::Vector2d>& left_outline,
                                            const MarkedRegion& marks,
                                            const geometry::ProjectiveCamera& left_camera,
                                            const LocateOptions& options,
                                            bool* left_empty = nullptr);
// Fails (left-right inconsistent) when either image has too few outline samples on an
// edge or a too large RMS residual: background edges picked up in one view only. With the
// outline's support, the share is of the samples that should show an edge.
std::optional<StepFailure> CheckBothViews(const FitOutcome& fit, const LocateOptions& options,
                                          const std::array<OutlineSupport, 2>* support = nullptr);
// Fails (left-right inconsistent) when a side of an upright pipe's outline (its left or right
// limb, OutlineSupport's sides 0 and 1) has an edge along much of it in one image and little
// in the other (their shares differ by more than max_limb_edge_difference): a pipe's limb
// lies against much the same background in both, where an outline run onto a neighbour's
// edge in one view finds nothing at the depth that view gives it in the other.
std::optional<StepFailure> CheckLimbsAgree(const std::array<OutlineSupport, 2>& support,
                                           const LocateOptions& options);
// Whether a pipe's outline has an edge along at least min_shown_side_share of its left, right
// and top sides in both images (OutlineSupport's sides 0, 1 and 2; a side under
// kMinSideSamples long is not judged): all of it but its bottom, an upright's foot, which can
// stand against a table of its own shade. An upright let past max_fit_score must show that
// much.
bool ShowsAllButFoot(const std::array<OutlineSupport, 2>& support, const LocateOptions& opt);
// Whether to fit the other type too: for a box always, since a box fits an upright cylinder's
// outline (its end ellipses seen thin) about as well as the cylinder does, while a real box's
// corners leave a cylinder well behind; for a cylinder when it explains the images only fairly
// (other_type_score) or its side does not shade round or only faintly (ClassifySide).
bool WantOtherType(bool cylinder, const FitOutcome& f, SideShape side, const LocateOptions& opt);

// Whether a box fit leaves its depth open: a horizontal size's sigma at least
// LocateOptions::min_open_depth_sigma.
bool DepthLeftOpen(const FitOutcome& box, const LocateOptions& opt);

// The other type's fit against this one's: a cylinder is refused when a box explains the
// outline much better (`other_type_ratio`), a box unless it clearly beats a cylinder
// (`box_over_cylinder`). A box the marks do not bound (`other_within_marks` false: it leaves
// part of them empty or runs beyond them, as it does on the top half of a cylinder whose
// bottom stands against the table) explains part of the object, and is not held against a
// cylinder; a cylinder is held against a box wherever it lies, so a box must beat them all.
// Both fits' scores in the reference camera's pixels (ScoreResidualScale): FitScore and
// SupportedFitScore, this fit's and the other's.
struct TypeScores {
  double fit = 0, other_fit = 0, supported = 0, other_supported = 0;
};
// Either is judged on the outline that should show an edge too (SupportedFitScore), against
// an other type that explains the images (under max_fit_score): a cylinder is refused when a
// box does `other_type_ratio` times better there, a box unless it does at least as well
// (box_over_cylinder_supported).
// `side` is how the cylinder's side shades (ClassifySide): this fit's, or for a box the other
// one's. A cylinder whose side is creased is refused whatever the box; one whose side is flat
// when a box the marks bound fits at all (both views explained, under max_fit_score). A box
// is not held against a cylinder whose side is creased; against one whose side is clearly
// round and that fits at all, it must also do `box_over_cylinder` times better on the
// outline that should show an edge. A cylinder whose side is clearly round is held against a
// box on that outline alone. A box whose rival's side shades flat or even is let through
// when its fit leaves its depth open (DepthLeftOpen): a block seen square on.
std::optional<StepFailure> CheckOtherType(bool cylinder, const FitOutcome& f,
                                          const FitOutcome& other, bool other_within_marks,
                                          SideShape side, const TypeScores& scores,
                                          const LocateOptions& opt);

// The result from the fit's parameters, with one standard deviation from its covariance. A
// cylinder's axis points up (along +x when level); it is left as the default when the
// cylinder has no size.
CylinderResult CylinderFromFit(const Eigen::VectorXd& params, const Eigen::MatrixXd& covariance);
// Everything but the texture, which BoxTextureRect and the left image give.
BoxResult BoxFromFit(const Eigen::VectorXd& params, const Eigen::MatrixXd& covariance);
// A block whose height the images leave open (its size's sigma over max_box_size_sigma: its
// top hidden) under a known pipe passing over its footprint (widened by known_reach_sigmas of
// its centre's deviation) reaches up to the pipe's underside, as a block carrying it does: its
// height is then from its bottom to there, with both their sigmas. Otherwise, or with no such
// pipe, the box is left as it is.
void ReachUpToKnown(const std::vector<KnownShape>& known, const LocateOptions& options,
                    BoxResult* box);
// The box's deviations (sizes, centre, extent, yaw) widened for a fit that explains the edges
// less well: by 1 + LocateOptions::box_sigma_score_gain times its score above
// box_sigma_score_floor. On the tuning and held-out seeds, of the blocks found scoring under
// 0.2, 1.3% of the errors lay beyond 2 sigma; from 0.35 to 0.5, 15%; from 0.5 up, 24-31%.
void WidenForFitScore(double score, const LocateOptions& options, BoxResult* box);
// The box's pixels in the left image (its corners' bounding rectangle), within `image`.
// Fails (fit failed) when a corner does not project into the left image.
StepResult<cv::Rect> BoxTextureRect(const Eigen::VectorXd& params,
                                    const geometry::ProjectiveCamera& left_camera,
                                    const cv::Rect& image);

// The left image's pixels in `rect`, in its own colours (grey or BGR) and ideal pixels: the
// patch for texture mapping (3.8.2).
cv::Mat LeftTexture(const LocateInput& in, const cv::Rect& rect);

// The range against the located solid (RangeCheck in locate.h): fills `check`'s expected
// ranges, whether it agrees and why not.
void CheckRange(const LocateInput& in, const LocateOptions& options, const Eigen::VectorXd& params,
                RangeCheck* check);

}  // namespace igms::object
