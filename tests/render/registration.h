// Registration of graphics on video, measured on pixels: the sub-pixel positions where two
// coverage images (0 outside the solids, 1 inside) cross one half, along rows and columns,
// paired within two pixels. The graphics are the site's true solids, or the models the
// object server's locator finds from generated marks on the site's simulated stereo pair.
// Used by the render test and bench/control/window.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "common/sim/marks.h"
#include "common/sim/renderer.h"
#include "common/sim/scene.h"
#include "control/render/draw_list.h"
#include "object_server/locate.h"

namespace igms::control::render::registration {

// The scene as a mask: its solids 255 on 0, no table, no shading, no sensor.
inline site::Scene MaskScene(site::Scene scene) {
  scene.lighting.ambient = 1.0;
  scene.lighting.lights.clear();
  scene.table.enabled = false;
  scene.table.background = 0.0;
  for (auto& o : scene.objects) {
    o.albedo = 1.0;
    o.texture.contrast = 0.0;
  }
  return scene;
}

// The scene's boxes and cylinders as the renderer's models, white and unlit.
inline std::vector<DrawModel> ModelsOf(const site::Scene& scene) {
  std::vector<DrawModel> models;
  for (const auto& o : scene.objects) {
    DrawModel m;
    m.color = {1.0f, 1.0f, 1.0f};
    if (const auto* c = std::get_if<site::Cylinder>(&o.shape)) {
      m.kind = DrawModel::Kind::kCylinder;
      m.center = c->center;
      m.axis = c->axis.normalized();
      m.radius = c->radius;
      m.height = c->height;
    } else if (const auto* b = std::get_if<site::Box>(&o.shape)) {
      m.kind = DrawModel::Kind::kBox;
      m.center = b->center;
      m.size = b->size;
      m.rotation = b->rotation;
    } else {
      continue;
    }
    models.push_back(m);
  }
  return models;
}

// The observed (distorted) image of an ideal one: each observed pixel reads the ideal image
// where the lens sends it back.
inline cv::Mat Distorted(const cv::Mat& ideal, const geometry::ProjectiveCamera& lensed) {
  cv::Mat map_x(ideal.size(), CV_32F), map_y(ideal.size(), CV_32F);
  for (int v = 0; v < ideal.rows; ++v) {
    for (int u = 0; u < ideal.cols; ++u) {
      const auto p = lensed.Undistort(Eigen::Vector2d(u, v));
      map_x.at<float>(v, u) = p ? static_cast<float>(p->x()) : -1000.f;
      map_y.at<float>(v, u) = p ? static_cast<float>(p->y()) : -1000.f;
    }
  }
  cv::Mat out;
  cv::remap(ideal, out, map_x, map_y, cv::INTER_LINEAR, cv::BORDER_CONSTANT, 0);
  return out;
}

// What a camera of the site delivers (lit, textured, blurred, noisy, 8-bit): through its
// lens when it has one, the lens bending the light before the sensor blurs and adds noise.
inline cv::Mat CameraImage(const site::Scene& scene, const geometry::ProjectiveCamera& camera,
                           uint64_t stream) {
  if (!camera.has_distortion()) return site::Render(scene, camera, stream);
  const geometry::ProjectiveCamera ideal(camera.P(), camera.image_size());
  return site::ApplySensor(Distorted(site::RenderRadiance(scene, ideal), camera), scene.sensor,
                           stream);
}

// The located models: each box and cylinder of `scene` asked of the object server's locator
// (object_server/locate.h) with the marks the mark model makes from the truth (seeded by
// mark_seed * 1000 + the object's index, as common/sim/vision's evaluation does), on the
// stereo pair `left`, `right` taken by `cameras` (with their lenses, if any). The found ones
// become the renderer's models, white; the truth is never drawn.
struct Located {
  std::vector<DrawModel> models;
  int asked = 0, found = 0;
  std::vector<std::string> refused;  // "NAME: reason", for a person
};
inline Located LocateModels(const site::Scene& scene, const site::StereoCameras& cameras,
                            const cv::Mat& left, const cv::Mat& right, uint64_t mark_seed) {
  Located out;
  const geometry::ProjectiveCamera ideal_left(cameras.left.P(), cameras.left.image_size());
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const auto& shape = scene.objects[i].shape;
    const bool cylinder = std::holds_alternative<site::Cylinder>(shape);
    if (!cylinder && !std::holds_alternative<site::Box>(shape)) continue;
    const auto marks = site::GenerateMarks(shape, ideal_left, mark_seed * 1000 + i);
    if (!marks) continue;
    ++out.asked;
    object::LocateInput in;
    in.type = cylinder ? object::SolidType::kCylinder : object::SolidType::kBox;
    in.marks = *marks;
    in.left = left;
    in.right = right;
    in.left_camera = cameras.left;
    in.right_camera = cameras.right;
    const object::LocateResult r = object::Locate(in);
    if (!r.found) {
      out.refused.push_back(scene.objects[i].name + ": " + object::FailureName(r.reason));
      continue;
    }
    ++out.found;
    DrawModel m;
    m.color = {1.0f, 1.0f, 1.0f};
    if (cylinder) {
      m.kind = DrawModel::Kind::kCylinder;
      m.center = r.cylinder.center;
      m.axis = r.cylinder.axis.normalized();
      m.radius = r.cylinder.radius;
      m.height = r.cylinder.height;
    } else {
      m.kind = DrawModel::Kind::kBox;
      m.center = r.box.center;
      m.size = r.box.size;
      m.rotation = r.box.rotation;
    }
    out.models.push_back(m);
  }
  return out;
}

// The sim's noiseless coverage (0..1, CV_32F) of the scene's solids seen by a camera.
inline cv::Mat TruthCoverage(const site::Scene& mask_scene,
                             const geometry::ProjectiveCamera& camera) {
  site::RenderOptions options;
  options.apply_sensor = false;
  cv::Mat radiance = site::RenderRadiance(mask_scene, camera, options);
  cv::Mat coverage;
  radiance.convertTo(coverage, CV_32F, 1.0 / 255.0);
  return cv::min(cv::max(coverage, 0.0), 1.0);
}

// An 8-bit grey or BGR image as coverage (its first channel over 255).
inline cv::Mat CoverageOf(const cv::Mat& image) {
  cv::Mat grey;
  if (image.channels() == 3) {
    cv::extractChannel(image, grey, 1);
  } else {
    grey = image;
  }
  cv::Mat out;
  grey.convertTo(out, CV_32F, 1.0 / 255.0);
  return out;
}

// Crossings of one half along a line of samples: position (sub-pixel) and sign, where the
// step between neighbours is steep (> 0.3: the edge runs across the line, not along it).
struct Crossing {
  double at;
  int sign;
};
inline std::vector<Crossing> Crossings(const float* v, int n, int stride) {
  std::vector<Crossing> out;
  for (int i = 0; i + 1 < n; ++i) {
    const float a = v[static_cast<std::ptrdiff_t>(i) * stride],
                b = v[(static_cast<std::ptrdiff_t>(i) + 1) * stride];
    if ((a < 0.5f) == (b < 0.5f) || std::abs(b - a) < 0.3f) continue;
    out.push_back({i + (0.5 - a) / (b - a), b > a ? 1 : -1});
  }
  return out;
}

// |position differences| of the video's crossings and the graphics' nearest of the same
// sign within 2 px, along every row and column. A crossing with no partner counts as
// `missing`.
inline std::vector<double> EdgeErrors(const cv::Mat& video, const cv::Mat& graphics,
                                      int* missing = nullptr) {
  std::vector<double> errors;
  int unpaired = 0;
  auto pair = [&](const float* a, const float* b, int n, int stride) {
    const auto ca = Crossings(a, n, stride), cb = Crossings(b, n, stride);
    for (const auto& x : ca) {
      double best = 1e9;
      for (const auto& y : cb) {
        if (y.sign == x.sign) best = std::min(best, std::abs(y.at - x.at));
      }
      if (best <= 2.0) {
        errors.push_back(best);
      } else {
        unpaired++;
      }
    }
  };
  for (int r = 0; r < video.rows; ++r) {
    pair(video.ptr<float>(r), graphics.ptr<float>(r), video.cols, 1);
  }
  const int stride = static_cast<int>(video.step1());
  for (int c = 0; c < video.cols; ++c) {
    pair(video.ptr<float>(0) + c, graphics.ptr<float>(0) + c, video.rows, stride);
  }
  if (missing) *missing = unpaired;
  return errors;
}

}  // namespace igms::control::render::registration
