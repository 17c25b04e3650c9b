// The calibration's hash: one calibration written two ways hashes the same, one changed value
// changes it, and the digest is SHA-256's.
#include "common/calibration/calibration_hash.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

namespace igms::calibration {
namespace {

std::string ThesisText() {
  const char* dir = std::getenv("IGMS_SOURCE_DIR");
  std::ifstream in(std::string(dir ? dir : ".") +
                   "/common/calibration/data/thesis_calibration.yaml");
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_FALSE(text.str().empty()) << "set IGMS_SOURCE_DIR";
  return text.str();
}

StereoCalibration Parse(const std::string& yaml) {
  auto c = ParseCalibration(yaml);
  EXPECT_TRUE(c.ok()) << c.error();
  return c.ok() ? *c : StereoCalibration();
}

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// The thesis's file rewritten by hand: no comments, its top-level maps in the reverse order,
// other spacing, and numbers written another way.
std::string Rewritten(const std::string& yaml) {
  std::vector<std::string> sections;
  std::istringstream lines(yaml);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#' || line[0] == '%' || line == "---") continue;
    if (line[0] != ' ') sections.emplace_back();
    if (!sections.empty()) sections.back() += line + "\n";
  }
  std::string out = "%YAML:1.0\n---\n";
  for (auto it = sections.rbegin(); it != sections.rend(); ++it) out += *it + "\n";
  out = Replace(out, "-232.71,", "-2.3271e+2 ,");
  out = Replace(out, "-0.01, -0.24, 0.01, 1.00 ]", "-1e-2,   -0.240, 0.010, 1 ]");
  out = Replace(out, "origin: [ -0.9972, -0.0030, -0.0021 ]",
                "origin: [ -0.99720, -3.0e-3, -0.0021 ]   # a note");
  return out;
}

TEST(CalibrationHash, IsSha256OfTheCanonicalText) {
  // FIPS 180-2's test vectors.
  EXPECT_EQ(Sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  const StereoCalibration c = Parse(ThesisText());
  EXPECT_EQ(CalibrationHash(c), Sha256Hex(CanonicalCalibrationText(c)));
  EXPECT_EQ(CalibrationHash(c).size(), 64u);
  const std::string text = CanonicalCalibrationText(c);
  EXPECT_EQ(text.rfind("igms-calibration-hash 1\nleft.P 3 4 -232.71000000000001 ", 0), 0u) << text;
  EXPECT_NE(text.find("\nplatform.joints[1] 4:tilt "), std::string::npos) << text;
}

TEST(CalibrationHash, OneCalibrationWrittenTwoWaysHashesTheSame) {
  const std::string original = ThesisText();
  const std::string rewritten = Rewritten(original);
  ASSERT_NE(rewritten, original);
  const StereoCalibration a = Parse(original);
  const StereoCalibration b = Parse(rewritten);
  EXPECT_EQ(CalibrationHash(a), CalibrationHash(b)) << rewritten;
  // And as this project writes it (cv::FileStorage's own layout and number format).
  EXPECT_EQ(CalibrationHash(Parse(FormatCalibration(a))), CalibrationHash(a));
  // -0 and 0 are the same value.
  StereoCalibration negative_zero = a;
  ASSERT_EQ(negative_zero.platform->world_from_base.matrix()(0, 2), 0.0);
  negative_zero.platform->world_from_base.matrix()(0, 2) = -0.0;
  EXPECT_EQ(CalibrationHash(negative_zero), CalibrationHash(a));
}

TEST(CalibrationHash, OneChangedValueChangesIt) {
  const std::string original = ThesisText();
  const std::string hash = CalibrationHash(Parse(original));
  const std::vector<std::pair<std::string, std::string>> changes = {
      {"-232.71,", "-232.7100000001,"},  // left.P
      {"-60.906,", "-60.907,"},          // right.P
      {"image_size: [ 512, 480 ]\nright", "image_size: [ 512, 481 ]\nright"},
      {"radians_per_tick: 6.4308373323298810e-05", "radians_per_tick: 6.43e-05"},
      {"{ name: pan,", "{ name: yaw,"},
      {"3.71,", "3.72,"},                            // platform.world_from_base
      {"origin: [ -0.9972,", "origin: [ -0.9973,"},  // ranger
      {"axis: [ 0.04348,", "axis: [ 0.04349,"},
  };
  for (const auto& [from, to] : changes) {
    EXPECT_NE(CalibrationHash(Parse(Replace(original, from, to))), hash) << from << " -> " << to;
  }
  // A lens, and a calibration without its ranger or platform.
  StereoCalibration c = Parse(original);
  c.left.K = Eigen::Matrix3d::Identity();
  const std::string with_lens = CalibrationHash(c);
  EXPECT_NE(with_lens, hash);
  c.left.dist = {0.1, 0.0, 0.0, 0.0};
  EXPECT_NE(CalibrationHash(c), with_lens);
  c = Parse(original);
  c.ranger.reset();
  EXPECT_NE(CalibrationHash(c), hash);
  c = Parse(original);
  c.platform.reset();
  EXPECT_NE(CalibrationHash(c), hash);
}

}  // namespace
}  // namespace igms::calibration
