// deploy/vision-demo.sh end to end: both servers as processes, the driver's table and JSON;
// and the driver naming the step that failed when the object server is not there.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace {

std::string Env(const char* name) {
  const char* v = std::getenv(name);
  return v ? v : "";
}

std::string Slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

int RunShell(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(VisionDemo, ScriptLocatesEveryTestbedObject) {
  const auto run =
      std::filesystem::temp_directory_path() / ("igms_vision_demo_" + std::to_string(::getpid()));
  std::filesystem::remove_all(run);
  const std::string out = (run / "stdout.txt").string();
  std::filesystem::create_directories(run);
  const int rc = RunShell("IGMS_RUN_DIR=" + run.string() + " " + Env("IGMS_SOURCE_DIR") +
                          "/deploy/vision-demo.sh " + Env("IGMS_BUILD_DIR") + " >" + out + " 2>&1");
  const std::string printed = Slurp(out);
  EXPECT_EQ(rc, 0) << printed;
  std::string json, video_log, object_log;
  for (const auto& entry : std::filesystem::directory_iterator(run)) {
    if (!entry.is_directory()) continue;
    json = Slurp((entry.path() / "results.json").string());
    video_log = Slurp((entry.path() / "video.log").string());
    object_log = Slurp((entry.path() / "object.log").string());
  }
  // The script stopped both servers before it returned (it waits for them).
  EXPECT_NE(video_log.find("shutting down"), std::string::npos) << video_log;
  EXPECT_NE(object_log.find("shutting down"), std::string::npos) << object_log;
  // The default testbed: five cylinders and two boxes, all found.
  size_t objects = 0, found = 0;
  for (size_t p = 0; (p = json.find("\"found\": ", p)) != std::string::npos; ++p) {
    ++objects;
    if (json.compare(p + 9, 4, "true") == 0) ++found;
  }
  EXPECT_EQ(objects, 7u) << json;
  EXPECT_EQ(found, 7u) << json;
  EXPECT_NE(printed.find("upright_0"), std::string::npos) << printed;
  std::filesystem::remove_all(run);
}

TEST(VisionDemo, DriverNamesTheFailedStep) {
  // A video server's port with nothing listening: the connect step fails, quickly and named.
  const std::string out = (std::filesystem::temp_directory_path() /
                           ("igms_vision_demo_fail_" + std::to_string(::getpid())))
                              .string();
  const int rc = RunShell(
      Env("IGMS_BIN_DIR") + "/igms-vision-demo --config " + Env("IGMS_SOURCE_DIR") +
      "/deploy/lab.yaml --set processes.video.port=1 --out " + out + " >" + out + ".txt 2>&1");
  const std::string printed = Slurp(out + ".txt");
  EXPECT_EQ(rc, 1) << printed;
  EXPECT_NE(printed.find("step 'connect video' failed"), std::string::npos) << printed;
  std::filesystem::remove(out + ".txt");
  std::filesystem::remove_all(out);
}

}  // namespace
