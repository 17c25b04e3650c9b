// Image measurements the locators are built from: smoothed gradients over a region,
// bicubic sampling of them, strong boundary pixels inside a polygon, and the SSD window
// matcher along an epipolar segment (Cooke, section 3.6).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

namespace igms::object {

// The gradient of the image smoothed by a Gaussian of `sigma` pixels, over `region` (clipped
// to the image) plus a border, in grey levels per pixel. Values are read at any sub-pixel
// position by Catmull-Rom interpolation, so an edge's gradient peak can be located to a
// small fraction of a pixel; outside the computed region they read as zero.
class Gradients {
 public:
  Gradients() = default;
  Gradients(const cv::Mat& gray, cv::Rect region, double sigma);

  // Gradient at full-image pixel coordinates.
  Eigen::Vector2d At(const Eigen::Vector2d& p) const;
  // Magnitude at an integer pixel (no interpolation).
  float MagnitudeAt(int x, int y) const;
  cv::Rect region() const { return region_; }
  bool empty() const { return g_.empty(); }

 private:
  cv::Rect region_;  // where g_ sits in the image
  cv::Mat g_;        // CV_32FC2: the x and y gradients side by side, read together
};

// An 8-bit grey image's value at sub-pixel p by bilinear interpolation; p is clamped to the
// image.
double GreyAt(const cv::Mat& image, const Eigen::Vector2d& p);

// The noise of an 8-bit grey image over `box` (clipped to it), grey levels: the median
// absolute difference of horizontal neighbours, as a Gaussian's sigma, over sqrt(2) for the
// difference. Edges are too few to move the median. 0 for an empty box.
double NoiseSigma(const cv::Mat& image, cv::Rect box);

// Pixels inside `polygon` (image coordinates) whose gradient magnitude is above
// max(min_gradient, fraction * strongest in the polygon) and, when `edges` is not empty,
// set in the edge map. Returns them with the strongest magnitude. The strongest is the
// `quantile` of the magnitudes above min_gradient (1: the largest; below, a brighter
// object's few edges do not set it), or the largest where under 20 pixels are.
std::vector<cv::Point> StrongEdgePixels(const Gradients& grad,
                                        const std::vector<cv::Point2f>& polygon,
                                        const cv::Mat& edges, double fraction, double min_gradient,
                                        double* strongest = nullptr, double quantile = 1.0);

// Sub-pixel position of the silhouette edge along the line p + s * normal (`normal` unit,
// pointing out of the object), |s| <= range: the outermost local maximum of the gradient
// along the normal that reaches 40% of the strongest on the line. False when the strongest
// is under `min_gradient` or the chosen peak sits at the end of the range.
bool EdgeAlongNormal(const Gradients& grad, const Eigen::Vector2d& p, const Eigen::Vector2d& normal,
                     double range, double min_gradient, double* s);

// The same along a line across an edge inside the silhouette (a box's face boundary): the
// local maximum nearest p that reaches 40% of the strongest on the line.
bool EdgeNearPoint(const Gradients& grad, const Eigen::Vector2d& p, const Eigen::Vector2d& normal,
                   double range, double min_gradient, double* s);

struct SsdMatch {
  bool ok = false;
  Eigen::Vector2d offset = Eigen::Vector2d::Zero();  // right position - left position
  double rms = 0;                                    // grey levels per pixel
  // The zero-mean normalised cross-correlation at that offset, in [-1, 1]: the match's
  // quality whatever the images' noise, contrast and brightness (1: the same pattern).
  double zncc = 0;
  bool banded = false;  // matched on the boundary's band alone (MatchObject)
};

// Matches the left patch `patch` (a rectangle of the left image) into the right image at
// offsets on the segment from `offset_a` to `offset_b` (the epipolar segment of the depth
// range, as offsets of the patch), by the smallest sum of squared differences (3.30). Only
// the part of the segment where the shifted patch lies inside the right image is searched;
// not ok when none is. The match's ZNCC is read at the same offset. With `mask` (8-bit, the
// patch's size), only its non-zero pixels are compared.
SsdMatch MatchAlongSegment(const cv::Mat& left, const cv::Mat& right, cv::Rect patch,
                           const Eigen::Vector2d& offset_a, const Eigen::Vector2d& offset_b,
                           const cv::Mat& mask = cv::Mat());

}  // namespace igms::object
