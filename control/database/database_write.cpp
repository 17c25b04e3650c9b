// Changing the geometric database: adding a model with its provenance, removing one, undoing
// the last add or removal. Each is one transaction with its row in the history.
#include <sqlite3.h>

#include <initializer_list>
#include <vector>

#include "common/base/clock.h"
#include "control/database/database_internal.h"
#include "control/database/geometric_database.h"
#include "control/database/sqlite.h"

namespace igms::control {

using database_detail::Fail;
using database_detail::FromSqlite;
using database_detail::KindFromName;
using sqlite::SqliteError;
using sqlite::Statement;
using sqlite::Transaction;

namespace {

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

std::int64_t GeometricDatabase::Impl::AppendChange(ChangeKind kind, std::int64_t model_id,
                                                   std::int64_t session_id,
                                                   std::optional<std::int64_t> undoes,
                                                   std::int64_t now) {
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

}  // namespace igms::control
