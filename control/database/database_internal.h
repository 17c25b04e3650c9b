// What the geometric database's source files share and nobody else sees: the
// connection with its prepared statements (GeometricDatabase::Impl), the writer's file lock,
// and how an SQLite failure becomes a DatabaseError.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "control/database/geometric_database.h"
#include "control/database/sqlite.h"

namespace igms::control {

namespace database_detail {

DatabaseError Fail(DatabaseErrorCode code, std::string message);

// An SQLite failure as the database's error, naming the file.
DatabaseError FromSqlite(const std::string& path, const sqlite::SqliteError& e);

std::string HostName();

// "add" -> ChangeKind::kAdd; a name it does not know is a damaged file.
ChangeKind KindFromName(const std::string& name);

// The exclusive lock that makes one session the database's only writer: flock on
// "<database>.lock", which the kernel releases when the process ends however it ends. The
// file says who holds it, for the message the next one gets.
class FileLock {
 public:
  static DatabaseResult<std::unique_ptr<FileLock>> Acquire(const std::string& database,
                                                           const SessionInfo& who);
  ~FileLock();
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  FileLock(std::string path, int fd) : path_(std::move(path)), fd_(fd) {}
  std::string path_;
  int fd_;
};

}  // namespace database_detail

struct GeometricDatabase::Impl {
  Impl(const std::string& path, std::unique_ptr<database_detail::FileLock> held,
       sqlite::Connection::Mode mode = sqlite::Connection::Mode::kReadWriteCreate)
      : lock(std::move(held)), connection(path, mode) {}

  // Prepared once, reused: storing a model is a handful of statements.
  sqlite::Statement& Prepared(const std::string& sql) {
    auto& slot = statements[sql];
    if (!slot) slot = std::make_unique<sqlite::Statement>(connection, sql);
    slot->Reset();
    return *slot;
  }

  // Appends one row to the history; returns its seq (database_write.cpp).
  std::int64_t AppendChange(ChangeKind kind, std::int64_t model_id, std::int64_t session_id,
                            std::optional<std::int64_t> undoes, std::int64_t now);

  // The model at the row m stands on, with its shape, marks and servers (database_read.cpp).
  StoredModel ReadModel(const sqlite::Statement& m);

  // Destroyed in reverse: the statements, the connection (its last checkpoint), the lock.
  std::unique_ptr<database_detail::FileLock> lock;
  sqlite::Connection connection;
  std::map<std::string, std::unique_ptr<sqlite::Statement>> statements;
};

}  // namespace igms::control
