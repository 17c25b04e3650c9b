// Platform calibration (thesis 3.4): Levenberg-Marquardt recovers a synthetic head's true
// joint axes and tick scales from noisy observations at 27 orientations, starting from the
// nominal thesis platform; degenerate data is refused.
#include <gtest/gtest.h>

#include <cstdio>

#include "common/sim/synthetic_platform.h"

namespace igms::calibration {
namespace {

TEST(PlatformModel, ForwardKinematicsAtZeroIsTheCalibratedCamera) {
  const auto s = MakePlatformScenario(0.0, 1);
  const std::vector<double> zero(3, 0.0);
  EXPECT_LT((geometry::CameraAtPose(s.P0[0], s.truth, zero) - s.P0[0]).norm(), 1e-9);
  // A pure pan moves the cameras about the pan axis: the pan axis's points stay put.
  const auto axes = JointAxes(s.truth);
  const std::vector<double> pan = {0.3, 0.0, 0.0};
  const auto motion = geometry::WorldMotion(s.truth, pan);
  const Eigen::Vector3d p = axes[0].point + 4.0 * axes[0].direction;
  EXPECT_LT((motion * p - p).norm(), 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(motion.linear()).angle(), 0.3, 1e-12);
  // Thesis 4.4's scales.
  EXPECT_NEAR(geometry::ThesisPanDegreesPerTick(), 3.684e-3, 1e-6);
  EXPECT_NEAR(geometry::ThesisTiltDegreesPerTick(), 1.750e-2, 1e-5);
}

TEST(PlatformCalibration, RecoversKnownParametersFromNoisyData) {
  const auto s = MakePlatformScenario(0.3, 2);
  ASSERT_GT(s.observations.size(), 1000u);
  const auto before = CompareToTruth(s, s.nominal, 3);
  for (bool scales : {false, true}) {
    PlatformCalibrationOptions options;
    options.estimate_scales = scales;
    auto r = CalibratePlatform(s.P0[0], s.P0[1], s.nominal, s.observations, options);
    ASSERT_TRUE(r.ok()) << r.error();
    const auto after = CompareToTruth(s, r->model, 3);
    std::printf(
        "scales %d: rms %.3f -> %.3f px in %d iterations; axes %.4f deg, %.4f in; scale %.2e; "
        "prediction %.3f -> %.3f px\n",
        scales, r->initial_rms, r->rms, r->iterations, after.max_axis_angle_deg,
        after.max_axis_offset, after.max_scale_error, before.prediction_rms_px,
        after.prediction_rms_px);
    EXPECT_GT(r->initial_rms, 2.0);
    if (scales) {
      // With the scales free the model matches the data to the noise: rms near 0.3 * sqrt(2).
      EXPECT_LT(r->rms, 0.5);
      EXPECT_LT(after.max_axis_angle_deg, 0.05);
      EXPECT_LT(after.max_axis_offset, 0.05);
      EXPECT_LT(after.max_scale_error, 1e-3);  // the truth is 2e-3 off nominal
      EXPECT_LT(after.prediction_rms_px, 0.1);
    } else {
      // The true scales are 0.2% off the nominal ones: a fixed-scale fit is left with that.
      EXPECT_LT(r->rms, 1.5);
      EXPECT_LT(after.prediction_rms_px, before.prediction_rms_px / 5);
    }
    EXPECT_GT(before.prediction_rms_px, 2.0);
  }
}

TEST(PlatformCalibration, RefusesDegenerateData) {
  auto s = MakePlatformScenario(0.3, 4);
  std::string why;
  // Only the zero pose: the joints are unobservable.
  std::vector<PlatformObservation> still;
  for (const auto& o : s.observations) {
    if (o.ticks[0] == 0 && o.ticks[1] == 0 && o.ticks[2] == 0) still.push_back(o);
  }
  ASSERT_GT(still.size(), 20u);
  why = CalibratePlatform(s.P0[0], s.P0[1], s.nominal, still, {}).error();
  EXPECT_NE(why, "");
  EXPECT_NE(why.find("do not"), std::string::npos) << why;
  why = CalibratePlatform(s.P0[0], s.P0[1], s.nominal, std::span(s.observations).first(3), {})
            .error();
  EXPECT_NE(why, "");
  EXPECT_NE(why.find("at least"), std::string::npos);
  auto bad = s.observations;
  bad[5].ticks.pop_back();
  why = CalibratePlatform(s.P0[0], s.P0[1], s.nominal, bad, {}).error();
  EXPECT_NE(why, "");
  EXPECT_NE(why.find("observation 6"), std::string::npos);
  bad = s.observations;
  bad[2].camera = 2;
  why = CalibratePlatform(s.P0[0], s.P0[1], s.nominal, bad, {}).error();
  EXPECT_NE(why, "");
}

TEST(PlatformCalibration, ParsesObservationText) {
  std::string why;
  auto obs = ParsePlatformObservations(
      "# cam pan tilt roll x y z u v\nleft 100 -20 0 40 1 2 250.5 239\n1,0,0,0,50,0,0,10,20\n", 3);
  ASSERT_TRUE(obs.ok()) << obs.error();
  ASSERT_EQ(obs->size(), 2u);
  EXPECT_EQ((*obs)[0].camera, 0);
  EXPECT_EQ((*obs)[0].ticks[0], 100);
  EXPECT_EQ((*obs)[1].camera, 1);
  EXPECT_EQ((*obs)[1].pixel, Eigen::Vector2d(10, 20));
  why = ParsePlatformObservations("middle 0 0 0 1 2 3 4 5\n", 3).error();
  EXPECT_NE(why, "");
  EXPECT_NE(why.find("line 1"), std::string::npos);
  why = ParsePlatformObservations("left 0 0 1 2 3 4 5\n", 3).error();
  EXPECT_NE(why, "");
  EXPECT_NE(why.find("expected"), std::string::npos);
}

}  // namespace
}  // namespace igms::calibration
