// The glTF exports against Khronos' glTF validator (npm gltf-validator, installed into the
// build tree by the CTest fixture export/gltf_validator_install): zero errors and zero
// warnings, for models with a texture and for an empty database. Skips, saying why, where
// node or the validator is missing.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "control/export/export.h"
#include "tests/control/export/export_samples.h"
#include "tests/support/child_process.h"

namespace igms::control {
namespace {

TEST(ExportGltfValidator, ReportsNoErrorsAndNoWarnings) {
  const char* build = std::getenv("IGMS_BUILD_DIR");
  ASSERT_NE(build, nullptr);
  const std::string modules = std::string(build) + "/npm/node_modules";
  if (!std::filesystem::exists(modules + "/gltf-validator/package.json")) {
    GTEST_SKIP() << "npm's gltf-validator is not in " << modules
                 << " (node, npm or the registry was unreachable when the fixture ran; see "
                    "its output): the glTF files were not validated";
  }
  igms::testing::ScratchDir dir;
  const std::vector<StoredModel> models = {testing::ExportCylinder(3), testing::ExportBox(5)};
  ExportOptions padded;
  padded.padding_sigmas = 2;
  for (const auto& [name, format, options] :
       {std::tuple{"models.glb", ExportFormat::kGlb, ExportOptions{}},
        std::tuple{"models.gltf", ExportFormat::kGltf, ExportOptions{}},
        std::tuple{"padded.glb", ExportFormat::kGlb, padded}}) {
    auto written = WriteExport(models, format, options, dir.File(name));
    ASSERT_TRUE(written.ok()) << written.error();
  }
  ASSERT_TRUE(WriteExport({}, ExportFormat::kGlb, {}, dir.File("empty.glb")).ok());
  ASSERT_TRUE(WriteExport({}, ExportFormat::kGltf, {}, dir.File("empty.gltf")).ok());
  const auto run =
      igms::testing::RunShell("NODE_PATH='" + modules + "' node '" + igms::testing::SourceDir() +
                              "/tests/control/export/validate_gltf.js' " + dir.File("models.glb") +
                              " " + dir.File("models.gltf") + " " + dir.File("padded.glb") + " " +
                              dir.File("empty.glb") + " " + dir.File("empty.gltf") + " 2>&1");
  EXPECT_EQ(run.status, 0) << run.out;
  for (const char* name : {"models.glb", "models.gltf", "padded.glb", "empty.glb", "empty.gltf"}) {
    EXPECT_NE(run.out.find(std::string(name) + ": 0 errors, 0 warnings"), std::string::npos)
        << name << "\n"
        << run.out;
  }
  std::cout << run.out;
}

}  // namespace
}  // namespace igms::control
