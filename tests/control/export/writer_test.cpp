// The control client's exports (ExportWriter): every format rewritten into one folder as the
// models change, on its own thread, the newest list winning; a refused model leaves the files
// as they were and says why.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <mutex>
#include <sstream>

#include "control/export/export_writer.h"
#include "tests/control/export/export_samples.h"
#include "tests/support/child_process.h"

namespace igms::control {
namespace {

using testing::ExportBox;
using testing::ExportCylinder;

std::string Read(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(ExportWriter, RewritesEveryFormatAsTheModelsChange) {
  igms::testing::ScratchDir dir;
  const std::string folder = dir.File("exports");
  std::mutex mutex;
  std::vector<std::string> heard;
  {
    ExportWriter writer(folder, ExportOptions{}, [&](bool ok, const std::string& what) {
      std::lock_guard lock(mutex);
      heard.push_back((ok ? "ok: " : "error: ") + what);
    });
    writer.Update({ExportCylinder(3)});
    writer.Flush();
    EXPECT_NE(Read(folder + "/models.urdf").find("model_3"), std::string::npos);
    EXPECT_TRUE(std::filesystem::exists(folder + "/models.glb"));
    EXPECT_TRUE(std::filesystem::exists(folder + "/models.stl"));

    writer.Update({ExportCylinder(3), ExportBox(5)});
    writer.Flush();
    EXPECT_NE(Read(folder + "/models.urdf").find("model_5"), std::string::npos);

    // A model the exports refuse: the files stay as they were, and the writer says why.
    StoredModel bad = ExportCylinder(9);
    bad.record.cylinder.set_radius(std::numeric_limits<double>::quiet_NaN());
    writer.Update({ExportCylinder(3), ExportBox(5), bad});
    writer.Flush();
    EXPECT_NE(Read(folder + "/models.urdf").find("model_5"), std::string::npos);
    EXPECT_EQ(Read(folder + "/models.urdf").find("model_9"), std::string::npos);

    // The last update before the writer ends is written.
    writer.Update({ExportBox(5)});
  }
  EXPECT_EQ(Read(folder + "/models.urdf").find("model_3"), std::string::npos);
  EXPECT_NE(Read(folder + "/models.urdf").find("model_5"), std::string::npos);
  ASSERT_EQ(heard.size(), 4u);
  EXPECT_EQ(heard[0].rfind("ok: 1 models in", 0), 0u) << heard[0];
  EXPECT_NE(heard[2].find("model 9"), std::string::npos) << heard[2];
  EXPECT_EQ(heard[2].rfind("error: ", 0), 0u) << heard[2];
}

}  // namespace
}  // namespace igms::control
