// igms-calibrate as a real process: every subcommand on real or synthetic data, its JSON, the
// files it writes, and exit status 2 with a message on bad input.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "common/calibration/calibration_file.h"
#include "common/sim/synthetic_platform.h"
#include "tests/common/geometry/synthetic_rig.h"

namespace igms::calibration {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int status = -1;
  std::string out, err;
};

class CalibrateCli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("igms_cli_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  Outcome Calibrate(const std::string& args) {
    const char* bin = std::getenv("IGMS_BIN_DIR");
    const std::string exe = std::string(bin ? bin : "bin") + "/igms-calibrate";
    const std::string out = (dir_ / "stdout").string(), err = (dir_ / "stderr").string();
    const int raw = std::system((exe + " " + args + " >" + out + " 2>" + err).c_str());
    Outcome r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = Read(out);
    r.err = Read(err);
    return r;
  }

  static std::string Read(const std::string& path) {
    std::ifstream in(path);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

  std::string Write(const std::string& name, const std::string& text) {
    std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }

  // The number after "key": in a JSON text (first occurrence).
  static double Number(const std::string& json, const std::string& key) {
    std::smatch m;
    const std::regex re("\"" + key + "\": (-?[0-9.eE+-]+)");
    if (!std::regex_search(json, m, re)) {
      ADD_FAILURE() << "no " << key << " in " << json;
      return NAN;
    }
    return std::stod(m[1]);
  }

  std::string Correspondences(const geometry::ProjectiveCamera& cam, int n) {
    std::mt19937 rng(7);
    std::ostringstream s;
    s << "# x y z u v\n";
    s.precision(17);
    for (int i = 0; i < n;) {
      const Eigen::Vector3d X = testing::RandomScenePoint(rng) - Eigen::Vector3d(30, 0, 0);
      const auto px = cam.Project(X);
      if (!px || !cam.InImage(*px)) continue;
      s << X.x() << " " << X.y() << " " << X.z() << " " << px->x() << " " << px->y() << "\n";
      ++i;
    }
    return s.str();
  }

  fs::path dir_;
};

geometry::ProjectiveCamera Shifted(const geometry::ProjectiveCamera& cam) {
  Eigen::Matrix4d T = Eigen::Matrix4d::Identity();
  T(0, 3) = 30;
  return geometry::ProjectiveCamera(cam.P() * T, {512, 480});
}

TEST_F(CalibrateCli, DecomposesTheThesisFile) {
  const char* src = std::getenv("IGMS_SOURCE_DIR");
  const std::string file =
      std::string(src ? src : ".") + "/common/calibration/data/thesis_calibration.yaml";
  const Outcome r = Calibrate("decompose " + file + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NEAR(Number(r.out, "ku"), -955.98, 0.01);
  EXPECT_NEAR(Number(r.out, "kv"), 1198.18, 0.01);
  EXPECT_NEAR(Number(r.out, "printed_theta"), 1.529, 0.001);
  EXPECT_NEAR(Number(r.out, "fovy_degrees"), 22.65, 0.01);  // thesis 4.4: "23 degrees"
  const Outcome text = Calibrate("decompose " + file);
  ASSERT_EQ(text.status, 0);
  EXPECT_NE(text.out.find("right camera"), std::string::npos);
}

TEST_F(CalibrateCli, PointsCalibratesAndWritesAFile) {
  const auto rig = testing::ThesisLikeRig();
  const auto left = Shifted(rig.left), right = Shifted(rig.right);
  const std::string l = Write("l.txt", Correspondences(left, 20));
  const std::string rr = Write("r.txt", Correspondences(right, 20));
  const std::string out = (dir_ / "cal.yaml").string();
  for (const char* method : {"thesis", "normalized"}) {
    std::string args = "points --left ";
    args.append(l).append(" --right ").append(rr).append(" --method ").append(method);
    const Outcome r = Calibrate(args.append(" --output ").append(out).append(" --json"));
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_LT(Number(r.out, "rms"), 1e-6);
    const auto cal = LoadCalibration(out);
    ASSERT_TRUE(cal.ok()) << cal.error();
    const Eigen::Vector3d X(20, 1, 3);
    EXPECT_LT((*cal->right.Camera().Project(X) - *right.Project(X)).norm(), 1e-6);
  }
  const Outcome text = Calibrate("points " + l);
  EXPECT_EQ(text.status, 0);
  EXPECT_NE(text.out.find("rms"), std::string::npos);
}

TEST_F(CalibrateCli, BadInputExitsTwoWithAMessage) {
  const auto left = Shifted(testing::ThesisLikeRig().left);
  Outcome r = Calibrate("points " + Write("few.txt", Correspondences(left, 5)));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("at least 6"), std::string::npos) << r.err;
  r = Calibrate("points " + Write("bad.txt", "1 2 3 4\n"));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("line 1"), std::string::npos) << r.err;
  r = Calibrate("decompose /nonexistent.yaml");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("cannot open"), std::string::npos);
  r = Calibrate("decompose " + Write("broken.yaml", "%YAML:1.0\n---\nleft: 3\n"));
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("left"), std::string::npos) << r.err;
  r = Calibrate("chessboard --left a.jpg --right b.jpg --board 9by6");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("--board"), std::string::npos);
  r = Calibrate("frobnicate");
  EXPECT_EQ(r.status, 2);
  r = Calibrate("points --no-such-flag");
  EXPECT_EQ(r.status, 2);
  r = Calibrate("");
  EXPECT_EQ(r.status, 2);
  r = Calibrate("platform --synthetic --noise -1");
  EXPECT_EQ(r.status, 2);
}

TEST_F(CalibrateCli, ChessboardOnRealPairsBeatsTheSample) {
  std::string left = " --left", right = " --right";
  for (int i = 1; i <= 14; ++i) {
    if (i == 10) continue;
    char name[96];
    std::snprintf(name, sizeof name, " /usr/share/doc/opencv-doc/examples/data/left%02d.jpg", i);
    left += name;
    std::snprintf(name, sizeof name, " /usr/share/doc/opencv-doc/examples/data/right%02d.jpg", i);
    right += name;
  }
  const std::string out = (dir_ / "cb.yaml").string();
  const Outcome r = Calibrate("chessboard" + left + right + " --board 9x6 --square 1.0 --output " +
                              out + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(Number(r.out, "pairs_used"), 13);
  EXPECT_LT(Number(r.out, "stereo_rms"), 0.634);
  EXPECT_LT(Number(r.out, "epipolar_error"), 0.445);
  EXPECT_LT(Number(r.out, "left_rms"), 0.5);
  EXPECT_NE(r.err.find("corners 13/13"), std::string::npos) << "progress is shown";
  EXPECT_TRUE(LoadCalibration(out).ok());
}

TEST_F(CalibrateCli, PlatformFromObservationFileAndSynthetic) {
  const auto s = MakePlatformScenario(0.2, 9);
  StereoCalibration cal;
  cal.left.P = s.P0[0];
  cal.right.P = s.P0[1];
  cal.left.image_size = cal.right.image_size = s.size;
  cal.platform = s.nominal;
  const std::string cal_path = (dir_ / "start.yaml").string();
  ASSERT_TRUE(SaveCalibration(cal, cal_path));
  std::ostringstream obs;
  obs.precision(17);
  for (const auto& o : s.observations) {
    obs << (o.camera ? "right" : "left");
    for (double t : o.ticks) obs << " " << t;
    obs << " " << o.world.x() << " " << o.world.y() << " " << o.world.z() << " " << o.pixel.x()
        << " " << o.pixel.y() << "\n";
  }
  const std::string obs_path = Write("obs.txt", obs.str());
  const std::string out = (dir_ / "fitted.yaml").string();
  Outcome r = Calibrate("platform --calibration " + cal_path + " --observations " + obs_path +
                        " --estimate-scales --output " + out + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_LT(Number(r.out, "rms"), 0.4);
  EXPECT_GT(Number(r.out, "initial_rms"), 2.0);
  EXPECT_NE(r.err.find("iteration 1"), std::string::npos);
  const auto fitted = LoadCalibration(out);
  ASSERT_TRUE(fitted.ok() && fitted->platform) << fitted.error();
  EXPECT_LT(CompareToTruth(s, *fitted->platform, 1).prediction_rms_px, 0.1);

  r = Calibrate("platform --synthetic --estimate-scales --json");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_LT(Number(r.out, "prediction_rms_px"), 0.1);
  EXPECT_LT(Number(r.out, "max_axis_angle_deg"), 0.05);

  // A calibration without a platform map cannot start.
  cal.platform.reset();
  ASSERT_TRUE(SaveCalibration(cal, cal_path));
  r = Calibrate("platform --calibration " + cal_path + " --observations " + obs_path);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("platform: missing"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace igms::calibration
