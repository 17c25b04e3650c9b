#include "device_daemons/viewer/boom_protocol.h"

#include <gtest/gtest.h>

#include <cmath>

#include "device_daemons/viewer/viewer_sim.h"

namespace igms::devices::boom {
namespace {

std::optional<Pose> ParseOne(const std::string& bytes, Frame7Parser& parser) {
  std::optional<Pose> out;
  for (char c : bytes) {
    if (parser.Feed(static_cast<uint8_t>(c)) == ParseResult::kGood)
      out = DecodeReport(parser.frame());
  }
  return out;
}

TEST(BoomProtocol, ReportIs13BytesAndFits70HzAt9600Baud) {
  const std::string bytes = EncodeReport(Pose{});
  EXPECT_EQ(bytes.size(), kReportLength);
  EXPECT_EQ(kReportLength, 13u);
  EXPECT_LE(kReportLength * 10 * kMaxRateHz, 9600.0);
}

TEST(BoomProtocol, RoundTripsWithinOneStep) {
  Pose in;
  in.x_m = 0.1234;
  in.y_m = -0.75;
  in.z_m = 1.0;
  in.yaw_deg = 179.9;
  in.pitch_deg = -45.3;
  in.roll_deg = 3.21;
  in.left = true;
  in.counter = 9;
  Frame7Parser parser(BodyLength);
  const auto out = ParseOne(EncodeReport(in), parser);
  ASSERT_TRUE(out);
  EXPECT_NEAR(out->x_m, in.x_m, kPositionStepM / 2);
  EXPECT_NEAR(out->y_m, in.y_m, kPositionStepM / 2);
  EXPECT_NEAR(out->z_m, in.z_m, kPositionStepM / 2);
  EXPECT_NEAR(out->yaw_deg, in.yaw_deg, kAngleStepDeg / 2);
  EXPECT_NEAR(out->pitch_deg, in.pitch_deg, kAngleStepDeg / 2);
  EXPECT_NEAR(out->roll_deg, in.roll_deg, kAngleStepDeg / 2);
  EXPECT_TRUE(out->left);
  EXPECT_FALSE(out->right);
  EXPECT_EQ(out->counter, 9);
}

TEST(BoomProtocol, AnglesWrapAndPositionsClamp) {
  Pose in;
  in.yaw_deg = 190;    // = -170
  in.pitch_deg = 180;  // = -180
  in.x_m = 5.0;        // beyond the arm's reach: clamped
  in.y_m = std::nan("");
  Frame7Parser parser(BodyLength);
  const auto out = ParseOne(EncodeReport(in), parser);
  ASSERT_TRUE(out);
  EXPECT_NEAR(out->yaw_deg, -170, kAngleStepDeg);
  EXPECT_NEAR(out->pitch_deg, -180, kAngleStepDeg);
  EXPECT_NEAR(out->x_m, 2047 * kPositionStepM, 1e-12);
  EXPECT_EQ(out->y_m, 0);
}

TEST(BoomProtocol, ResynchronisesAfterGarbageAndTruncation) {
  Pose a;
  a.x_m = 0.5;
  const std::string good = EncodeReport(a);
  std::string corrupt = good;
  corrupt[4] ^= 0x01;
  Frame7Parser parser(BodyLength);
  int decoded = 0;
  std::string stream("\x01\x02zz\x85", 5);  // garbage, a cut frame, a corrupt one, two good
  stream.append(good.substr(0, 6)).append(corrupt).append(good).append(good);
  for (char c : stream) {
    if (parser.Feed(static_cast<uint8_t>(c)) == ParseResult::kGood && DecodeReport(parser.frame()))
      ++decoded;
  }
  EXPECT_EQ(decoded, 2);
  EXPECT_EQ(parser.bad_frames(), 2u);  // cut short, bad checksum
  EXPECT_EQ(parser.garbage_bytes(), 5u);
}

TEST(ViewerPath, ParsesInterpolatesAndLoops) {
  const auto path = ParseViewerPath(
      "# t x y z yaw pitch roll buttons\n0 0 0 0 0 0 0\n1 0.2 0 0 90 0 0 1\n\n2 0 0 0 0 0 0\n");
  ASSERT_TRUE(path.ok()) << path.error();
  ASSERT_EQ(path->size(), 3u);
  EXPECT_NEAR(PoseAt(*path, 0.5).yaw_deg, 45, 1e-9);
  EXPECT_NEAR(PoseAt(*path, 1.5).x_m, 0.1, 1e-9);
  EXPECT_TRUE(PoseAt(*path, 1.5).right);
  EXPECT_NEAR(PoseAt(*path, 2.5).yaw_deg, 45, 1e-9);  // looped
  const auto short_line = ParseViewerPath("0 1 2\n");
  EXPECT_FALSE(short_line.ok());
  EXPECT_NE(short_line.error().find("line 1"), std::string::npos);
  EXPECT_FALSE(ParseViewerPath("0 0 0 0 0 0 0\n0 0 0 0 0 0 0\n").ok());
  EXPECT_FALSE(ParseViewerPath("0 0 0 0 0 0 0 7\n").ok());
  EXPECT_FALSE(ParseViewerPath("").ok());
}

// The simulator is a pose tracker of the site: a head pose in the site is reported relative
// to the power-up pose, on the serial line, at the BOOM's resolution.
TEST(ViewerSim, ReportsTheHeadRelativeToItsPowerUpPose) {
  ViewerSimOptions options;
  options.power_up = {0.5, -0.2, 0.3, 90, 0, 0};  // 90 degrees to the left of the site's x
  ViewerSim sim(options);
  Frame7Parser parser(BodyLength);
  // At the power-up pose: zero, whatever the site pose.
  sim.SetSteady(options.power_up);
  auto p = ParseOne(sim.OnInput("P", 0).at(0), parser);
  ASSERT_TRUE(p);
  EXPECT_NEAR(std::abs(p->x_m) + std::abs(p->y_m) + std::abs(p->z_m) + std::abs(p->yaw_deg), 0,
              1e-9);
  // 0.1 m further along the site's y is 0.1 m forward for the head; turning to the site's
  // -x is a further 90 degrees left; a 20-degree nod stays a pitch.
  sim.SetSteady({0.5, -0.1, 0.3, 180, 20, 0});
  sim.SetButtons(true, false);
  p = ParseOne(sim.OnInput("P", 0).at(0), parser);
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x_m, 0.1, kPositionStepM);
  EXPECT_NEAR(p->y_m, 0, kPositionStepM);
  EXPECT_NEAR(p->z_m, 0, kPositionStepM);
  EXPECT_NEAR(p->yaw_deg, 90, kAngleStepDeg);
  EXPECT_NEAR(p->pitch_deg, 20, kAngleStepDeg);
  EXPECT_NEAR(p->roll_deg, 0, kAngleStepDeg);
  EXPECT_TRUE(p->left);
  EXPECT_FALSE(p->right);
  // A path drives it the same way: its first keyframe is at the power-up pose.
  auto path = ParseViewerPath("0 0.5 -0.2 0.3 90 0 0\n1 0.5 -0.2 0.3 90 0 0\n");
  ASSERT_TRUE(path.ok()) << path.error();
  sim.SetPath(*path);
  p = ParseOne(sim.OnInput("P", 0).at(0), parser);
  ASSERT_TRUE(p);
  EXPECT_NEAR(std::abs(p->x_m) + std::abs(p->yaw_deg), 0, 1e-9);
}

}  // namespace
}  // namespace igms::devices::boom
