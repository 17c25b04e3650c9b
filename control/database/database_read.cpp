// Reading the geometric database: the models present, one model with its shape, marks and
// servers, the history of changes, and the sessions that wrote them.
#include <sqlite3.h>

#include "control/database/database_internal.h"
#include "control/database/geometric_database.h"
#include "control/database/sqlite.h"

namespace igms::control {

using database_detail::Fail;
using database_detail::FromSqlite;
using database_detail::KindFromName;
using sqlite::Connection;
using sqlite::SqliteError;
using sqlite::Statement;

namespace database_detail {

ChangeKind KindFromName(const std::string& name) {
  if (name == "add") return ChangeKind::kAdd;
  if (name == "remove") return ChangeKind::kRemove;
  if (name == "undo_add") return ChangeKind::kUndoAdd;
  if (name == "undo_remove") return ChangeKind::kUndoRemove;
  throw SqliteError(SQLITE_CORRUPT, "unknown change kind '" + name + "'");
}

}  // namespace database_detail

namespace {

object::Vec3 ReadVec(const Statement& s, const std::string& name) {
  object::Vec3 v;
  v.set_x(s.Real(name + "_x"));
  v.set_y(s.Real(name + "_y"));
  v.set_z(s.Real(name + "_z"));
  return v;
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

}  // namespace

StoredModel GeometricDatabase::Impl::ReadModel(const Statement& m) {
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
      throw SqliteError(SQLITE_CORRUPT, "model " + std::to_string(stored.id) + " has no cylinder");
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
