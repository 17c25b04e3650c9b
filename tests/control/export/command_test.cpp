// igms export, the real program, on real database files made with the database's API: every
// format written and loaded by real consumers (check_urdf, assimp) when they are installed;
// read-only beside a running session; --watch; and bad input, each with its message and exit
// status.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>

#include "common/config/exit_codes.h"
#include "control/database/geometric_database.h"
#include "tests/control/export/export_samples.h"
#include "tests/support/child_process.h"
#include "tests/support/files.h"
#include "tests/support/wait_for.h"

namespace igms::control {
namespace {

namespace fs = std::filesystem;
using igms::testing::ReadFile;
using igms::testing::RunShell;
using igms::testing::ScratchDir;
using igms::testing::ShellRun;

std::string Export() { return igms::testing::BinDir() + "/igms-export"; }

ShellRun RunExport(const std::string& args) { return RunShell(Export() + " " + args + " 2>&1"); }

bool Installed(const std::string& program) {
  return RunShell("command -v " + program + " >/dev/null 2>&1").status == 0;
}

// A database with a cylinder and a textured box, written by a session that has ended.
std::string MakeDatabase(const ScratchDir& dir, bool with_models = true) {
  std::string path = dir.File("igms.db");
  auto db = GeometricDatabase::Open(path, {"export-test", "1"});
  EXPECT_TRUE(db.ok()) << db.error();
  if (with_models) {
    EXPECT_TRUE((*db)->AddModel(testing::ExportCylinder().record).ok());
    EXPECT_TRUE((*db)->AddModel(testing::ExportBox().record).ok());
  }
  return path;
}

TEST(ExportCommand, WritesEveryFormatAndRealConsumersLoadThem) {
  ScratchDir dir;
  const std::string db = MakeDatabase(dir);
  const std::string out = dir.File("out");
  const ShellRun run = RunExport("--database " + db + " --all " + out);
  ASSERT_EQ(run.status, kExitOk) << run.out;
  EXPECT_NE(run.out.find("2 models in 7 formats"), std::string::npos) << run.out;
  for (const char* name :
       {"models.scene", "models.urdf", "models.gltf", "models.bin", "models.glb", "models.obj",
        "models.mtl", "models.stl", "models.json", "models_textures/model_2.png"}) {
    EXPECT_TRUE(fs::exists(out + "/" + name)) << name;
  }
  if (Installed("check_urdf")) {
    const ShellRun urdf = RunShell("check_urdf " + out + "/models.urdf 2>&1");
    EXPECT_EQ(urdf.status, 0) << urdf.out;
    EXPECT_NE(urdf.out.find("root Link: world has 2 child(ren)"), std::string::npos) << urdf.out;
  } else {
    std::cout << "check_urdf is not installed (liburdfdom-tools): URDF not checked by it\n";
  }
  if (Installed("assimp")) {
    for (const char* name : {"models.obj", "models.stl", "models.gltf", "models.glb"}) {
      const ShellRun info = RunShell("cd " + out + " && assimp info " + name + " 2>&1");
      EXPECT_EQ(info.status, 0) << name << ": " << info.out;
      EXPECT_EQ(info.out.find("rror"), std::string::npos) << name << ": " << info.out;
      EXPECT_NE(info.out.find("Meshes:"), std::string::npos) << name << ": " << info.out;
    }
  } else {
    std::cout << "assimp is not installed (assimp-utils): OBJ, STL, glTF not checked by it\n";
  }
  // Through the lab's dispatcher too.
  const ShellRun dispatched = RunShell(igms::testing::BinDir() + "/igms export --database " + db +
                                       " --format scene --out " + dir.File("d.scene") + " 2>&1");
  EXPECT_EQ(dispatched.status, kExitOk) << dispatched.out;
  EXPECT_NE(ReadFile(dir.File("d.scene")).find("* model_1\n"), std::string::npos);
}

TEST(ExportCommand, ReadsBesideARunningSessionAndWatchesItsChanges) {
  ScratchDir dir;
  const std::string path = dir.File("live.db");
  auto session = GeometricDatabase::Open(path, {"igms-control", "test"});
  ASSERT_TRUE(session.ok()) << session.error();
  ASSERT_TRUE((*session)->AddModel(testing::ExportCylinder().record).ok());
  // The session holds the file: the export reads it anyway, and takes no lock of its own.
  const std::string json = dir.File("out/models.json");
  igms::testing::ChildProcess watcher(
      Export(), {"--database", path, "--all", dir.File("out"), "--watch", "--interval-ms", "20"});
  ASSERT_TRUE(watcher.WaitForLog("watching")) << watcher.Log();
  EXPECT_NE(ReadFile(json).find("\"id\": 1,"), std::string::npos);
  ASSERT_TRUE((*session)->AddModel(testing::ExportBox().record).ok());
  EXPECT_TRUE(igms::testing::WaitFor("the new box in the export", [&] {
    return ReadFile(json).find("\"id\": 2,") != std::string::npos;
  }));
  const std::string texture = dir.File("out/models_textures/model_2.png");
  EXPECT_TRUE(fs::exists(texture));
  ASSERT_TRUE((*session)->RemoveModel(1).ok());
  EXPECT_TRUE(igms::testing::WaitFor("the removed cylinder gone from the export", [&] {
    return ReadFile(json).find("\"id\": 1,") == std::string::npos;
  }));
  // A removed box takes its texture with it.
  ASSERT_TRUE((*session)->RemoveModel(2).ok());
  EXPECT_TRUE(igms::testing::WaitFor("the removed box's texture gone",
                                     [&] { return !fs::exists(texture); }));
  EXPECT_EQ(watcher.Terminate(), 0) << watcher.Log();
  // The session went on writing throughout.
  EXPECT_TRUE((*session)->Undo().ok());
}

TEST(ExportCommand, ReadsIgmsLocateJson) {
  ScratchDir dir;
  igms::testing::WriteFile(
      dir.File("found.jsonl"),
      "{\"found\": true, \"type\": \"cylinder\", \"center\": [1, 2, 3], \"axis\": [0, 0, 1], "
      "\"radius\": 0.5, \"height\": 4, \"sigma\": {\"center\": [0.01, 0.01, 0.02], \"radius\": "
      "0.003, \"height\": 0.02}, \"rms_px\": [0.4, 0.5], \"outline_samples\": 80, "
      "\"boundary_pixels\": 500, \"ssd_rms\": 2.1, \"elapsed_ms\": 35}\n");
  const ShellRun run = RunExport("--locate-json - --format stl --out " + dir.File("p.stl") + " < " +
                                 dir.File("found.jsonl"));
  ASSERT_EQ(run.status, kExitOk) << run.out;
  EXPECT_FALSE(testing::ReadStl(ReadFile(dir.File("p.stl"))).empty());
}

TEST(ExportCommand, BadInputIsNamedWithItsExitStatus) {
  ScratchDir dir;
  // No database.
  ShellRun r =
      RunExport("--database " + dir.File("none.db") + " --format json --out " + dir.File("x.json"));
  EXPECT_EQ(r.status, kExitUnavailable) << r.out;
  EXPECT_NE(r.out.find("no database at"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir.File("none.db")));
  // A file that is not a database: refused, and left as it was.
  igms::testing::WriteFile(dir.File("junk.db"), std::string(4096, 'x'));
  r = RunExport("--database " + dir.File("junk.db") + " --format json --out " + dir.File("x.json"));
  EXPECT_EQ(r.status, kExitUnavailable) << r.out;
  EXPECT_NE(r.out.find("not an SQLite database"), std::string::npos) << r.out;
  EXPECT_EQ(ReadFile(dir.File("junk.db")), std::string(4096, 'x'));
  // An unknown format, no output named.
  const std::string db = MakeDatabase(dir);
  r = RunExport("--database " + db + " --format step --out " + dir.File("x.step"));
  EXPECT_EQ(r.status, kExitUsage) << r.out;
  EXPECT_NE(r.out.find("unknown format 'step'"), std::string::npos) << r.out;
  r = RunExport("--database " + db + " --format json");
  EXPECT_EQ(r.status, kExitUsage) << r.out;
  // An output that cannot be written: below a file.
  r = RunExport("--database " + db + " --format json --out " + db + "/x.json");
  EXPECT_EQ(r.status, kExitUnavailable) << r.out;
  EXPECT_NE(r.out.find("cannot"), std::string::npos) << r.out;
  // A model with an infinite value (made behind the API's back): refused by its id.
  {
    sqlite3* handle = nullptr;
    ASSERT_EQ(sqlite3_open(db.c_str(), &handle), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(handle, "UPDATE cylinders SET radius = 9e999 WHERE model_id = 1",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(handle);
  }
  r = RunExport("--database " + db + " --format urdf --out " + dir.File("inf.urdf"));
  EXPECT_EQ(r.status, kExitFailure) << r.out;
  EXPECT_NE(r.out.find("model 1: cylinder.radius is infinite"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir.File("inf.urdf")));
}

TEST(ExportCommand, AnEmptyDatabaseGivesEmptyFilesAndNoSTL) {
  ScratchDir dir;
  const std::string db = MakeDatabase(dir, false);
  ShellRun r = RunExport("--database " + db + " --format stl --out " + dir.File("e.stl"));
  EXPECT_EQ(r.status, kExitFailure) << r.out;
  EXPECT_NE(r.out.find("STL has no empty form"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir.File("e.stl")));
  r = RunExport("--database " + db + " --all " + dir.File("out"));
  EXPECT_EQ(r.status, kExitOk) << r.out;
  EXPECT_NE(r.out.find("STL has no empty form"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir.File("out/models.stl")));
  if (Installed("check_urdf")) {
    const ShellRun urdf = RunShell("check_urdf " + dir.File("out/models.urdf") + " 2>&1");
    EXPECT_EQ(urdf.status, 0) << urdf.out;
  }
}

}  // namespace
}  // namespace igms::control
