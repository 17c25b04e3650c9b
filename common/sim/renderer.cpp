#include "common/sim/renderer.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <vector>

namespace igms::site {
namespace {

// Surface keys: which surface a sample saw. Solids get index * 8 + face.
constexpr int kBackground = -1;
constexpr int kTable = -2;

struct Sample {
  int key;
  float radiance;
};

class Tracer {
 public:
  Tracer(const Scene& scene, const geometry::ProjectiveCamera& camera)
      : scene_(scene), size_(camera.image_size()) {
    const Eigen::Matrix3d M = camera.P().leftCols<3>();
    minv_ = M.inverse();
    center_ = camera.Center();
    // Ray direction for pixel (u, v) is sign * Minv * (u, v, 1), oriented into the scene.
    sign_ = M.determinant() * (minv_ * Eigen::Vector3d(size_.width / 2.0, size_.height / 2.0, 1))
                                  .dot(M.row(2).transpose()) <
                    0
                ? -1.0
                : 1.0;
    ray_ = sign_ * minv_;
    for (const auto& light : scene.lighting.lights)
      lights_.push_back({light.direction.normalized(), light.intensity});
    for (const auto& object : scene.objects) {
      rects_.push_back(ImageRect(object.shape, camera));
      solids_.emplace_back(object.shape, center_);
    }
    table_shade_ = Shade(Eigen::Vector3d::UnitZ());
    for (const auto& object : scene.objects) bounds_.push_back(BoundingSphere(object.shape));
    const Eigen::Vector3d a =
        (minv_ * Eigen::Vector3d(size_.width / 2.0, size_.height / 2.0, 1)).normalized();
    const Eigen::Vector3d b =
        (minv_ * Eigen::Vector3d(size_.width / 2.0 + 1, size_.height / 2.0, 1)).normalized();
    pixel_angle_ = std::acos(std::clamp(a.dot(b), -1.0, 1.0));
  }

  // The surface and radiance seen through image point (u, v), testing only the solids listed
  // in `objects` (indices into the scene; a caller lists those whose rectangles may matter).
  // `table_radiance`, when not negative, is used for a sample that lands on the table instead
  // of filtering the hole texture at that sample (see Supersample).
  Sample Trace(double u, double v, const int* objects, int object_count,
               float table_radiance = -1.0f) const {
    Eigen::Vector3d d = ray_ * Eigen::Vector3d(u, v, 1.0);
    d *= 1.0 / d.norm();  // one division, not three
    double best_t = std::numeric_limits<double>::infinity();
    int key = kBackground;
    Eigen::Vector3d normal;
    int hit_object = -1;
    int hit_face = 0;
    for (int k = 0; k < object_count; ++k) {
      const int i = objects[k];
      const cv::Rect2d& r = rects_[i];
      if (u < r.x || u > r.x + r.width || v < r.y || v > r.y + r.height) continue;
      double t;
      int face;
      if (solids_[i].Hit(d, best_t, &t, &face)) {
        best_t = t;
        key = i * 8 + face;
        hit_object = i;
        hit_face = face;
      }
    }
    // The normal for the nearest hit only.
    if (hit_object >= 0) normal = solids_[hit_object].Normal(d, best_t, hit_face);
    const Table& table = scene_.table;
    if (table.enabled && center_.z() > 0 && d.z() < 0) {
      const double t = -center_.z() / d.z();
      if (t < best_t) {
        const Eigen::Vector3d p = center_ + t * d;
        if (p.x() >= table.x_min && p.x() <= table.x_max && p.y() >= table.y_min &&
            p.y() <= table.y_max) {
          // In shadow, the table's radiance scaled by the light it still gets.
          const double lit = scene_.lighting.shadows
                                 ? ShadeAt(Eigen::Vector3d::UnitZ(), p, -1) / table_shade_
                                 : 1.0;
          if (table_radiance >= 0.0f) return {kTable, static_cast<float>(table_radiance * lit)};
          return {kTable, static_cast<float>(255.0 * TableAlbedo(p, t, d) * table_shade_ * lit)};
        }
      }
    }
    if (key == kBackground) return {key, static_cast<float>(255.0 * table.background)};
    const SceneObject& object = scene_.objects[static_cast<size_t>(hit_object)];
    const double rho =
        object.texture.enabled() ? AlbedoAt(object, center_ + best_t * d) : object.albedo;
    const double shade =
        scene_.lighting.shadows ? ShadeAt(normal, center_ + best_t * d, hit_object) : Shade(normal);
    return {key, static_cast<float>(255.0 * rho * shade)};
  }

  // The table's radiance filtered over pixel (x, y)'s footprint, as the pixel-centre ray sees
  // it, whether or not that ray lands inside the table; -1 when it misses the plane.
  float TableRadianceAt(int x, int y) const {
    Eigen::Vector3d d = ray_ * Eigen::Vector3d(x, y, 1.0);
    d.normalize();
    if (!scene_.table.enabled || center_.z() <= 0 || d.z() >= 0) return -1.0f;
    const double t = -center_.z() / d.z();
    return static_cast<float>(255.0 * TableAlbedo(center_ + t * d, t, d) * table_shade_);
  }

  // Solids whose padded image rectangle meets the square [x0, x1] x [y0, y1], into `out`.
  int ObjectsMeeting(double x0, double x1, double y0, double y1, int* out) const {
    int n = 0;
    for (size_t i = 0; i < rects_.size(); ++i) {
      const cv::Rect2d& r = rects_[i];
      if (x1 < r.x || x0 > r.x + r.width || y1 < r.y || y0 > r.y + r.height) continue;
      out[n++] = static_cast<int>(i);
    }
    return n;
  }
  size_t object_count() const { return rects_.size(); }

 private:
  struct DirLight {
    Eigen::Vector3d dir;
    double intensity;
  };

  // The table's albedo at p, with the holes filtered over the pixel's footprint on the table
  // (t * pixel angle across, stretched by 1 / |d.z| along the ray's grazing direction), so
  // the hole grid is anti-aliased without extra rays. Holes are background texture: this
  // approximation is not used to locate anything.
  double TableAlbedo(const Eigen::Vector3d& p, double t, const Eigen::Vector3d& d) const {
    const Table& table = scene_.table;
    const double dx = p.x() - table.hole_origin.x(), dy = p.y() - table.hole_origin.y();
    const double rx = dx - table.hole_pitch * std::floor(dx / table.hole_pitch + 0.5);
    const double ry = dy - table.hole_pitch * std::floor(dy / table.hole_pitch + 0.5);
    const double across = t * pixel_angle_;
    const double along = across / std::max(0.02, std::abs(d.z()));
    // The footprint's extent below never exceeds `along`: beyond hole_radius + along / 2 the
    // coverage clamps to zero, so most of the table skips the filter.
    const double reach = table.hole_radius + 0.5 * along;
    const double rho2 = rx * rx + ry * ry;
    if (rho2 > reach * reach) return table.albedo;
    const double rho = std::sqrt(rho2);
    // Footprint extent in the direction from the hole centre (d's horizontal part is along).
    const Eigen::Vector2d h = Eigen::Vector2d(d.x(), d.y()).normalized();
    const double c = rho > 1e-12 ? std::abs(h.x() * rx + h.y() * ry) / rho : 1.0;
    const double extent = std::sqrt(along * c * along * c + across * across * (1 - c * c));
    double coverage = std::clamp(0.5 + (table.hole_radius - rho) / extent, 0.0, 1.0);
    // Far away a hole is smaller than the footprint: keep its mean darkness.
    const double hole_area = M_PI * table.hole_radius * table.hole_radius;
    coverage *= std::min(1.0, hole_area / (across * along + 1e-12) * 0.25 +
                                  0.75 * std::min(1.0, hole_area / (across * along + 1e-12)));
    return table.albedo + coverage * (table.hole_albedo - table.albedo);
  }

  double Shade(const Eigen::Vector3d& n) const {
    double s = scene_.lighting.ambient;
    for (const auto& l : lights_) s += l.intensity * std::max(0.0, n.dot(l.dir));
    return s;
  }

  // Shade() with shadows: a light counts only when no solid lies between p and it. `self` is
  // the solid p lies on (-1: the table); a convex solid never shadows its own lit side.
  double ShadeAt(const Eigen::Vector3d& n, const Eigen::Vector3d& p, int self) const {
    double s = scene_.lighting.ambient;
    for (const auto& l : lights_) {
      const double c = n.dot(l.dir);
      if (c <= 0) continue;
      if (!Blocked(p, l.dir, self)) s += l.intensity * c;
    }
    return s;
  }

  bool Blocked(const Eigen::Vector3d& p, const Eigen::Vector3d& dir, int self) const {
    for (size_t i = 0; i < bounds_.size(); ++i) {
      if (static_cast<int>(i) == self) continue;
      // The solid's bounding sphere first: most shadow rays pass far from most solids.
      const Eigen::Vector3d q = bounds_[i].first - p;
      const double along = q.dot(dir);
      const double r = bounds_[i].second;
      if (along < -r || (q - along * dir).squaredNorm() > r * r) continue;
      if (Intersect(scene_.objects[i].shape, p, dir)) return true;
    }
    return false;
  }

  static std::pair<Eigen::Vector3d, double> BoundingSphere(const Shape& shape) {
    const auto points = OutlinePoints(shape, 36);
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (const auto& q : points) c += q / static_cast<double>(points.size());
    double r = 0;
    for (const auto& q : points) r = std::max(r, (q - c).norm());
    return {c, 1.05 * r + 0.05};
  }

  // Pixel rectangle that holds the solid's projection (the whole image if any outline point
  // is behind the camera), padded by two pixels.
  static cv::Rect2d ImageRect(const Shape& shape, const geometry::ProjectiveCamera& camera) {
    const auto size = camera.image_size();
    double u0 = 1e18, v0 = 1e18, u1 = -1e18, v1 = -1e18;
    for (const auto& p : OutlinePoints(shape, 180)) {
      auto px = camera.Project(p);
      if (camera.Depth(p) <= 0 || !px) return {-10.0, -10.0, size.width + 20.0, size.height + 20.0};
      u0 = std::min(u0, px->x());
      v0 = std::min(v0, px->y());
      u1 = std::max(u1, px->x());
      v1 = std::max(v1, px->y());
    }
    // Cylinder caps are sampled by a polygon; pad for the chord error and the pixel footprint.
    return {u0 - 2, v0 - 2, u1 - u0 + 4, v1 - v0 + 4};
  }

  const Scene& scene_;
  geometry::ImageSize size_;
  Eigen::Matrix3d minv_;
  Eigen::Matrix3d ray_;  // sign_ * minv_: pixel (u, v, 1) to a ray direction into the scene
  Eigen::Vector3d center_;
  double sign_ = 1;
  double pixel_angle_ = 0.001;
  double table_shade_ = 1.0;
  std::vector<DirLight> lights_;
  std::vector<cv::Rect2d> rects_;
  std::vector<SolidFromOrigin> solids_;                     // every ray starts at the camera centre
  std::vector<std::pair<Eigen::Vector3d, double>> bounds_;  // solids' bounding spheres

 public:
  // Whether solid i alone covers image point (u, v), whatever hides it.
  bool Covers(int i, double u, double v) const {
    Eigen::Vector3d d = ray_ * Eigen::Vector3d(u, v, 1.0);
    d.normalize();
    double t;
    int face;
    return solids_[i].Hit(d, std::numeric_limits<double>::infinity(), &t, &face);
  }
  // The solid's padded image rectangle (the whole image when part is behind the camera).
  const cv::Rect2d& Rect(int i) const { return rects_[i]; }
};

std::vector<int>& ScratchObjects(size_t size) {
  thread_local std::vector<int> objects;
  if (objects.size() < size) objects.resize(size);
  return objects;
}

// The mean radiance over pixel (x, y) from n x n sheared-grid samples. Only the solids whose
// rectangles meet the pixel are tested, and samples that land on the table take the table's
// radiance filtered over the whole pixel's footprint (the texture filter already integrates
// the footprint; filtering it again around every sample would blur the holes twice).
float Supersample(const Tracer& tracer, int x, int y, int n) {
  std::vector<int>& objects = ScratchObjects(tracer.object_count());
  const int count = tracer.ObjectsMeeting(x - 0.5, x + 0.5, y - 0.5, y + 0.5, objects.data());
  const float table = tracer.TableRadianceAt(x, y);
  double sum = 0;
  const double inv = 1.0 / (n * n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double du = (i * n + j + 0.5) * inv - 0.5;
      const double dv = (j * n + i + 0.5) * inv - 0.5;
      sum += tracer.Trace(x + du, y + dv, objects.data(), count, table).radiance;
    }
  }
  return static_cast<float>(sum * inv);
}

}  // namespace

bool RenderOptions::Check(std::string* error) const {
  if (edge_samples_object < 1 || edge_samples_object > 32) {
    *error = "edge_samples_object must be in 1..32";
    return false;
  }
  if (edge_samples_table < 1 || edge_samples_table > 32) {
    *error = "edge_samples_table must be in 1..32";
    return false;
  }
  return true;
}

cv::Mat RenderRadiance(const Scene& scene, const geometry::ProjectiveCamera& camera,
                       const RenderOptions& options) {
  const auto size = camera.image_size();
  const Tracer tracer(scene, camera);
  cv::Mat keys(size.height, size.width, CV_32S);
  cv::Mat radiance(size.height, size.width, CV_32F);
  std::vector<int> objects(tracer.object_count());
  for (int y = 0; y < size.height; ++y) {
    int* k = keys.ptr<int>(y);
    float* r = radiance.ptr<float>(y);
    // Solids whose rectangles meet this row; each pixel then tests only those.
    const int count = tracer.ObjectsMeeting(-1e18, 1e18, y, y, objects.data());
    for (int x = 0; x < size.width; ++x) {
      const Sample s = tracer.Trace(x, y, objects.data(), count);
      k[x] = s.key;
      r[x] = s.radiance;
    }
  }
  for (int y = 0; y < size.height; ++y) {
    const int* k = keys.ptr<int>(y);
    const int* up = keys.ptr<int>(std::max(0, y - 1));
    const int* down = keys.ptr<int>(std::min(size.height - 1, y + 1));
    float* r = radiance.ptr<float>(y);
    for (int x = 0; x < size.width; ++x) {
      const int c = k[x];
      const int l = k[std::max(0, x - 1)], rt = k[std::min(size.width - 1, x + 1)];
      if (c == l && c == rt && c == up[x] && c == down[x]) continue;
      // Solid keys are >= 0; a change between table and background alone takes fewer samples.
      const bool solid = c >= 0 || l >= 0 || rt >= 0 || up[x] >= 0 || down[x] >= 0;
      r[x] = Supersample(tracer, x, y,
                         solid ? options.edge_samples_object : options.edge_samples_table);
    }
  }
  return radiance;
}

std::vector<double> VisibleFractions(const Scene& scene, const geometry::ProjectiveCamera& camera) {
  const Tracer tracer(scene, camera);
  const auto size = camera.image_size();
  std::vector<int> objects(tracer.object_count());
  std::vector<double> out(scene.objects.size(), 0.0);
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const int index = static_cast<int>(i);
    const cv::Rect2d& r = tracer.Rect(index);
    // Wholly behind the camera (or a rectangle that lost its meaning): nothing seen.
    if (r.width > 20 * size.width || r.height > 20 * size.height) continue;
    long covered = 0, seen = 0;
    for (int y = static_cast<int>(std::floor(r.y));
         y <= static_cast<int>(std::ceil(r.y + r.height)); ++y) {
      for (int x = static_cast<int>(std::floor(r.x));
           x <= static_cast<int>(std::ceil(r.x + r.width)); ++x) {
        if (!tracer.Covers(index, x, y)) continue;
        ++covered;
        if (x < 0 || y < 0 || x >= size.width || y >= size.height) continue;
        const int count = tracer.ObjectsMeeting(x, x, y, y, objects.data());
        const int key = tracer.Trace(x, y, objects.data(), count).key;
        seen += key >= 0 && key / 8 == index;
      }
    }
    out[i] = covered ? static_cast<double>(seen) / static_cast<double>(covered) : 0.0;
  }
  return out;
}

cv::Mat ApplySensor(const cv::Mat& radiance, const SensorModel& sensor, uint64_t stream) {
  cv::Mat img = radiance.clone();
  if (sensor.blur_sigma > 0) cv::GaussianBlur(img, img, cv::Size(0, 0), sensor.blur_sigma);
  if (sensor.noise_sigma > 0) {
    cv::RNG rng(sensor.seed * 0x9E3779B97F4A7C15ULL + 2 * stream + 1);
    cv::Mat noise(img.size(), CV_32F);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, sensor.noise_sigma);
    img += noise;
  }
  cv::Mat out;
  img.convertTo(out, CV_8U);  // rounds to nearest and saturates to 0..255
  return out;
}

cv::Mat Render(const Scene& scene, const geometry::ProjectiveCamera& camera, uint64_t stream,
               const RenderOptions& options) {
  const cv::Mat radiance = RenderRadiance(scene, camera, options);
  if (!options.apply_sensor) {
    cv::Mat out;
    radiance.convertTo(out, CV_8U);
    return out;
  }
  return ApplySensor(radiance, scene.sensor, stream);
}

StereoImages RenderStereo(const Scene& scene, const RenderOptions& options) {
  return {Render(scene, scene.cameras.left, 0, options),
          Render(scene, scene.cameras.right, 1, options)};
}

}  // namespace igms::site
