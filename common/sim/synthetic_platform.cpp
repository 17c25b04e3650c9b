#include "common/sim/synthetic_platform.h"

#include <Eigen/Dense>
#include <cmath>
#include <random>

namespace igms::calibration {
namespace {

constexpr double kDeg = M_PI / 180.0;

geometry::Matrix34 LookAt(const Eigen::Vector3d& c, const Eigen::Vector3d& target) {
  Eigen::Matrix3d K;
  K << 1150, 0, 255.5, 0, 1173, 239.5, 0, 0, 1;
  const Eigen::Vector3d z = (target - c).normalized();
  const Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d y = z.cross(x);
  Eigen::Matrix3d R;
  R << x.transpose(), y.transpose(), z.transpose();
  geometry::Matrix34 Rt;
  Rt << R, -R * c;
  return K * Rt;
}

std::vector<double> Ticks(const geometry::PlatformModel& m, double pan, double tilt, double roll) {
  return {pan * kDeg / m.joints[0].radians_per_tick, tilt * kDeg / m.joints[1].radians_per_tick,
          roll * kDeg / m.joints[2].radians_per_tick};
}

}  // namespace

PlatformScenario MakePlatformScenario(double pixel_noise, unsigned seed) {
  PlatformScenario s;
  const Eigen::Vector3d target(60, 0, 2);
  s.P0[0] = LookAt({0, 2, 6}, target);
  s.P0[1] = LookAt({0, -2, 6}, target);
  s.nominal = geometry::ThesisPlatform({-2, 0, 0}, 5.5, 0.0);
  s.truth = s.nominal;
  s.truth.world_from_base.linear() = (Eigen::AngleAxisd(0.3 * kDeg, Eigen::Vector3d::UnitX()) *
                                      Eigen::AngleAxisd(-0.2 * kDeg, Eigen::Vector3d::UnitY()) *
                                      Eigen::AngleAxisd(0.5 * kDeg, Eigen::Vector3d::UnitZ()))
                                         .toRotationMatrix();
  s.truth.world_from_base.translation() += Eigen::Vector3d(0.1, -0.15, 0.05);
  s.truth.joints[0].a += 0.3;
  s.truth.joints[0].alpha += 0.6 * kDeg;
  s.truth.joints[1].theta_offset += 1.1 * kDeg;
  s.truth.joints[1].d += 0.25;
  s.truth.joints[1].a += 0.15;
  s.truth.joints[1].alpha -= 0.9 * kDeg;
  for (auto& j : s.truth.joints) j.radians_per_tick *= 1.002;

  std::vector<Eigen::Vector3d> grid;
  for (double x : {40.0, 55.0, 70.0}) {
    for (double y = -16; y <= 16; y += 4) {
      for (double z = 0; z <= 12; z += 3) grid.emplace_back(x, y, z);
    }
  }
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, pixel_noise);
  for (double pan : {-15.0, 0.0, 15.0}) {
    for (double tilt : {-8.0, 0.0, 8.0}) {
      for (double roll : {-5.0, 0.0, 5.0}) {
        // Encoders count in whole ticks: the pose is commanded in the nominal scale.
        std::vector<double> ticks = Ticks(s.nominal, pan, tilt, roll);
        for (auto& t : ticks) t = std::round(t);
        const auto q = geometry::AnglesFromTicks(s.truth, ticks);
        for (int cam = 0; cam < 2; ++cam) {
          const geometry::ProjectiveCamera P(geometry::CameraAtPose(s.P0[cam], s.truth, q), s.size);
          for (const auto& X : grid) {
            const auto px = P.Project(X);
            if (!px || P.Depth(X) <= 0 || !P.InImage(*px, 2.0)) continue;
            s.observations.push_back(
                {cam, ticks, X, *px + Eigen::Vector2d(noise(rng), noise(rng))});
          }
        }
      }
    }
  }
  return s;
}

std::vector<AxisLine> JointAxes(const geometry::PlatformModel& model) {
  std::vector<AxisLine> axes;
  Eigen::Isometry3d frame = model.world_from_base;
  for (const auto& joint : model.joints) {
    axes.push_back({frame.translation(), frame.linear().col(2)});
    frame = frame * geometry::DhTransform(joint, 0.0);
  }
  return axes;
}

PlatformRecovery CompareToTruth(const PlatformScenario& s, const geometry::PlatformModel& estimate,
                                unsigned seed) {
  PlatformRecovery r;
  const auto truth_axes = JointAxes(s.truth), est_axes = JointAxes(estimate);
  const Eigen::Vector3d head = s.truth.world_from_base.translation() + Eigen::Vector3d(0, 0, 5.5);
  for (size_t i = 0; i < truth_axes.size(); ++i) {
    const auto& a = truth_axes[i];
    const auto& b = est_axes[i];
    const double cosine = std::clamp(std::abs(a.direction.dot(b.direction)), 0.0, 1.0);
    r.max_axis_angle_deg = std::max(r.max_axis_angle_deg, std::acos(cosine) / kDeg);
    // Distance between the lines at the point of the true axis nearest the head.
    const Eigen::Vector3d on_a = a.point + (head - a.point).dot(a.direction) * a.direction;
    const Eigen::Vector3d v = on_a - b.point;
    r.max_axis_offset = std::max(r.max_axis_offset, (v - v.dot(b.direction) * b.direction).norm());
    r.max_scale_error = std::max(
        r.max_scale_error,
        std::abs(estimate.joints[i].radians_per_tick / s.truth.joints[i].radians_per_tick - 1.0));
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pan(-15, 15), tilt(-8, 8), roll(-5, 5), x(40, 70),
      y(-12, 12), z(0, 12);
  double sum = 0;
  int n = 0;
  while (n < 200) {
    std::vector<double> ticks = Ticks(s.nominal, pan(rng), tilt(rng), roll(rng));
    const Eigen::Vector3d X(x(rng), y(rng), z(rng));
    for (int cam = 0; cam < 2; ++cam) {
      const geometry::ProjectiveCamera T(
          geometry::CameraAtPose(s.P0[cam], s.truth, geometry::AnglesFromTicks(s.truth, ticks)),
          s.size);
      const geometry::ProjectiveCamera E(
          geometry::CameraAtPose(s.P0[cam], estimate, geometry::AnglesFromTicks(estimate, ticks)),
          s.size);
      const auto pt = T.Project(X);
      if (!pt || !T.InImage(*pt)) continue;
      sum += (*E.Project(X) - *pt).squaredNorm();
      ++n;
    }
  }
  r.prediction_rms_px = std::sqrt(sum / n);
  return r;
}

}  // namespace igms::calibration
