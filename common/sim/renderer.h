// A CPU ray caster for the simulated site: one ray per pixel centre against the table
// plane and the analytic solids of the scene, supersampled where the surface under the
// pixel changes (silhouettes, face boundaries, the table's edge), Lambert shading, then the
// sensor model (blur, noise, 8-bit rounding). The table's holes are a texture filtered over
// each pixel's footprint, so they cost no extra rays.
//
// Anti-aliasing: a pixel whose centre sample sees a different surface than one of its four
// neighbours is resampled on an N x N "sheared" grid whose N*N samples all have distinct u
// and distinct v offsets, so a straight edge's coverage is measured to 1/N^2 of a pixel in
// both directions (N = 8 near solids: 1/64 px; N = 4 where only the table's edge and the
// background meet, an edge nothing is located from). A pixel integrates over its square
// footprint (a box filter), so in the noiseless, unblurred image the 50% grey-level
// crossing of a step edge is where the edge is. Samples that land on the table share the
// hole texture filtered once over the pixel's footprint.
//
// Cost: each solid is tested only inside its projected bounding rectangle (per row for the
// pixel-centre rays, per pixel for the supersamples).
//
// Cameras: any 3x4 P (common/geometry/camera.h); pass a P already moved by the camera
// platform's pose to render the panned view.
#pragma once

#include <opencv2/core.hpp>

#include "common/sim/scene.h"

namespace igms::site {

struct RenderOptions {
  int edge_samples_object = 8;  // N for pixels where the surface changes next to a solid
  int edge_samples_table = 4;   // N where only the table's edge and the background meet
  bool apply_sensor = true;     // false: the noiseless, unblurred radiance, rounded to 8 bits
  // False, with what is wrong in *error, when invalid.
  bool Check(std::string* error) const;
};

// Radiance in grey levels (0..255 scale, not clipped), CV_32F, before the sensor model.
cv::Mat RenderRadiance(const Scene& scene, const geometry::ProjectiveCamera& camera,
                       const RenderOptions& options = {});

// The 8-bit grey image the camera delivers. `stream` picks an independent noise stream
// (0 = left, 1 = right) from scene.sensor.seed.
cv::Mat Render(const Scene& scene, const geometry::ProjectiveCamera& camera, uint64_t stream,
               const RenderOptions& options = {});

struct StereoImages {
  cv::Mat left;
  cv::Mat right;
};
StereoImages RenderStereo(const Scene& scene, const RenderOptions& options = {});

// The share of each scene object's image (in scene.objects' order) that the camera sees:
// pixels where the object is the nearest surface, over the pixels its silhouette would cover
// alone in an unbounded image. Less than 1 when another solid hides part of it or part lies
// outside the image; 0 for an object wholly behind the camera. From pixel centres, no
// anti-aliasing: good to a pixel's share of the silhouette.
std::vector<double> VisibleFractions(const Scene& scene, const geometry::ProjectiveCamera& camera);

// The sensor model alone, applied to a radiance image (CV_32F) to give CV_8U.
cv::Mat ApplySensor(const cv::Mat& radiance, const SensorModel& sensor, uint64_t stream);

}  // namespace igms::site
