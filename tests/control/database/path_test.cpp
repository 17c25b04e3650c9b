// Where the database lives: --database, else lab.database (relative to the lab file), else
// the operator's data folder.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "control/database/database_path.h"
#include "tests/support/child_process.h"

namespace igms::control {
namespace {

namespace fs = std::filesystem;

const UserFolders kFolders{"/data/operator", "/home/operator"};

TEST(DatabasePath, TheFlagWinsAndIsTakenFromTheWorkingFolder) {
  const auto config = config::LabConfig::FromString("lab:\n  database: lab.db\n");
  EXPECT_EQ(ResolveDatabasePath(config, "/tmp/x/flag.db", kFolders).value(), "/tmp/x/flag.db");
  EXPECT_EQ(ResolveDatabasePath(config, "rel/flag.db", kFolders).value(),
            (fs::current_path() / "rel/flag.db").string());
}

TEST(DatabasePath, TheLabFilesPathIsRelativeToItsFolder) {
  igms::testing::ScratchDir dir;
  fs::create_directories(dir.path() / "etc");
  const std::string lab = (dir.path() / "etc" / "lab.yaml").string();
  std::ofstream(lab) << "lab:\n  database: ../run/igms-db\n";
  const auto config = config::LabConfig::Load(lab);
  EXPECT_EQ(ResolveDatabasePath(config, "", kFolders).value(),
            (dir.path() / "run" / "igms-db").string());

  const auto home = config::LabConfig::FromString("lab:\n  database: ~/models/igms.db\n");
  EXPECT_EQ(ResolveDatabasePath(home, "", kFolders).value(), "/home/operator/models/igms.db");
  EXPECT_FALSE(ResolveDatabasePath(home, "", {"", ""}).ok());
  const auto absolute = config::LabConfig::FromString("lab:\n  database: /srv/igms.db\n");
  EXPECT_EQ(ResolveDatabasePath(absolute, "", kFolders).value(), "/srv/igms.db");
}

TEST(DatabasePath, TheOneMachineLabKeepsItInTheRunFolder) {
  const auto lab = config::LabConfig::Load(igms::testing::SourceDir() + "/deploy/lab.yaml");
  EXPECT_EQ(ResolveDatabasePath(lab, "", kFolders).value(),
            (fs::absolute(igms::testing::SourceDir()) / ".lab-run" / "igms-db")
                .lexically_normal()
                .string());
}

TEST(DatabasePath, WithoutEitherItIsTheOperatorsDataFolder) {
  const config::LabConfig none;
  EXPECT_EQ(ResolveDatabasePath(none, "", kFolders).value(), "/data/operator/igms/igms.db");
  const auto empty = config::LabConfig::FromString("lab:\n  database: \"\"\n");
  EXPECT_EQ(ResolveDatabasePath(empty, "", kFolders).value(), "/data/operator/igms/igms.db");
  // XDG_DATA_HOME unset, or relative (which the XDG specification says to ignore): ~/.local/share.
  EXPECT_EQ(ResolveDatabasePath(none, "", {"", "/home/operator"}).value(),
            "/home/operator/.local/share/igms/igms.db");
  EXPECT_EQ(ResolveDatabasePath(none, "", {"relative/data", "/home/operator"}).value(),
            "/home/operator/.local/share/igms/igms.db");
  auto nowhere = ResolveDatabasePath(none, "", {"", ""});
  ASSERT_FALSE(nowhere.ok());
  EXPECT_NE(nowhere.error().find("--database FILE"), std::string::npos) << nowhere.error();
}

TEST(DatabasePath, AWrongTypeInTheLabFileIsNamed) {
  const auto config = config::LabConfig::FromString("lab:\n  database: [1, 2]\n", "lab.yaml");
  auto path = ResolveDatabasePath(config, "", kFolders);
  ASSERT_FALSE(path.ok());
  EXPECT_NE(path.error().find("lab.yaml:2: lab.database"), std::string::npos) << path.error();
}

TEST(DatabasePath, TheDefaultFolderIsMadeOnFirstOpen) {
  igms::testing::ScratchDir dir;
  const UserFolders folders{(dir.path() / "share").string(), dir.path().string()};
  const auto path = DefaultDatabasePath(folders);
  ASSERT_TRUE(path.ok()) << path.error();
  auto db = GeometricDatabase::Open(*path);
  ASSERT_TRUE(db.ok()) << db.error();
  EXPECT_TRUE(fs::exists(dir.path() / "share" / "igms" / "igms.db"));
}

TEST(DatabasePath, TheEnvironmentIsRead) {
  const UserFolders folders = UserFolders::FromEnvironment();
  EXPECT_FALSE(folders.home.empty());
  if (const char* xdg = std::getenv("XDG_DATA_HOME")) {
    EXPECT_EQ(folders.xdg_data_home, xdg);
  }
}

}  // namespace
}  // namespace igms::control
