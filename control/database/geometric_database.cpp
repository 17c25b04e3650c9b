#include "control/database/geometric_database.h"

#include <fcntl.h>
#include <sqlite3.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>

#include "common/base/clock.h"
#include "control/database/schema.h"
#include "control/database/sqlite.h"

namespace igms::control {

namespace fs = std::filesystem;
using sqlite::Connection;
using sqlite::SqliteError;
using sqlite::Statement;
using sqlite::Transaction;

namespace {

std::string HostName() {
  char name[256] = {};
  if (gethostname(name, sizeof(name) - 1) != 0) return "unknown";
  return name;
}

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

std::string Hex(std::int64_t value) {
  char text[32];
  std::snprintf(text, sizeof(text), "0x%08llX", static_cast<unsigned long long>(value));
  return text;
}

// The exclusive lock that makes one session the database's only writer: flock on
// "<database>.lock", which the kernel releases when the process ends however it ends. The
// file says who holds it, for the message the next one gets.
class FileLock {
 public:
  static DatabaseResult<std::unique_ptr<FileLock>> Acquire(const std::string& database,
                                                           const SessionInfo& who) {
    const std::string path = database + ".lock";
    // A holder unlinks the file as it ends; a file locked after that is no longer the lock,
    // so lock again until the lock is on the file the path names.
    for (int attempt = 0; attempt < 20; ++attempt) {
      const int fd = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
      if (fd < 0) {
        return Fail(DatabaseErrorCode::kStorage,
                    "cannot create the lock file " + path + ": " + std::strerror(errno));
      }
      if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
        const int error = errno;
        std::string holder;
        if (error == EWOULDBLOCK) {
          char text[512] = {};
          const ssize_t n = pread(fd, text, sizeof(text) - 1, 0);
          holder = n > 0 ? std::string(text, static_cast<std::size_t>(n)) : std::string();
          while (!holder.empty() && (holder.back() == '\n' || holder.back() == ' ')) {
            holder.pop_back();
          }
        }
        close(fd);
        if (error != EWOULDBLOCK) {
          return Fail(DatabaseErrorCode::kStorage,
                      "cannot lock " + path + ": " + std::strerror(error));
        }
        return Fail(DatabaseErrorCode::kInUse,
                    database + " is in use by another session" +
                        (holder.empty() ? std::string() : " (" + holder + ")") +
                        ": one operator per database; end that session or give another file "
                        "with --database");
      }
      struct stat held {};
      struct stat named {};
      if (fstat(fd, &held) == 0 && stat(path.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
          held.st_ino == named.st_ino) {
        const std::string text = who.program + (who.version.empty() ? "" : " " + who.version) +
                                 ", pid " + std::to_string(getpid()) + " on " + HostName() + "\n";
        // Who holds it is only for the next opener's message: a failed write is no failure.
        [[maybe_unused]] const bool said =
            ftruncate(fd, 0) == 0 && pwrite(fd, text.data(), text.size(), 0) > 0;
        return std::unique_ptr<FileLock>(new FileLock(path, fd));
      }
      close(fd);
    }
    return Fail(DatabaseErrorCode::kInUse,
                "cannot take the lock " + path + ": other sessions keep replacing it");
  }

  ~FileLock() {
    // Unlinked while still held, so a waiting opener finds the path free or a new file.
    unlink(path_.c_str());
    close(fd_);
  }

 private:
  FileLock(std::string path, int fd) : path_(std::move(path)), fd_(fd) {}
  std::string path_;
  int fd_;
};

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

const char* TypeName(object::ObjectType type) {
  return type == object::OBJECT_TYPE_CYLINDER ? "cylinder" : "box";
}

// Vec3 fields are three columns: center -> center_x, center_y, center_z.
void BindVec(Statement& s, const std::string& name, const object::Vec3& v) {
  s.Bind((":" + name + "_x").c_str(), v.x());
  s.Bind((":" + name + "_y").c_str(), v.y());
  s.Bind((":" + name + "_z").c_str(), v.z());
}

void BindOptionalVec(Statement& s, const std::string& name, bool present, const object::Vec3& v) {
  if (present) return BindVec(s, name, v);
  for (const char* axis : {"_x", "_y", "_z"}) s.BindNull((":" + name + axis).c_str());
}

object::Vec3 ReadVec(const Statement& s, const std::string& name) {
  object::Vec3 v;
  v.set_x(s.Real(name + "_x"));
  v.set_y(s.Real(name + "_y"));
  v.set_z(s.Real(name + "_z"));
  return v;
}

// "INSERT INTO t (a, b) VALUES (:a, :b)", so the names are written once.
std::string InsertSql(const std::string& table, const std::vector<std::string>& columns) {
  std::string names;
  std::string values;
  for (const auto& column : columns) {
    names += (names.empty() ? "" : ", ") + column;
    values += (values.empty() ? ":" : ", :") + column;
  }
  return "INSERT INTO " + table + " (" + names + ") VALUES (" + values + ")";
}

std::vector<std::string> Columns(std::initializer_list<std::string> plain,
                                 std::initializer_list<std::string> vectors = {}) {
  std::vector<std::string> all(plain);
  for (const auto& v : vectors) {
    for (const char* axis : {"_x", "_y", "_z"}) all.push_back(v + axis);
  }
  return all;
}

const std::string& InsertModelSql() {
  static const std::string sql = InsertSql("models", Columns({"type",
                                                              "present",
                                                              "added_unix_ns",
                                                              "session_id",
                                                              "frame_id",
                                                              "left_capture_unix_ns",
                                                              "right_capture_unix_ns",
                                                              "platform_from_platform",
                                                              "platform_pan_rad",
                                                              "platform_tilt_rad",
                                                              "platform_roll_rad",
                                                              "platform_time_unix_ns",
                                                              "range_sent",
                                                              "range_used",
                                                              "range_constrained",
                                                              "range_measured",
                                                              "range_expected_min",
                                                              "range_expected_max",
                                                              "range_agrees",
                                                              "range_detail",
                                                              "calibration_hash",
                                                              "boundary_pixels",
                                                              "ssd_rms",
                                                              "outline_samples",
                                                              "rms_left_px",
                                                              "rms_right_px",
                                                              "locate_ms",
                                                              "fetch_ms",
                                                              "round_trip_ms"}));
  return sql;
}

const std::string& InsertCylinderSql() {
  static const std::string sql = InsertSql(
      "cylinders", Columns({"model_id", "radius", "height", "radius_sigma", "height_sigma"},
                           {"center", "axis", "center_sigma"}));
  return sql;
}

const std::string& InsertBoxSql() {
  static const std::string sql =
      InsertSql("boxes", Columns({"model_id", "yaw_deg", "yaw_sigma_deg", "texture_u0",
                                  "texture_v0", "texture_u1", "texture_v1", "texture_png"},
                                 {"center", "size", "center_sigma", "size_sigma", "min", "max",
                                  "min_sigma", "max_sigma"}));
  return sql;
}

// BEGIN (deferred) ... COMMIT around reads, so they share one snapshot.
class ReadTransaction {
 public:
  explicit ReadTransaction(Connection& c) : c_(c) { c_.Execute("BEGIN"); }
  ~ReadTransaction() {
    try {
      c_.Execute("COMMIT");
    } catch (const SqliteError&) {
      // Nothing was written; ending a read cannot lose anything.
    }
  }
  ReadTransaction(const ReadTransaction&) = delete;
  ReadTransaction& operator=(const ReadTransaction&) = delete;

 private:
  Connection& c_;
};

ChangeKind KindFromName(const std::string& name) {
  if (name == "add") return ChangeKind::kAdd;
  if (name == "remove") return ChangeKind::kRemove;
  if (name == "undo_add") return ChangeKind::kUndoAdd;
  if (name == "undo_remove") return ChangeKind::kUndoRemove;
  throw SqliteError(SQLITE_CORRUPT, "unknown change kind '" + name + "'");
}

}  // namespace

const char* ChangeKindName(ChangeKind kind) {
  switch (kind) {
    case ChangeKind::kAdd:
      return "add";
    case ChangeKind::kRemove:
      return "remove";
    case ChangeKind::kUndoAdd:
      return "undo_add";
    case ChangeKind::kUndoRemove:
      return "undo_remove";
  }
  return "?";
}

struct GeometricDatabase::Impl {
  Impl(const std::string& path, std::unique_ptr<FileLock> held,
       Connection::Mode mode = Connection::Mode::kReadWriteCreate)
      : lock(std::move(held)), connection(path, mode) {}

  // Prepared once, reused: storing a model is a handful of statements.
  Statement& Prepared(const std::string& sql) {
    auto& slot = statements[sql];
    if (!slot) slot = std::make_unique<Statement>(connection, sql);
    slot->Reset();
    return *slot;
  }

  std::int64_t AppendChange(ChangeKind kind, std::int64_t model_id, std::int64_t session_id,
                            std::optional<std::int64_t> undoes, std::int64_t now) {
    Statement& s = Prepared(
        "INSERT INTO changes (unix_ns, kind, model_id, session_id, undoes) "
        "VALUES (:unix_ns, :kind, :model_id, :session_id, :undoes)");
    s.Bind(":unix_ns", now);
    s.Bind(":kind", std::string_view(ChangeKindName(kind)));
    s.Bind(":model_id", model_id);
    s.Bind(":session_id", session_id);
    s.Bind(":undoes", undoes);
    s.Step();
    const std::int64_t seq = connection.LastInsertId();
    s.Reset();
    return seq;
  }

  StoredModel ReadModel(const Statement& m) {
    StoredModel stored;
    stored.id = m.Int("id");
    stored.present = m.Int("present") != 0;
    stored.added_unix_ns = m.Int("added_unix_ns");
    stored.removed_unix_ns = m.OptionalInt("removed_unix_ns");
    stored.session_id = m.Int("session_id");
    ModelRecord& r = stored.record;
    const std::string type = m.Text("type");
    r.type = type == "cylinder" ? object::OBJECT_TYPE_CYLINDER : object::OBJECT_TYPE_BOX;
    ModelProvenance& p = r.provenance;
    p.frame_id = static_cast<std::uint64_t>(m.Int("frame_id"));
    p.left_capture_unix_ns = m.Int("left_capture_unix_ns");
    p.right_capture_unix_ns = m.Int("right_capture_unix_ns");
    p.platform_pose.set_from_platform(m.Int("platform_from_platform") != 0);
    p.platform_pose.set_time_unix_ns(m.Int("platform_time_unix_ns"));
    if (!m.IsNull("platform_pan_rad")) {
      p.platform_pose.add_joints_rad(m.Real("platform_pan_rad"));
      p.platform_pose.add_joints_rad(m.Real("platform_tilt_rad"));
      p.platform_pose.add_joints_rad(m.Real("platform_roll_rad"));
    }
    p.range = m.Real("range_sent");
    if (!m.IsNull("range_used")) {
      object::RangeReport report;
      report.set_used(m.Int("range_used") != 0);
      report.set_constrained(m.Int("range_constrained") != 0);
      report.set_measured(m.Real("range_measured"));
      report.set_expected_min(m.Real("range_expected_min"));
      report.set_expected_max(m.Real("range_expected_max"));
      report.set_agrees(m.Int("range_agrees") != 0);
      report.set_detail(m.Text("range_detail"));
      p.range_report = report;
    }
    p.calibration_hash = m.Text("calibration_hash");
    p.boundary_pixels = static_cast<std::int32_t>(m.Int("boundary_pixels"));
    p.ssd_rms = m.Real("ssd_rms");
    p.outline_samples = static_cast<std::int32_t>(m.Int("outline_samples"));
    p.rms_left_px = m.Real("rms_left_px");
    p.rms_right_px = m.Real("rms_right_px");
    p.locate_ms = m.Real("locate_ms");
    p.fetch_ms = m.Real("fetch_ms");
    p.round_trip_ms = m.Real("round_trip_ms");

    if (r.type == object::OBJECT_TYPE_CYLINDER) {
      Statement& c = Prepared("SELECT * FROM cylinders WHERE model_id = :id");
      c.Bind(":id", stored.id);
      if (!c.Step()) {
        throw SqliteError(SQLITE_CORRUPT,
                          "model " + std::to_string(stored.id) + " has no cylinder");
      }
      auto& cyl = r.cylinder;
      *cyl.mutable_center() = ReadVec(c, "center");
      *cyl.mutable_axis() = ReadVec(c, "axis");
      cyl.set_radius(c.Real("radius"));
      cyl.set_height(c.Real("height"));
      *cyl.mutable_center_sigma() = ReadVec(c, "center_sigma");
      cyl.set_radius_sigma(c.Real("radius_sigma"));
      cyl.set_height_sigma(c.Real("height_sigma"));
      c.Reset();
    } else {
      Statement& b = Prepared("SELECT * FROM boxes WHERE model_id = :id");
      b.Bind(":id", stored.id);
      if (!b.Step()) {
        throw SqliteError(SQLITE_CORRUPT, "model " + std::to_string(stored.id) + " has no box");
      }
      auto& box = r.box;
      *box.mutable_center() = ReadVec(b, "center");
      *box.mutable_size() = ReadVec(b, "size");
      box.set_yaw_deg(b.Real("yaw_deg"));
      *box.mutable_center_sigma() = ReadVec(b, "center_sigma");
      *box.mutable_size_sigma() = ReadVec(b, "size_sigma");
      box.set_yaw_sigma_deg(b.Real("yaw_sigma_deg"));
      for (const char* name : {"min", "max", "min_sigma", "max_sigma"}) {
        if (b.IsNull(std::string(name) + "_x")) continue;
        const object::Vec3 v = ReadVec(b, name);
        const std::string n = name;
        if (n == "min") *box.mutable_min() = v;
        if (n == "max") *box.mutable_max() = v;
        if (n == "min_sigma") *box.mutable_min_sigma() = v;
        if (n == "max_sigma") *box.mutable_max_sigma() = v;
      }
      box.set_texture_u0(static_cast<std::int32_t>(b.Int("texture_u0")));
      box.set_texture_v0(static_cast<std::int32_t>(b.Int("texture_v0")));
      box.set_texture_u1(static_cast<std::int32_t>(b.Int("texture_u1")));
      box.set_texture_v1(static_cast<std::int32_t>(b.Int("texture_v1")));
      box.set_texture_png(b.Blob("texture_png"));
      b.Reset();
    }

    Statement& marks = Prepared("SELECT * FROM marks WHERE model_id = :id ORDER BY mark_index");
    marks.Bind(":id", stored.id);
    while (marks.Step()) {
      object::Vec3 v;
      v.set_x(marks.Real("x"));
      v.set_y(marks.Real("y"));
      v.set_z(marks.Real("z"));
      p.marks.push_back(v);
    }
    marks.Reset();
    Statement& servers = Prepared("SELECT * FROM servers WHERE model_id = :id ORDER BY name");
    servers.Bind(":id", stored.id);
    while (servers.Step()) {
      p.servers.push_back({servers.Text("name"), servers.Text("program"), servers.Text("version")});
    }
    servers.Reset();
    return stored;
  }

  // Destroyed in reverse: the statements, the connection (its last checkpoint), the lock.
  std::unique_ptr<FileLock> lock;
  Connection connection;
  std::map<std::string, std::unique_ptr<Statement>> statements;
};

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

DatabaseResult<std::int64_t> GeometricDatabase::AddModel(const ModelRecord& record) {
  if (auto problem = CheckModelRecord(record)) {
    return Fail(DatabaseErrorCode::kBadInput, "model refused, nothing written: " + *problem);
  }
  try {
    const std::int64_t now = igms::UnixNs();
    const ModelProvenance& p = record.provenance;
    Transaction t(impl_->connection);
    Statement& m = impl_->Prepared(InsertModelSql());
    m.Bind(":type", std::string_view(TypeName(record.type)));
    m.Bind(":present", std::int64_t{1});
    m.Bind(":added_unix_ns", now);
    m.Bind(":session_id", session_id_);
    m.Bind(":frame_id", static_cast<std::int64_t>(p.frame_id));
    m.Bind(":left_capture_unix_ns", p.left_capture_unix_ns);
    m.Bind(":right_capture_unix_ns", p.right_capture_unix_ns);
    m.Bind(":platform_from_platform", std::int64_t{p.platform_pose.from_platform()});
    const auto& joints = p.platform_pose.joints_rad();
    const char* joint_names[] = {":platform_pan_rad", ":platform_tilt_rad", ":platform_roll_rad"};
    for (int i = 0; i < 3; ++i) {
      if (joints.size() == 3)
        m.Bind(joint_names[i], joints[i]);
      else
        m.BindNull(joint_names[i]);
    }
    m.Bind(":platform_time_unix_ns", p.platform_pose.time_unix_ns());
    m.Bind(":range_sent", p.range);
    if (p.range_report) {
      const auto& r = *p.range_report;
      m.Bind(":range_used", std::int64_t{r.used()});
      m.Bind(":range_constrained", std::int64_t{r.constrained()});
      m.Bind(":range_measured", r.measured());
      m.Bind(":range_expected_min", r.expected_min());
      m.Bind(":range_expected_max", r.expected_max());
      m.Bind(":range_agrees", std::int64_t{r.agrees()});
      m.Bind(":range_detail", std::string_view(r.detail()));
    } else {
      for (const char* name :
           {":range_used", ":range_constrained", ":range_measured", ":range_expected_min",
            ":range_expected_max", ":range_agrees", ":range_detail"}) {
        m.BindNull(name);
      }
    }
    m.Bind(":calibration_hash", std::string_view(p.calibration_hash));
    m.Bind(":boundary_pixels", std::int64_t{p.boundary_pixels});
    m.Bind(":ssd_rms", p.ssd_rms);
    m.Bind(":outline_samples", std::int64_t{p.outline_samples});
    m.Bind(":rms_left_px", p.rms_left_px);
    m.Bind(":rms_right_px", p.rms_right_px);
    m.Bind(":locate_ms", p.locate_ms);
    m.Bind(":fetch_ms", p.fetch_ms);
    m.Bind(":round_trip_ms", p.round_trip_ms);
    m.Step();
    const std::int64_t id = impl_->connection.LastInsertId();
    m.Reset();

    if (record.type == object::OBJECT_TYPE_CYLINDER) {
      const auto& c = record.cylinder;
      Statement& s = impl_->Prepared(InsertCylinderSql());
      s.Bind(":model_id", id);
      BindVec(s, "center", c.center());
      BindVec(s, "axis", c.axis());
      s.Bind(":radius", c.radius());
      s.Bind(":height", c.height());
      BindVec(s, "center_sigma", c.center_sigma());
      s.Bind(":radius_sigma", c.radius_sigma());
      s.Bind(":height_sigma", c.height_sigma());
      s.Step();
      s.Reset();
    } else {
      const auto& b = record.box;
      Statement& s = impl_->Prepared(InsertBoxSql());
      s.Bind(":model_id", id);
      BindVec(s, "center", b.center());
      BindVec(s, "size", b.size());
      s.Bind(":yaw_deg", b.yaw_deg());
      BindVec(s, "center_sigma", b.center_sigma());
      BindVec(s, "size_sigma", b.size_sigma());
      s.Bind(":yaw_sigma_deg", b.yaw_sigma_deg());
      BindOptionalVec(s, "min", b.has_min(), b.min());
      BindOptionalVec(s, "max", b.has_max(), b.max());
      BindOptionalVec(s, "min_sigma", b.has_min_sigma(), b.min_sigma());
      BindOptionalVec(s, "max_sigma", b.has_max_sigma(), b.max_sigma());
      s.Bind(":texture_u0", std::int64_t{b.texture_u0()});
      s.Bind(":texture_v0", std::int64_t{b.texture_v0()});
      s.Bind(":texture_u1", std::int64_t{b.texture_u1()});
      s.Bind(":texture_v1", std::int64_t{b.texture_v1()});
      s.BindBlob(":texture_png", b.texture_png());
      s.Step();
      s.Reset();
    }

    Statement& mark = impl_->Prepared(
        "INSERT INTO marks (model_id, mark_index, x, y, z) VALUES (:model_id, :i, :x, :y, :z)");
    for (std::size_t i = 0; i < p.marks.size(); ++i) {
      mark.Reset();
      mark.Bind(":model_id", id);
      mark.Bind(":i", static_cast<std::int64_t>(i));
      mark.Bind(":x", p.marks[i].x());
      mark.Bind(":y", p.marks[i].y());
      mark.Bind(":z", p.marks[i].z());
      mark.Step();
    }
    mark.Reset();
    Statement& server = impl_->Prepared(
        "INSERT INTO servers (model_id, name, program, version) "
        "VALUES (:model_id, :name, :program, :version)");
    for (const auto& v : p.servers) {
      server.Reset();
      server.Bind(":model_id", id);
      server.Bind(":name", std::string_view(v.name));
      server.Bind(":program", std::string_view(v.program));
      server.Bind(":version", std::string_view(v.version));
      server.Step();
    }
    server.Reset();
    impl_->AppendChange(ChangeKind::kAdd, id, session_id_, std::nullopt, now);
    t.Commit();
    return id;
  } catch (const SqliteError& e) {
    return FromSqlite(path_, e);
  }
}

DatabaseResult<Change> GeometricDatabase::RemoveModel(std::int64_t id) {
  try {
    Transaction t(impl_->connection);
    Statement& q = impl_->Prepared("SELECT present FROM models WHERE id = :id");
    q.Bind(":id", id);
    if (!q.Step()) {
      return Fail(DatabaseErrorCode::kNoSuchModel,
                  "no model " + std::to_string(id) + " in " + path_);
    }
    const bool present = q.Int("present") != 0;
    q.Reset();
    if (!present) {
      return Fail(DatabaseErrorCode::kAlreadyRemoved,
                  "model " + std::to_string(id) + " is already removed");
    }
    const std::int64_t now = igms::UnixNs();
    Statement& u =
        impl_->Prepared("UPDATE models SET present = 0, removed_unix_ns = :now WHERE id = :id");
    u.Bind(":now", now);
    u.Bind(":id", id);
    u.Step();
    u.Reset();
    Change change{0, now, ChangeKind::kRemove, id, session_id_, std::nullopt};
    change.seq = impl_->AppendChange(change.kind, id, session_id_, std::nullopt, now);
    t.Commit();
    return change;
  } catch (const SqliteError& e) {
    return FromSqlite(path_, e);
  }
}

DatabaseResult<Change> GeometricDatabase::Undo() {
  try {
    Transaction t(impl_->connection);
    // The stack of undoable changes: adds and removals not undone yet, newest on top.
    Statement& q = impl_->Prepared(
        "SELECT seq, kind, model_id FROM changes AS c WHERE kind IN ('add', 'remove') "
        "AND NOT EXISTS (SELECT 1 FROM changes AS u WHERE u.undoes = c.seq) "
        "ORDER BY seq DESC LIMIT 1");
    if (!q.Step()) {
      return Fail(DatabaseErrorCode::kNothingToUndo,
                  "nothing to undo: no model added or removed that is not undone already");
    }
    const std::int64_t undone = q.Int("seq");
    const ChangeKind undone_kind = KindFromName(q.Text("kind"));
    const std::int64_t model = q.Int("model_id");
    q.Reset();
    const std::int64_t now = igms::UnixNs();
    Change change{0,
                  now,
                  undone_kind == ChangeKind::kAdd ? ChangeKind::kUndoAdd : ChangeKind::kUndoRemove,
                  model,
                  session_id_,
                  undone};
    Statement& u = impl_->Prepared(
        "UPDATE models SET present = :present, removed_unix_ns = :removed WHERE id = :id");
    u.Bind(":present", std::int64_t{change.kind == ChangeKind::kUndoRemove});
    u.Bind(":removed",
           change.kind == ChangeKind::kUndoAdd ? std::optional<std::int64_t>(now) : std::nullopt);
    u.Bind(":id", model);
    u.Step();
    u.Reset();
    change.seq = impl_->AppendChange(change.kind, model, session_id_, undone, now);
    t.Commit();
    return change;
  } catch (const SqliteError& e) {
    return FromSqlite(path_, e);
  }
}

DatabaseResult<std::vector<StoredModel>> GeometricDatabase::ListModels() {
  try {
    std::vector<StoredModel> models;
    std::vector<std::int64_t> ids;
    // One read transaction: a reader sees one committed state even while a session writes.
    ReadTransaction snapshot(impl_->connection);
    Statement& q = impl_->Prepared("SELECT id FROM models WHERE present = 1 ORDER BY id");
    while (q.Step()) ids.push_back(q.Int("id"));
    q.Reset();
    for (const std::int64_t id : ids) {
      Statement& m = impl_->Prepared("SELECT * FROM models WHERE id = :id");
      m.Bind(":id", id);
      if (!m.Step()) continue;
      StoredModel stored = impl_->ReadModel(m);
      m.Reset();
      models.push_back(std::move(stored));
    }
    return models;
  } catch (const SqliteError& e) {
    return FromSqlite(path_, e);
  }
}

DatabaseResult<StoredModel> GeometricDatabase::GetModel(std::int64_t id) {
  try {
    Statement& m = impl_->Prepared("SELECT * FROM models WHERE id = :id");
    m.Bind(":id", id);
    if (!m.Step()) {
      return Fail(DatabaseErrorCode::kNoSuchModel,
                  "no model " + std::to_string(id) + " in " + path_);
    }
    StoredModel stored = impl_->ReadModel(m);
    m.Reset();
    return stored;
  } catch (const SqliteError& e) {
    return FromSqlite(path_, e);
  }
}

DatabaseResult<std::vector<Change>> GeometricDatabase::History() {
  try {
    std::vector<Change> changes;
    Statement& q = impl_->Prepared("SELECT * FROM changes ORDER BY seq");
    while (q.Step()) {
      changes.push_back({q.Int("seq"), q.Int("unix_ns"), KindFromName(q.Text("kind")),
                         q.Int("model_id"), q.Int("session_id"), q.OptionalInt("undoes")});
    }
    q.Reset();
    return changes;
  } catch (const SqliteError& e) {
    return FromSqlite(path_, e);
  }
}

DatabaseResult<std::vector<DatabaseSession>> GeometricDatabase::Sessions() {
  try {
    std::vector<DatabaseSession> sessions;
    Statement& q = impl_->Prepared("SELECT * FROM sessions ORDER BY id");
    while (q.Step()) {
      sessions.push_back({q.Int("id"), q.Int("opened_unix_ns"), q.OptionalInt("closed_unix_ns"),
                          q.Text("program"), q.Text("version"), q.Text("host"), q.Int("pid")});
    }
    q.Reset();
    return sessions;
  } catch (const SqliteError& e) {
    return FromSqlite(path_, e);
  }
}

}  // namespace igms::control
