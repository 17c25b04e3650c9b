// Opening and closing the geometric database: the writer's lock, what a file already there
// holds (refused with a message and left as it was), the schema of a new one, and the
// session row each writer adds.
#include "control/database/geometric_database.h"

#include <sqlite3.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>

#include "common/base/clock.h"
#include "control/database/database_internal.h"
#include "control/database/schema.h"
#include "control/database/sqlite.h"

namespace igms::control {

namespace fs = std::filesystem;
using database_detail::Fail;
using database_detail::FileLock;
using database_detail::FromSqlite;
using database_detail::HostName;
using sqlite::Connection;
using sqlite::SqliteError;
using sqlite::Statement;
using sqlite::Transaction;

namespace database_detail {

DatabaseError Fail(DatabaseErrorCode code, std::string message) {
  return DatabaseError{code, std::move(message)};
}

// An SQLite failure as the database's error, naming the file.
DatabaseError FromSqlite(const std::string& path, const SqliteError& e) {
  switch (e.code()) {
    case SQLITE_NOTADB:
      return Fail(DatabaseErrorCode::kNotDatabase,
                  path + " is not an SQLite database (" + e.what() + "); it was left as it is");
    case SQLITE_CORRUPT:
      return Fail(DatabaseErrorCode::kDamaged, path + " is damaged (" + e.what() + ")");
    default:
      return Fail(DatabaseErrorCode::kStorage, path + ": " + e.what());
  }
}

}  // namespace database_detail

namespace {

std::string Hex(std::int64_t value) {
  char text[32];
  std::snprintf(text, sizeof(text), "0x%08llX", static_cast<unsigned long long>(value));
  return text;
}

// What a file already there holds: true when it is an empty SQLite database (a new one),
// false when it is a current IGMS database that passes its integrity check. Read through a
// read-only connection, which never writes the file, so a file refused stays as it was.
DatabaseResult<bool> Inspect(const std::string& path) {
  try {
    Connection c(path, Connection::Mode::kReadOnly);
    // The first read: SQLITE_NOTADB here for a file that is not a database.
    const std::int64_t objects = c.QueryInt("SELECT count(*) FROM sqlite_schema");
    const std::int64_t application = c.QueryInt("PRAGMA application_id");
    const std::int64_t version = c.QueryInt("PRAGMA user_version");
    if (application == 0 && version == 0 && objects == 0) return true;
    if (application != GeometricDatabase::kApplicationId) {
      return Fail(DatabaseErrorCode::kForeignSchema,
                  path + " is an SQLite database of another application (application_id " +
                      Hex(application) + ", not IGMS's " + Hex(GeometricDatabase::kApplicationId) +
                      "); it was left as it is");
    }
    if (version > GeometricDatabase::kSchemaVersion) {
      return Fail(DatabaseErrorCode::kNewerSchema,
                  path + " has schema version " + std::to_string(version) +
                      ", newer than this program's " +
                      std::to_string(GeometricDatabase::kSchemaVersion) +
                      "; open it with a newer igms-control (it was left as it is)");
    }
    if (version < 1) {
      return Fail(DatabaseErrorCode::kForeignSchema,
                  path + " is an IGMS database without a schema version (user_version " +
                      std::to_string(version) + "); it was left as it is");
    }
    Statement check(c, "PRAGMA integrity_check(5)");
    std::string problems;
    while (check.Step()) {
      const std::string line = check.FirstText();
      if (line == "ok") continue;
      problems += (problems.empty() ? "" : "; ") + line;
    }
    if (!problems.empty()) {
      return Fail(DatabaseErrorCode::kDamaged,
                  path + " is damaged (integrity check: " + problems +
                      "); it was left as it is: restore a copy or give another file");
    }
    return false;
  } catch (const SqliteError& e) {
    DatabaseError error = FromSqlite(path, e);
    if (error.code == DatabaseErrorCode::kDamaged) error.message += "; it was left as it is";
    return error;
  }
}

// Removes the side files SQLite made while inspecting a file that was then refused.
void RemoveSideFilesCreated(const std::string& path, bool wal_existed, bool shm_existed) {
  std::error_code ignored;
  if (!wal_existed) fs::remove(path + "-wal", ignored);
  if (!shm_existed) fs::remove(path + "-shm", ignored);
}

}  // namespace

GeometricDatabase::GeometricDatabase(std::string path, std::unique_ptr<Impl> impl,
                                     std::int64_t session_id)
    : path_(std::move(path)), impl_(std::move(impl)), session_id_(session_id) {}

GeometricDatabase::~GeometricDatabase() {
  if (read_only()) return;
  try {
    Transaction t(impl_->connection);
    Statement& s = impl_->Prepared("UPDATE sessions SET closed_unix_ns = :now WHERE id = :id");
    s.Bind(":now", igms::UnixNs());
    s.Bind(":id", session_id_);
    s.Step();
    s.Reset();
    t.Commit();
  } catch (const SqliteError&) {
    // The session's end is a courtesy for the history; the models are already committed.
  }
}

DatabaseResult<std::unique_ptr<GeometricDatabase>> GeometricDatabase::Open(
    const std::string& requested, const SessionInfo& who) {
  if (requested.empty()) {
    return Fail(DatabaseErrorCode::kStorage, "no file given for the geometric database");
  }
  // Symbolic links resolved, so every name of the file finds the same lock.
  std::error_code error;
  const std::string path = fs::weakly_canonical(fs::absolute(requested), error).string();
  if (error) {
    return Fail(DatabaseErrorCode::kStorage, "cannot reach " + requested + ": " + error.message());
  }
  fs::create_directories(fs::path(path).parent_path(), error);
  if (error) {
    return Fail(DatabaseErrorCode::kStorage,
                "cannot create the folder of " + path + ": " + error.message());
  }
  if (fs::is_directory(path, error)) {
    return Fail(DatabaseErrorCode::kStorage, path + " is a folder, not a database file");
  }
  auto lock = FileLock::Acquire(path, who);
  if (!lock.ok()) return DatabaseError{lock.code(), lock.error()};

  bool empty = true;
  if (fs::exists(path, error)) {
    const bool wal_existed = fs::exists(path + "-wal", error);
    const bool shm_existed = fs::exists(path + "-shm", error);
    auto inspected = Inspect(path);
    if (!inspected.ok()) {
      RemoveSideFilesCreated(path, wal_existed, shm_existed);
      return DatabaseError{inspected.code(), inspected.error()};
    }
    empty = *inspected;
  }

  try {
    auto impl = std::make_unique<Impl>(path, std::move(*lock));
    Connection& c = impl->connection;
    // WAL: a commit appends to the log and a reader never blocks the writer; FULL: the log
    // is synced at every commit, so a committed change survives a power cut, not only a
    // crash of this process.
    const std::string mode = c.QueryText("PRAGMA journal_mode = WAL");
    if (mode != "wal") {
      return Fail(DatabaseErrorCode::kStorage,
                  path + ": cannot use write-ahead logging (journal mode " + mode + ")");
    }
    c.Execute("PRAGMA synchronous = FULL; PRAGMA foreign_keys = ON; PRAGMA busy_timeout = 5000");
    if (empty) {
      Transaction t(c);
      c.Execute(kSchemaSql);
      c.Execute("PRAGMA application_id = " + std::to_string(kApplicationId));
      c.Execute("PRAGMA user_version = " + std::to_string(kSchemaVersion));
      t.Commit();
    }
    Transaction t(c);
    Statement& s = impl->Prepared(
        "INSERT INTO sessions (opened_unix_ns, program, version, host, pid) "
        "VALUES (:now, :program, :version, :host, :pid)");
    s.Bind(":now", igms::UnixNs());
    s.Bind(":program", std::string_view(who.program));
    s.Bind(":version", std::string_view(who.version));
    s.Bind(":host", std::string_view(HostName()));
    s.Bind(":pid", static_cast<std::int64_t>(getpid()));
    s.Step();
    const std::int64_t session = c.LastInsertId();
    s.Reset();
    t.Commit();
    return std::unique_ptr<GeometricDatabase>(
        new GeometricDatabase(path, std::move(impl), session));
  } catch (const SqliteError& e) {
    return FromSqlite(path, e);
  }
}

DatabaseResult<std::unique_ptr<GeometricDatabase>> GeometricDatabase::OpenReadOnly(
    const std::string& requested) {
  if (requested.empty()) {
    return Fail(DatabaseErrorCode::kStorage, "no file given for the geometric database");
  }
  std::error_code error;
  const std::string path = fs::weakly_canonical(fs::absolute(requested), error).string();
  if (error || !fs::exists(path, error)) {
    return Fail(DatabaseErrorCode::kStorage, "no database at " + requested);
  }
  if (fs::is_directory(path, error)) {
    return Fail(DatabaseErrorCode::kStorage, path + " is a folder, not a database file");
  }
  const bool wal_existed = fs::exists(path + "-wal", error);
  const bool shm_existed = fs::exists(path + "-shm", error);
  auto inspected = Inspect(path);
  if (!inspected.ok()) {
    RemoveSideFilesCreated(path, wal_existed, shm_existed);
    return DatabaseError{inspected.code(), inspected.error()};
  }
  if (*inspected) {
    RemoveSideFilesCreated(path, wal_existed, shm_existed);
    return Fail(DatabaseErrorCode::kForeignSchema,
                path + " is an empty SQLite file, not yet a geometric database");
  }
  try {
    auto impl = std::make_unique<Impl>(path, nullptr, Connection::Mode::kReadOnly);
    impl->connection.Execute("PRAGMA busy_timeout = 5000");
    return std::unique_ptr<GeometricDatabase>(new GeometricDatabase(path, std::move(impl), 0));
  } catch (const SqliteError& e) {
    return FromSqlite(path, e);
  }
}

DatabaseResult<std::int64_t> GeometricDatabase::DataVersion() {
  try {
    return impl_->connection.QueryInt("PRAGMA data_version");
  } catch (const SqliteError& e) {
    return FromSqlite(path_, e);
  }
}

}  // namespace igms::control
