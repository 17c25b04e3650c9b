#include "control/database/sqlite.h"

#include <sqlite3.h>

namespace igms::control::sqlite {

Connection::Connection(const std::string& path, Mode mode) : path_(path) {
  const int flags =
      mode == Mode::kReadOnly ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE;
  const int rc = sqlite3_open_v2(path.c_str(), &db_, flags, nullptr);
  if (rc != SQLITE_OK) {
    const std::string message = db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(rc);
    sqlite3_close_v2(db_);
    db_ = nullptr;
    throw SqliteError(rc & 0xff, "cannot open: " + message);
  }
}

Connection::~Connection() {
  if (db_) sqlite3_close_v2(db_);
}

void Connection::Throw(int code, std::string_view what) const {
  std::string message(what);
  message += ": ";
  message += db_ ? sqlite3_errmsg(db_) : sqlite3_errstr(code);
  throw SqliteError(code & 0xff, message);
}

void Connection::Execute(std::string_view sql) {
  char* error = nullptr;
  const std::string text(sql);
  const int rc = sqlite3_exec(db_, text.c_str(), nullptr, nullptr, &error);
  if (rc != SQLITE_OK) {
    const std::string message = error ? error : sqlite3_errstr(rc);
    sqlite3_free(error);
    throw SqliteError(rc & 0xff, message);
  }
}

std::int64_t Connection::QueryInt(std::string_view sql) {
  Statement statement(*this, sql);
  if (!statement.Step()) Throw(SQLITE_ERROR, "no answer to " + std::string(sql));
  return statement.FirstInt();
}

std::string Connection::QueryText(std::string_view sql) {
  Statement statement(*this, sql);
  if (!statement.Step()) Throw(SQLITE_ERROR, "no answer to " + std::string(sql));
  return statement.FirstText();
}

std::int64_t Connection::LastInsertId() const { return sqlite3_last_insert_rowid(db_); }

Statement::Statement(Connection& connection, std::string_view sql) : connection_(connection) {
  const int rc = sqlite3_prepare_v2(connection.handle(), sql.data(), static_cast<int>(sql.size()),
                                    &stmt_, nullptr);
  if (rc != SQLITE_OK) connection.Throw(rc, "cannot prepare '" + std::string(sql) + "'");
  const int count = sqlite3_column_count(stmt_);
  for (int i = 0; i < count; ++i) columns_[sqlite3_column_name(stmt_, i)] = i;
}

Statement::~Statement() { sqlite3_finalize(stmt_); }

int Statement::Parameter(const char* name) const {
  const int index = sqlite3_bind_parameter_index(stmt_, name);
  // A name the SQL lacks is a programmer error in this folder, never the operator's.
  if (index == 0) {
    throw SqliteError(SQLITE_MISUSE,
                      std::string("no parameter ") + name + " in '" + sqlite3_sql(stmt_) + "'");
  }
  return index;
}

int Statement::Column(const std::string& name) const {
  const auto it = columns_.find(name);
  if (it == columns_.end()) {
    throw SqliteError(SQLITE_MISUSE,
                      "no column " + name + " in '" + std::string(sqlite3_sql(stmt_)) + "'");
  }
  return it->second;
}

void Statement::Bind(const char* name, std::int64_t value) {
  const int rc = sqlite3_bind_int64(stmt_, Parameter(name), value);
  if (rc != SQLITE_OK) connection_.Throw(rc, std::string("cannot bind ") + name);
}

void Statement::Bind(const char* name, double value) {
  const int rc = sqlite3_bind_double(stmt_, Parameter(name), value);
  if (rc != SQLITE_OK) connection_.Throw(rc, std::string("cannot bind ") + name);
}

void Statement::Bind(const char* name, std::string_view text) {
  const int rc = sqlite3_bind_text64(stmt_, Parameter(name), text.data(), text.size(),
                                     SQLITE_TRANSIENT, SQLITE_UTF8);
  if (rc != SQLITE_OK) connection_.Throw(rc, std::string("cannot bind ") + name);
}

void Statement::BindBlob(const char* name, std::string_view bytes) {
  // An empty blob stays a zero-length blob, not NULL (SQLite makes a null pointer NULL).
  static const char kEmpty = 0;
  const int rc = sqlite3_bind_blob64(stmt_, Parameter(name), bytes.empty() ? &kEmpty : bytes.data(),
                                     bytes.size(), SQLITE_TRANSIENT);
  if (rc != SQLITE_OK) connection_.Throw(rc, std::string("cannot bind ") + name);
}

void Statement::BindNull(const char* name) {
  const int rc = sqlite3_bind_null(stmt_, Parameter(name));
  if (rc != SQLITE_OK) connection_.Throw(rc, std::string("cannot bind ") + name);
}

bool Statement::Step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  connection_.Throw(rc, "'" + std::string(sqlite3_sql(stmt_)) + "' failed");
}

void Statement::Reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

bool Statement::IsNull(const std::string& column) const {
  return sqlite3_column_type(stmt_, Column(column)) == SQLITE_NULL;
}

std::int64_t Statement::Int(const std::string& column) const {
  return sqlite3_column_int64(stmt_, Column(column));
}

double Statement::Real(const std::string& column) const {
  return sqlite3_column_double(stmt_, Column(column));
}

std::string Statement::Text(const std::string& column) const {
  const int index = Column(column);
  const auto* text = sqlite3_column_text(stmt_, index);
  return text ? std::string(reinterpret_cast<const char*>(text), sqlite3_column_bytes(stmt_, index))
              : std::string();
}

std::string Statement::Blob(const std::string& column) const {
  const int index = Column(column);
  const void* bytes = sqlite3_column_blob(stmt_, index);
  return bytes ? std::string(static_cast<const char*>(bytes), sqlite3_column_bytes(stmt_, index))
               : std::string();
}

std::optional<std::int64_t> Statement::OptionalInt(const std::string& column) const {
  if (IsNull(column)) return std::nullopt;
  return Int(column);
}

std::optional<double> Statement::OptionalReal(const std::string& column) const {
  if (IsNull(column)) return std::nullopt;
  return Real(column);
}

std::int64_t Statement::FirstInt() const { return sqlite3_column_int64(stmt_, 0); }

std::string Statement::FirstText() const {
  const auto* text = sqlite3_column_text(stmt_, 0);
  return text ? std::string(reinterpret_cast<const char*>(text), sqlite3_column_bytes(stmt_, 0))
              : std::string();
}

Transaction::Transaction(Connection& connection) : connection_(connection) {
  connection_.Execute("BEGIN IMMEDIATE");
}

Transaction::~Transaction() {
  if (!done_) {
    try {
      connection_.Execute("ROLLBACK");
    } catch (const SqliteError&) {
      // SQLite may have rolled back already (after an I/O error); nothing is left to undo.
    }
  }
}

void Transaction::Commit() {
  connection_.Execute("COMMIT");
  done_ = true;
}

}  // namespace igms::control::sqlite
