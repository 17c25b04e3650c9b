// The installed lab: `cmake --install` of this build tree into a scratch prefix, and the lab
// file installed there (deploy/lab.yaml with its paths made the installed ones, derived by
// cmake/DeriveLabFile.cmake), read by the installed programs themselves.
#include <gtest/gtest.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "common/config/lab_ports.h"
#include "common/version/version.h"
#include "tests/support/child_process.h"

namespace igms {
namespace {

namespace fs = std::filesystem;
using testing::RunShell;
using testing::ScratchDir;
using testing::SourceDir;

// Every scalar of a YAML tree by its dotted key ("processes.video.port" -> "7301").
void Leaves(const YAML::Node& node, const std::string& key,
            std::map<std::string, std::string>* out) {
  if (node.IsMap()) {
    for (const auto& entry : node) {
      const std::string name = entry.first.as<std::string>();
      Leaves(entry.second, key.empty() ? name : std::string(key).append(".").append(name), out);
    }
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      Leaves(node[i], key + "." + std::to_string(i), out);
  } else {
    (*out)[key] = node.IsNull() ? "" : node.Scalar();
  }
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> out;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);) out.push_back(line);
  return out;
}

bool Inside(const fs::path& path, const fs::path& folder) {
  const std::string p = fs::weakly_canonical(path).string();
  const std::string f = fs::weakly_canonical(folder).string() + "/";
  return p.rfind(f, 0) == 0;
}

class Installed : public ::testing::Test {
 protected:
  // One install for every test here: it copies every program.
  static void SetUpTestSuite() {
    prefix_ = new ScratchDir();
    install_ =
        RunShell(std::string(IGMS_CMAKE_COMMAND) + " --install '" + std::getenv("IGMS_BUILD_DIR") +
                 "' --prefix '" + prefix_->path().string() + "' 2>&1");
  }
  static void TearDownTestSuite() {
    delete prefix_;
    prefix_ = nullptr;
  }
  void SetUp() override {
    ASSERT_EQ(install_.status, 0) << install_.out;
    ASSERT_TRUE(fs::exists(Lab())) << "no installed lab file " << Lab();
  }

  static fs::path Prefix() { return prefix_->path(); }
  static fs::path Bin() { return Prefix() / IGMS_INSTALL_BINDIR; }
  static fs::path Units() { return Prefix() / IGMS_SYSTEMD_UNIT_DIR; }
  static std::string Lab() {
    return (Prefix() / IGMS_INSTALL_SYSCONFDIR / "igms/lab.yaml").string();
  }
  // The installed `igms config ARGS --config LAB`.
  static testing::ShellRun Config(const std::string& args) {
    return RunShell("'" + (Bin() / "igms").string() + "' config " + args + " --config '" + Lab() +
                    "' 2>&1");
  }

  static ScratchDir* prefix_;
  static testing::ShellRun install_;
};
ScratchDir* Installed::prefix_ = nullptr;
testing::ShellRun Installed::install_;

TEST_F(Installed, TheLabFileNamesOnlyInstalledPrograms) {
  const auto processes = Config("processes");
  ASSERT_EQ(processes.status, 0) << processes.out;
  std::set<std::string> names;
  for (const std::string& name : Lines(processes.out)) {
    names.insert(name);
    const auto program = Config("get processes." + name + ".program");
    ASSERT_EQ(program.status, 0) << name << ": " << program.out;
    const fs::path path = Bin() / Lines(program.out).at(0);
    EXPECT_TRUE(fs::is_regular_file(path) && access(path.c_str(), X_OK) == 0)
        << "the installed lab file's " << name << " runs " << path << ", which is not installed";
  }
  // Every process of the lab, the voice daemon and the platform included.
  for (const auto& p : config::ports::kLabPorts) EXPECT_TRUE(names.count(p.process)) << p.process;
}

TEST_F(Installed, TheLabFileNamesInstalledFiles) {
  const auto calibration = Config("get lab.calibration");
  ASSERT_EQ(calibration.status, 0) << calibration.out;
  const fs::path calibration_path = Lines(calibration.out).at(0);
  EXPECT_TRUE(calibration_path.is_absolute()) << calibration_path;
  EXPECT_TRUE(fs::is_regular_file(calibration_path)) << calibration_path << " is not installed";
  EXPECT_TRUE(Inside(calibration_path, Prefix())) << calibration_path;
  // No database path: each operator's database goes in their own data folder
  // (docs/database.md), never in a folder of the installation.
  const auto database = Config("get lab.database");
  ASSERT_EQ(database.status, 0) << database.out;
  EXPECT_TRUE(Lines(database.out).empty() || Lines(database.out).at(0).empty()) << database.out;
}

// The installed programs check the installed file: every key known, every file it names there.
TEST_F(Installed, TheInstalledProgramsPassTheConfigurationCheck) {
  const auto check = Config("check");
  EXPECT_EQ(check.status, 0) << check.out;
  for (const auto& p : config::ports::kLabPorts) {
    EXPECT_NE(check.out.find(std::string(p.process) + ": OK"), std::string::npos)
        << p.process << " did not pass:\n"
        << check.out;
  }
}

// The installed file is deploy/lab.yaml with only its paths rewritten.
TEST_F(Installed, TheLabFileIsTheSourceLabWithInstalledPaths) {
  std::map<std::string, std::string> source, installed;
  Leaves(YAML::LoadFile(SourceDir() + "/deploy/lab.yaml"), "", &source);
  Leaves(YAML::LoadFile(Lab()), "", &installed);
  const std::set<std::string> paths = {"lab.calibration", "lab.database"};
  for (const auto& [key, value] : source) {
    ASSERT_TRUE(installed.count(key)) << "the installed lab file has no " << key;
    if (paths.count(key)) {
      EXPECT_NE(installed[key], value) << key << " still names the source tree's path";
    } else {
      EXPECT_EQ(installed[key], value) << key;
    }
  }
  EXPECT_EQ(installed.size(), source.size());
}

TEST_F(Installed, EveryInstalledProgramPrintsItsVersion) {
  int programs = 0;
  for (const auto& entry : fs::directory_iterator(Bin())) {
    const std::string name = entry.path().filename().string();
    const auto run = RunShell("'" + entry.path().string() + "' --version 2>&1");
    EXPECT_EQ(run.status, 0) << name << ": " << run.out;
    EXPECT_EQ(run.out, version::Line(name) + "\n") << name;
    ++programs;
  }
  EXPECT_GE(programs, 15);
}

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool HaveSystemdAnalyze() { return RunShell("command -v systemd-analyze >/dev/null").status == 0; }

// The units are written when installing: they name this prefix's igms and lab file, wherever
// the build was configured to install.
TEST_F(Installed, TheUnitsNameTheInstalledProgramsAndLabFile) {
  const std::string unit = ReadAll(Units() / "igms@.service");
  ASSERT_FALSE(unit.empty()) << "no unit " << Units() / "igms@.service";
  EXPECT_NE(unit.find("\nExecStart=" + (Bin() / "igms").string() + " run %i\n"), std::string::npos)
      << unit;
  EXPECT_NE(unit.find("\nEnvironment=IGMS_CONFIG=" + Lab() + "\n"), std::string::npos) << unit;
  EXPECT_TRUE(fs::is_regular_file(Units() / "igms.target"));
  // Enabling one instance enables the target that starts them at boot.
  EXPECT_NE(unit.find("\nAlso=igms.target\n"), std::string::npos);
  EXPECT_NE(ReadAll(Units() / "igms.target").find("WantedBy=multi-user.target"), std::string::npos);
  EXPECT_TRUE(fs::is_regular_file(Units() / "igms@video.service.d/devices.conf"));
}

// systemd-analyze verify on every process's instance, drop-ins included. systemd 252 exits 0
// on an unknown key, so any output at all is a failure.
TEST_F(Installed, EveryInstanceVerifies) {
  if (!HaveSystemdAnalyze()) GTEST_SKIP() << "no systemd-analyze";
  for (const auto& p : config::ports::kLabPorts) {
    const fs::path unit = Units() / ("igms@" + std::string(p.process) + ".service");
    const auto run = RunShell("systemd-analyze verify '" + unit.string() + "' 2>&1");
    EXPECT_EQ(run.status, 0) << unit << ":\n" << run.out;
    EXPECT_EQ(run.out, "") << unit << ":\n" << run.out;
  }
}

// Exposure under 3.0 on every instance (systemd-analyze security: 0 best, 10 worst).
TEST_F(Installed, EveryInstanceIsHardened) {
  if (!HaveSystemdAnalyze()) GTEST_SKIP() << "no systemd-analyze";
  const std::regex overall("Overall exposure level for [^:]+: ([0-9.]+)");
  for (const auto& p : config::ports::kLabPorts) {
    const fs::path unit = Units() / ("igms@" + std::string(p.process) + ".service");
    const auto run =
        RunShell("systemd-analyze security --offline=true --no-pager '" + unit.string() + "' 2>&1");
    std::smatch m;
    ASSERT_TRUE(std::regex_search(run.out, m, overall)) << unit << ":\n" << run.out;
    const double exposure = std::stod(m[1]);
    std::cout << "igms@" << p.process << ".service exposure " << exposure << "\n";
    EXPECT_LT(exposure, 3.0) << unit << ":\n" << run.out;
  }
}

}  // namespace
}  // namespace igms
