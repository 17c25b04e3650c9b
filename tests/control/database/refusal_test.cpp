// Files the database must not take, each refused with a message and left byte for byte as it
// was, with no side files left behind: not SQLite, damaged (every page in turn), another
// application's, a newer schema.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "control/database/geometric_database.h"
#include "tests/control/database/sample_records.h"
#include "tests/support/child_process.h"

namespace igms::control {
namespace {

namespace fs = std::filesystem;

std::string FileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

void WriteFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << bytes;
}

void Sql(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* error = nullptr;
  EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error), SQLITE_OK)
      << (error ? error : "");
  sqlite3_free(error);
  sqlite3_close(db);
}

// Opens `path` expecting a refusal of `code` whose message holds `words`, and checks the file
// is unchanged and no side file was left.
void ExpectRefusedUnchanged(const std::string& path, DatabaseErrorCode code,
                            const std::string& words) {
  const std::string before = FileBytes(path);
  auto db = GeometricDatabase::Open(path);
  ASSERT_FALSE(db.ok()) << "opened " << path;
  EXPECT_EQ(static_cast<int>(db.code()), static_cast<int>(code)) << db.error();
  EXPECT_NE(db.error().find(words), std::string::npos) << db.error();
  EXPECT_NE(db.error().find(path), std::string::npos)
      << "the message names the file: " << db.error();
  EXPECT_TRUE(FileBytes(path) == before) << path << " was changed";
  for (const char* side : {"-wal", "-shm", "-journal", ".lock"}) {
    EXPECT_FALSE(fs::exists(path + side)) << path + side << " was left behind";
  }
}

// A closed database of several pages: models with textures, added and one removed.
std::string MakeDatabase(const std::string& path) {
  {
    auto db = GeometricDatabase::Open(path);
    EXPECT_TRUE(db.ok()) << db.error();
    if (!db.ok()) return {};
    for (int i = 1; i <= 6; ++i) {
      auto id = (*db)->AddModel(i % 2 ? testing::SampleCylinder(i) : testing::SampleBox(i, 5000));
      EXPECT_TRUE(id.ok()) << id.error();
    }
    EXPECT_TRUE((*db)->RemoveModel(2).ok());
  }
  return FileBytes(path);
}

TEST(DatabaseRefusals, AFileThatIsNotSQLiteIsRefusedUnchanged) {
  igms::testing::ScratchDir dir;
  const std::string path = dir.File("notes.db");
  std::string text;
  for (int i = 0; i < 200; ++i) text += "these are an operator's notes, not a database\n";
  WriteFile(path, text);
  ExpectRefusedUnchanged(path, DatabaseErrorCode::kNotDatabase, "is not an SQLite database");
}

TEST(DatabaseRefusals, AnOverwrittenHeaderIsRefusedUnchanged) {
  igms::testing::ScratchDir dir;
  const std::string path = dir.File("models.db");
  std::string bytes = MakeDatabase(path);
  ASSERT_GT(bytes.size(), 4096u);
  for (int i = 0; i < 16; ++i) bytes[i] = 'X';
  WriteFile(path, bytes);
  ExpectRefusedUnchanged(path, DatabaseErrorCode::kNotDatabase, "is not an SQLite database");
}

TEST(DatabaseRefusals, EveryPageOverwrittenInTurnIsRefusedUnchanged) {
  igms::testing::ScratchDir dir;
  const std::string pristine_path = dir.File("pristine.db");
  const std::string pristine = MakeDatabase(pristine_path);
  ASSERT_FALSE(pristine.empty());
  const std::size_t page = 4096;
  ASSERT_EQ(pristine.size() % page, 0u);
  const std::size_t pages = pristine.size() / page;
  ASSERT_GE(pages, 8u) << "too few pages to test";
  // Page 1 is the header and the schema (above); each other page is a table's, an index's or
  // a texture's overflow page, and all of them are in use: none may be damaged unseen.
  for (std::size_t n = 2; n <= pages; ++n) {
    SCOPED_TRACE("page " + std::to_string(n) + " of " + std::to_string(pages));
    const std::string path = dir.File("damaged-" + std::to_string(n) + ".db");
    std::string bytes = pristine;
    std::fill(bytes.begin() + static_cast<long>((n - 1) * page),
              bytes.begin() + static_cast<long>(n * page), '\xff');
    WriteFile(path, bytes);
    ExpectRefusedUnchanged(path, DatabaseErrorCode::kDamaged, "is damaged");
  }
  // The pristine copy still opens, with its five models.
  auto db = GeometricDatabase::Open(pristine_path);
  ASSERT_TRUE(db.ok()) << db.error();
  EXPECT_EQ((*db)->ListModels()->size(), 5u);
}

TEST(DatabaseRefusals, AnotherApplicationsDatabaseIsRefusedUnchanged) {
  igms::testing::ScratchDir dir;
  const std::string plain = dir.File("plain.db");
  Sql(plain, "CREATE TABLE parts (name TEXT); INSERT INTO parts VALUES ('valve')");
  ExpectRefusedUnchanged(plain, DatabaseErrorCode::kForeignSchema, "of another application");

  const std::string other = dir.File("other.db");
  Sql(other, "PRAGMA application_id = 1234; CREATE TABLE models (id INTEGER)");
  ExpectRefusedUnchanged(other, DatabaseErrorCode::kForeignSchema, "application_id 0x000004D2");

  // Even in write-ahead-log mode.
  const std::string wal = dir.File("wal.db");
  Sql(wal, "PRAGMA journal_mode = WAL; CREATE TABLE t (x); INSERT INTO t VALUES (1)");
  ExpectRefusedUnchanged(wal, DatabaseErrorCode::kForeignSchema, "of another application");
}

TEST(DatabaseRefusals, ANewerSchemaIsRefusedUnchanged) {
  igms::testing::ScratchDir dir;
  const std::string path = dir.File("future.db");
  ASSERT_FALSE(MakeDatabase(path).empty());
  Sql(path, "PRAGMA user_version = " + std::to_string(GeometricDatabase::kSchemaVersion + 1));
  ExpectRefusedUnchanged(path, DatabaseErrorCode::kNewerSchema,
                         "has schema version " +
                             std::to_string(GeometricDatabase::kSchemaVersion + 1) +
                             ", newer than this program's");
}

TEST(DatabaseRefusals, AnEmptyFileOrEmptySQLiteDatabaseIsTakenAsNew) {
  igms::testing::ScratchDir dir;
  const std::string empty = dir.File("empty.db");
  WriteFile(empty, "");
  {
    auto db = GeometricDatabase::Open(empty);
    ASSERT_TRUE(db.ok()) << db.error();
    EXPECT_TRUE((*db)->AddModel(testing::SampleCylinder()).ok());
  }
  const std::string vacant = dir.File("vacant.db");
  Sql(vacant, "PRAGMA journal_mode = WAL");
  auto db = GeometricDatabase::Open(vacant);
  ASSERT_TRUE(db.ok()) << db.error();
  EXPECT_TRUE((*db)->AddModel(testing::SampleBox()).ok());
}

}  // namespace
}  // namespace igms::control
