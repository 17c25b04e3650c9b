#include "common/config/lab_config.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>

#include "common/config/process_options.h"

namespace igms::config {
namespace {

const char* kLab = R"(lab:
  token: abc
  calibration: cal/thesis.yaml
processes:
  video:
    program: igms-video-server
    host: 127.0.0.1
    port: 7301
  sound:
    port: not-a-port
)";

TEST(LabConfig, ReadsDottedKeysWithFallbacks) {
  const auto c = LabConfig::FromString(kLab, "lab.yaml");
  EXPECT_EQ(c.Get<int>("processes.video.port"), 7301);
  EXPECT_EQ(c.Get<std::string>("lab.token"), "abc");
  EXPECT_EQ(c.Get<int>("processes.video.missing", 5), 5);
  EXPECT_TRUE(c.Has("processes.sound"));
  EXPECT_FALSE(c.Has("processes.object"));
  EXPECT_EQ(c.ProcessNames(), (std::vector<std::string>{"video", "sound"}));
}

TEST(LabConfig, ErrorsNameFileLineAndKey) {
  const auto c = LabConfig::FromString(kLab, "lab.yaml");
  try {
    c.Get<int>("processes.sound.port");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_STREQ(
        e.what(),
        "lab.yaml:10: processes.sound.port cannot be read as an integer (found 'not-a-port')");
  }
  try {
    c.Get<std::string>("processes.object.host");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("processes.object.host is missing"), std::string::npos);
  }
}

TEST(LabConfig, BadYamlNamesTheLine) {
  try {
    LabConfig::FromString("lab:\n  token: [unclosed\nprocesses: {}\n", "broken.yaml");
    FAIL() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("broken.yaml:", 0), 0u) << e.what();
  }
  EXPECT_THROW(LabConfig::Load("/nonexistent/lab.yaml"), ConfigError);
  EXPECT_THROW(LabConfig::FromString("- a list\n- not a map\n"), ConfigError);
}

TEST(LabConfig, OverridesCreateAndReplaceKeys) {
  auto c = LabConfig::FromString(kLab, "lab.yaml");
  c.Set("processes.video.port", "7400");
  c.Set("processes.object.host", "10.0.0.2");
  c.Set("processes.video.roi", "[1, 2, 3]");
  EXPECT_EQ(c.Get<int>("processes.video.port"), 7400);
  EXPECT_EQ(c.Get<std::string>("processes.object.host"), "10.0.0.2");
  EXPECT_EQ(c.Get<std::vector<int>>("processes.video.roi"), (std::vector<int>{1, 2, 3}));
  // The rest of the file is untouched.
  EXPECT_EQ(c.Get<std::string>("processes.video.program"), "igms-video-server");
}

// yaml-cpp's Node copies share one tree and Node assignment rewrites the shared tree: a
// copy of a configuration must still be a configuration of its own.
TEST(LabConfig, CopiesAndAssignmentsLeaveTheOriginalAlone) {
  const auto original = LabConfig::FromString(kLab, "lab.yaml");
  LabConfig copy = original;
  copy.Set("processes.video.port", "7400");
  EXPECT_EQ(original.Get<int>("processes.video.port"), 7301);
  EXPECT_EQ(copy.Get<int>("processes.video.port"), 7400);

  LabConfig assigned = original;  // shares nothing with original, so assigning to it...
  assigned = LabConfig::FromString("lab: {token: other}\n", "other.yaml");
  EXPECT_EQ(original.Get<std::string>("lab.token"), "abc");  // ...leaves original as it was
  EXPECT_EQ(assigned.Get<std::string>("lab.token"), "other");
  EXPECT_EQ(assigned.source(), "other.yaml");
  const LabConfig from = LabConfig::FromString("lab: {token: third}\n");
  assigned = from;
  assigned.Set("lab.token", "changed");
  EXPECT_EQ(from.Get<std::string>("lab.token"), "third");
  EXPECT_EQ(original.Get<std::string>("lab.token"), "abc");

  LabConfig moved = std::move(copy);
  EXPECT_EQ(moved.Get<int>("processes.video.port"), 7400);
  moved = std::move(assigned);
  EXPECT_EQ(moved.Get<std::string>("lab.token"), "changed");
}

TEST(ProcessOptions, CopiesLeaveTheOriginalAlone) {
  ProcessOptions process;
  process.name = "video";
  process.config = LabConfig::FromString(kLab, "lab.yaml");
  const auto port = [](const ProcessOptions& p) { return p.config.Get<int>(p.Key("port")); };
  ProcessOptions copy = process;
  copy.config.Set(copy.Key("port"), "7400");
  EXPECT_EQ(port(process), 7301);
  EXPECT_EQ(port(copy), 7400);
  ProcessOptions assigned = process;
  assigned = copy;
  assigned.config.Set(assigned.Key("port"), "7500");
  EXPECT_EQ(port(process), 7301);
  EXPECT_EQ(port(copy), 7400);
  EXPECT_EQ(port(assigned), 7500);
}

TEST(LabConfig, RelativePathsResolveAgainstTheFilesFolder) {
  const auto dir = std::filesystem::temp_directory_path() / "igms_config_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "lab.yaml") << kLab;
  const auto c = LabConfig::Load((dir / "lab.yaml").string());
  EXPECT_EQ(c.ResolvePath(c.Get<std::string>("lab.calibration")),
            (dir / "cal/thesis.yaml").string());
  EXPECT_EQ(c.ResolvePath("/abs/x.yaml"), "/abs/x.yaml");
  std::filesystem::remove_all(dir);
}

TEST(ProcessOptions, FlagsOverrideTheFile) {
  const auto dir = std::filesystem::temp_directory_path() / "igms_process_options_test";
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "lab.yaml").string();
  std::ofstream(file) << kLab;
  std::vector<std::string> args = {"prog",   "--config", file,
                                   "--name", "video",    "--port",
                                   "0",      "--set",    "processes.video.edges.sigma=1.5"};
  std::vector<char*> argv;
  argv.reserve(args.size());
  for (auto& a : args) argv.push_back(a.data());
  int rc = -1;
  boost::program_options::options_description extra("extra");
  Keys keys;
  keys.Add("edges.sigma", KeyType::kNumber, "1", "edge sigma");
  auto p = ParseProcessOptions(static_cast<int>(argv.size()), argv.data(), "video", "test", extra,
                               keys, &rc);
  ASSERT_TRUE(p);
  EXPECT_EQ(rc, 0);
  EXPECT_EQ(p->Port(9), 0);
  EXPECT_EQ(p->entry.port, 0);
  EXPECT_EQ(p->entry.program, "igms-video-server");
  EXPECT_DOUBLE_EQ(p->Get<double>("edges.sigma", 0), 1.5);
  EXPECT_EQ(p->lab.token, "abc");
  // Relative to the lab file's folder.
  EXPECT_EQ(p->lab.calibration, (dir / "cal/thesis.yaml").string());
  EXPECT_THROW(p->PortOf("video"), ConfigError) << "port 0 is no address for a client";
  EXPECT_EQ(p->HostOf("sound"), "127.0.0.1");

  std::vector<std::string> bad = {"prog", "--config", file, "--set", "novalue"};
  argv.clear();
  for (auto& a : bad) argv.push_back(a.data());
  EXPECT_FALSE(ParseProcessOptions(static_cast<int>(argv.size()), argv.data(), "video", "t", extra,
                                   keys, &rc));
  EXPECT_EQ(rc, 2);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace igms::config
