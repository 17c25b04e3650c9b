// A thin C++ layer over the SQLite C API for the geometric database: a connection, a prepared
// statement with named parameters and columns, and a transaction that rolls back unless
// committed. Failures throw SqliteError, which geometric_database.cpp turns into a
// DatabaseError at its API; nothing outside this folder sees SQLite.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <unordered_map>

struct sqlite3;
struct sqlite3_stmt;

namespace igms::control::sqlite {

class SqliteError : public std::runtime_error {
 public:
  SqliteError(int code, const std::string& what) : std::runtime_error(what), code_(code) {}
  int code() const { return code_; }  // the primary SQLite result code (SQLITE_CORRUPT, ...)

 private:
  int code_;
};

class Connection {
 public:
  enum class Mode { kReadOnly, kReadWriteCreate };
  // Throws SqliteError when the file cannot be opened. SQLite reads lazily: a file that is
  // not a database is found out by the first statement.
  Connection(const std::string& path, Mode mode);
  ~Connection();
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;

  // Runs SQL without results (several statements allowed).
  void Execute(std::string_view sql);
  // The first column of the first row of a query as an integer or text.
  std::int64_t QueryInt(std::string_view sql);
  std::string QueryText(std::string_view sql);
  std::int64_t LastInsertId() const;
  sqlite3* handle() { return db_; }
  const std::string& path() const { return path_; }

  // Throws SqliteError for `code` with SQLite's message, prefixed by `what`.
  [[noreturn]] void Throw(int code, std::string_view what) const;

 private:
  sqlite3* db_ = nullptr;
  std::string path_;
};

// A prepared statement. Parameters are named (":center_x") and columns read by name.
class Statement {
 public:
  Statement(Connection& connection, std::string_view sql);
  ~Statement();
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  void Bind(const char* name, std::int64_t value);
  void Bind(const char* name, double value);
  void Bind(const char* name, std::string_view text);
  void BindBlob(const char* name, std::string_view bytes);
  void BindNull(const char* name);
  template <class T>
  void Bind(const char* name, const std::optional<T>& value) {
    if (value)
      Bind(name, *value);
    else
      BindNull(name);
  }

  // Runs one step: true when a row is ready to be read, false when done.
  bool Step();
  // Ready for new bindings and a new run.
  void Reset();

  bool IsNull(const std::string& column) const;
  std::int64_t Int(const std::string& column) const;
  double Real(const std::string& column) const;
  std::string Text(const std::string& column) const;
  std::string Blob(const std::string& column) const;
  std::optional<std::int64_t> OptionalInt(const std::string& column) const;
  std::optional<double> OptionalReal(const std::string& column) const;
  // The first column, whatever its name (PRAGMA answers, counts).
  std::int64_t FirstInt() const;
  std::string FirstText() const;

 private:
  int Parameter(const char* name) const;
  int Column(const std::string& name) const;

  Connection& connection_;
  sqlite3_stmt* stmt_ = nullptr;
  std::unordered_map<std::string, int> columns_;
};

// BEGIN IMMEDIATE on construction (the write lock is taken at once, so a change never fails
// half-way for a lock); ROLLBACK on destruction unless Commit() ran.
class Transaction {
 public:
  explicit Transaction(Connection& connection);
  ~Transaction();
  Transaction(const Transaction&) = delete;
  Transaction& operator=(const Transaction&) = delete;
  void Commit();

 private:
  Connection& connection_;
  bool done_ = false;
};

}  // namespace igms::control::sqlite
