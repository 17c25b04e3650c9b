// The geometric database in one process, on real files: models stored and read back whole,
// removal as a mark, undo and history, a session continued, bad input refused before
// anything is written, and one writer at a time.
#include <google/protobuf/util/message_differencer.h>
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "control/database/geometric_database.h"
#include "tests/control/database/sample_records.h"
#include "tests/support/child_process.h"

namespace igms::control {
namespace {

using google::protobuf::util::MessageDifferencer;
using testing::SampleBox;
using testing::SampleCylinder;
using testing::V;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::unique_ptr<GeometricDatabase> OpenOrFail(const std::string& path) {
  auto db = GeometricDatabase::Open(path, {"database_test", "1"});
  EXPECT_TRUE(db.ok()) << db.error();
  return db.ok() ? std::move(*db) : nullptr;
}

// Rows of every table, read through a connection of its own, as a reader would see them.
std::int64_t RowsOf(const std::string& path) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  std::int64_t total = 0;
  for (const char* table : {"models", "cylinders", "boxes", "marks", "servers", "changes"}) {
    sqlite3_stmt* s = nullptr;
    const std::string sql = std::string("SELECT count(*) FROM ") + table;
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &s, nullptr) == SQLITE_OK &&
        sqlite3_step(s) == SQLITE_ROW) {
      total += sqlite3_column_int64(s, 0);
    } else {
      total = -1000000;
    }
    sqlite3_finalize(s);
  }
  sqlite3_close(db);
  return total;
}

void ExpectSameProvenance(const ModelProvenance& a, const ModelProvenance& b) {
  EXPECT_EQ(a.frame_id, b.frame_id);
  EXPECT_EQ(a.left_capture_unix_ns, b.left_capture_unix_ns);
  EXPECT_EQ(a.right_capture_unix_ns, b.right_capture_unix_ns);
  EXPECT_TRUE(MessageDifferencer::Equals(a.platform_pose, b.platform_pose))
      << a.platform_pose.DebugString() << " vs " << b.platform_pose.DebugString();
  ASSERT_EQ(a.marks.size(), b.marks.size());
  for (std::size_t i = 0; i < a.marks.size(); ++i) {
    EXPECT_TRUE(MessageDifferencer::Equals(a.marks[i], b.marks[i])) << "mark " << i;
  }
  EXPECT_EQ(a.range, b.range);
  ASSERT_EQ(a.range_report.has_value(), b.range_report.has_value());
  if (a.range_report) {
    EXPECT_TRUE(MessageDifferencer::Equals(*a.range_report, *b.range_report));
  }
  EXPECT_EQ(a.calibration_hash, b.calibration_hash);
  EXPECT_EQ(a.boundary_pixels, b.boundary_pixels);
  EXPECT_EQ(a.ssd_rms, b.ssd_rms);
  EXPECT_EQ(a.outline_samples, b.outline_samples);
  EXPECT_EQ(a.rms_left_px, b.rms_left_px);
  EXPECT_EQ(a.rms_right_px, b.rms_right_px);
  EXPECT_EQ(a.locate_ms, b.locate_ms);
  EXPECT_EQ(a.fetch_ms, b.fetch_ms);
  EXPECT_EQ(a.round_trip_ms, b.round_trip_ms);
  ASSERT_EQ(a.servers.size(), b.servers.size());
  for (const auto& server : a.servers) {
    bool found = false;
    for (const auto& other : b.servers) {
      if (other.name == server.name) {
        found = true;
        EXPECT_EQ(other.program, server.program);
        EXPECT_EQ(other.version, server.version);
      }
    }
    EXPECT_TRUE(found) << server.name;
  }
}

TEST(GeometricDatabase, StoresCylindersAndBoxesWithTheirProvenanceWhole) {
  igms::testing::ScratchDir dir;
  auto db = OpenOrFail(dir.File("models.db"));
  ASSERT_TRUE(db);
  const ModelRecord cylinder = SampleCylinder(11);
  const ModelRecord box = SampleBox(12, 20000);  // a texture over several pages
  auto c = db->AddModel(cylinder);
  auto b = db->AddModel(box);
  ASSERT_TRUE(c.ok()) << c.error();
  ASSERT_TRUE(b.ok()) << b.error();
  EXPECT_NE(*c, *b);

  auto got_c = db->GetModel(*c);
  ASSERT_TRUE(got_c.ok()) << got_c.error();
  EXPECT_EQ(got_c->record.type, object::OBJECT_TYPE_CYLINDER);
  EXPECT_TRUE(MessageDifferencer::Equals(got_c->record.cylinder, cylinder.cylinder))
      << got_c->record.cylinder.DebugString();
  ExpectSameProvenance(got_c->record.provenance, cylinder.provenance);
  EXPECT_TRUE(got_c->present);
  EXPECT_EQ(got_c->session_id, db->session_id());
  EXPECT_GT(got_c->added_unix_ns, 0);

  auto got_b = db->GetModel(*b);
  ASSERT_TRUE(got_b.ok()) << got_b.error();
  EXPECT_EQ(got_b->record.type, object::OBJECT_TYPE_BOX);
  EXPECT_TRUE(MessageDifferencer::Equals(got_b->record.box, box.box));
  EXPECT_EQ(got_b->record.box.texture_png(), box.box.texture_png());
  ExpectSameProvenance(got_b->record.provenance, box.provenance);

  auto list = db->ListModels();
  ASSERT_TRUE(list.ok()) << list.error();
  ASSERT_EQ(list->size(), 2u);
  EXPECT_EQ((*list)[0].id, *c);
  EXPECT_EQ((*list)[1].id, *b);
}

TEST(GeometricDatabase, MakeModelRecordTakesTheGrabTheRequestAndTheAnswer) {
  video::GrabResponse grab;
  grab.set_frame_id(41);
  grab.set_left_capture_unix_ns(1000);
  grab.set_right_capture_unix_ns(1001);
  grab.mutable_pose()->add_joints_rad(0.5);
  grab.mutable_pose()->add_joints_rad(0.25);
  grab.mutable_pose()->add_joints_rad(0);
  grab.mutable_pose()->set_from_platform(true);
  object::LocateRequest request;
  request.set_type(object::OBJECT_TYPE_CYLINDER);
  for (int i = 0; i < 4; ++i) *request.add_marks() = V(i, 0, 1);
  request.set_frame_id(41);
  request.set_range(1.5);
  object::LocateResponse found;
  found.set_found(true);
  found.set_type(object::OBJECT_TYPE_CYLINDER);
  *found.mutable_cylinder() = SampleCylinder().cylinder;
  found.set_boundary_pixels(300);
  found.set_locate_ms(3.5);
  found.set_fetch_ms(0.5);
  found.mutable_range()->set_used(true);
  found.mutable_range()->set_measured(1.5);

  const ModelRecord r = MakeModelRecord(grab, request, found, "hash", {{"video", "v", "1"}}, 9);
  EXPECT_FALSE(CheckModelRecord(r).has_value()) << *CheckModelRecord(r);
  EXPECT_EQ(r.provenance.frame_id, 41u);
  EXPECT_EQ(r.provenance.marks.size(), 4u);
  EXPECT_EQ(r.provenance.range, 1.5);
  ASSERT_TRUE(r.provenance.range_report.has_value());
  EXPECT_EQ(r.provenance.range_report->measured(), 1.5);
  EXPECT_EQ(r.provenance.platform_pose.joints_rad_size(), 3);
  EXPECT_EQ(r.provenance.locate_ms, 3.5);
  EXPECT_EQ(r.provenance.round_trip_ms, 9);
  EXPECT_EQ(r.provenance.calibration_hash, "hash");
}

TEST(GeometricDatabase, BadInputIsRefusedBeforeAnythingIsWritten) {
  igms::testing::ScratchDir dir;
  const std::string path = dir.File("models.db");
  auto db = OpenOrFail(path);
  ASSERT_TRUE(db);
  auto first = db->AddModel(SampleCylinder());
  ASSERT_TRUE(first.ok()) << first.error();
  const std::int64_t rows = RowsOf(path);
  ASSERT_GT(rows, 0);

  struct Case {
    const char* expected;  // what the message must name
    ModelRecord record;
  };
  std::vector<Case> cases;
  {
    ModelRecord r = SampleCylinder();
    r.cylinder.mutable_center()->set_y(kNaN);
    cases.push_back({"cylinder.center.y is NaN", r});
  }
  {
    ModelRecord r = SampleCylinder();
    r.cylinder.set_radius(std::numeric_limits<double>::infinity());
    cases.push_back({"cylinder.radius is infinite", r});
  }
  {
    ModelRecord r = SampleCylinder();
    r.cylinder.clear_axis();
    cases.push_back({"cylinder.axis is missing", r});
  }
  {
    ModelRecord r = SampleCylinder();
    *r.cylinder.mutable_axis() = V(0, 0, 2);
    cases.push_back({"cylinder.axis is not a unit vector", r});
  }
  {
    ModelRecord r = SampleBox();
    r.box.mutable_size()->set_z(kNaN);
    cases.push_back({"box.size.z is NaN", r});
  }
  {
    ModelRecord r = SampleBox();
    r.box.mutable_size()->set_x(0);
    cases.push_back({"box.size.x must be positive", r});
  }
  {
    ModelRecord r = SampleBox();
    r.box.clear_center_sigma();
    cases.push_back({"box.center_sigma is missing", r});
  }
  {
    ModelRecord r = SampleBox();
    r.box.set_texture_png("not a png");
    cases.push_back({"box.texture_png is not a PNG file", r});
  }
  {
    ModelRecord r = SampleCylinder();
    r.type = object::OBJECT_TYPE_UNSPECIFIED;
    cases.push_back({"a model is a cylinder or a box", r});
  }
  {
    ModelRecord r = SampleCylinder();
    r.provenance.platform_pose.set_joints_rad(1, kNaN);
    cases.push_back({"provenance.platform_pose.joints_rad[1] is NaN", r});
  }
  {
    ModelRecord r = SampleCylinder();
    r.provenance.marks.pop_back();
    cases.push_back({"provenance.marks has 3 marks, not 4", r});
  }
  {
    ModelRecord r = SampleCylinder();
    r.provenance.marks[2].set_x(kNaN);
    cases.push_back({"provenance.marks[2].x is NaN", r});
  }
  {
    ModelRecord r = SampleCylinder();
    r.provenance.frame_id = 0;
    cases.push_back({"provenance.frame_id is missing", r});
  }
  {
    ModelRecord r = SampleCylinder();
    r.provenance.calibration_hash.clear();
    cases.push_back({"provenance.calibration_hash is missing", r});
  }
  {
    ModelRecord r = SampleCylinder();
    r.provenance.locate_ms = kNaN;
    cases.push_back({"provenance.locate_ms is NaN", r});
  }
  {
    ModelRecord r = SampleCylinder();
    r.provenance.servers.push_back(r.provenance.servers.front());
    cases.push_back({"provenance.servers names video twice", r});
  }
  for (const auto& c : cases) {
    auto id = db->AddModel(c.record);
    ASSERT_FALSE(id.ok()) << c.expected;
    EXPECT_EQ(id.code(), DatabaseErrorCode::kBadInput) << id.error();
    EXPECT_NE(id.error().find(c.expected), std::string::npos)
        << "expected '" << c.expected << "' in: " << id.error();
    EXPECT_NE(id.error().find("nothing written"), std::string::npos) << id.error();
  }
  EXPECT_EQ(RowsOf(path), rows) << "a refused model left rows behind";
  auto history = db->History();
  ASSERT_TRUE(history.ok());
  EXPECT_EQ(history->size(), 1u);
  // No id was taken by the refusals either.
  auto next = db->AddModel(SampleBox());
  ASSERT_TRUE(next.ok()) << next.error();
  EXPECT_EQ(*next, *first + 1);
}

TEST(GeometricDatabase, RemovalIsAMarkAndUndoWalksBackThroughAddsAndRemovals) {
  igms::testing::ScratchDir dir;
  auto db = OpenOrFail(dir.File("models.db"));
  ASSERT_TRUE(db);
  const std::int64_t a = db->AddModel(SampleCylinder(1)).value();
  const std::int64_t b = db->AddModel(SampleBox(2)).value();

  auto removed = db->RemoveModel(a);
  ASSERT_TRUE(removed.ok()) << removed.error();
  EXPECT_EQ(removed->kind, ChangeKind::kRemove);
  EXPECT_EQ(removed->model_id, a);
  auto list = db->ListModels().value();
  ASSERT_EQ(list.size(), 1u);
  EXPECT_EQ(list[0].id, b);
  // Removed is kept: the model is still there to read, marked.
  auto gone = db->GetModel(a);
  ASSERT_TRUE(gone.ok()) << gone.error();
  EXPECT_FALSE(gone->present);
  EXPECT_TRUE(gone->removed_unix_ns.has_value());

  auto again = db->RemoveModel(a);
  EXPECT_EQ(again.code(), DatabaseErrorCode::kAlreadyRemoved);
  EXPECT_NE(again.error().find("model " + std::to_string(a) + " is already removed"),
            std::string::npos)
      << again.error();
  auto none = db->RemoveModel(999);
  EXPECT_EQ(none.code(), DatabaseErrorCode::kNoSuchModel);
  EXPECT_NE(none.error().find("no model 999"), std::string::npos) << none.error();
  EXPECT_EQ(db->GetModel(999).code(), DatabaseErrorCode::kNoSuchModel);

  // Undo the removal of a: both present.
  auto u1 = db->Undo();
  ASSERT_TRUE(u1.ok()) << u1.error();
  EXPECT_EQ(u1->kind, ChangeKind::kUndoRemove);
  EXPECT_EQ(u1->model_id, a);
  EXPECT_EQ(db->ListModels()->size(), 2u);
  EXPECT_TRUE(db->GetModel(a)->present);
  EXPECT_FALSE(db->GetModel(a)->removed_unix_ns.has_value());
  // Undo the add of b, then the add of a.
  auto u2 = db->Undo();
  ASSERT_TRUE(u2.ok()) << u2.error();
  EXPECT_EQ(u2->kind, ChangeKind::kUndoAdd);
  EXPECT_EQ(u2->model_id, b);
  auto u3 = db->Undo();
  ASSERT_TRUE(u3.ok()) << u3.error();
  EXPECT_EQ(u3->kind, ChangeKind::kUndoAdd);
  EXPECT_EQ(u3->model_id, a);
  EXPECT_TRUE(db->ListModels()->empty());
  auto u4 = db->Undo();
  EXPECT_EQ(u4.code(), DatabaseErrorCode::kNothingToUndo);
  EXPECT_NE(u4.error().find("nothing to undo"), std::string::npos) << u4.error();
  // An undone model cannot be removed again, and a new add is undoable.
  EXPECT_EQ(db->RemoveModel(b).code(), DatabaseErrorCode::kAlreadyRemoved);
  const std::int64_t c = db->AddModel(SampleCylinder(3)).value();
  EXPECT_GT(c, b);
  auto u5 = db->Undo();
  ASSERT_TRUE(u5.ok());
  EXPECT_EQ(u5->model_id, c);

  auto history = db->History();
  ASSERT_TRUE(history.ok()) << history.error();
  const std::vector<std::pair<ChangeKind, std::int64_t>> expected = {
      {ChangeKind::kAdd, a},        {ChangeKind::kAdd, b},     {ChangeKind::kRemove, a},
      {ChangeKind::kUndoRemove, a}, {ChangeKind::kUndoAdd, b}, {ChangeKind::kUndoAdd, a},
      {ChangeKind::kAdd, c},        {ChangeKind::kUndoAdd, c}};
  ASSERT_EQ(history->size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const Change& change = (*history)[i];
    EXPECT_EQ(change.seq, static_cast<std::int64_t>(i + 1));
    EXPECT_EQ(change.kind, expected[i].first)
        << "change " << i + 1 << " is " << ChangeKindName(change.kind);
    EXPECT_EQ(change.model_id, expected[i].second) << "change " << i + 1;
    EXPECT_EQ(change.session_id, db->session_id());
    EXPECT_GT(change.unix_ns, 0);
  }
  // Each undo names the change it undid.
  EXPECT_EQ((*history)[3].undoes, 3);
  EXPECT_EQ((*history)[4].undoes, 2);
  EXPECT_EQ((*history)[5].undoes, 1);
  EXPECT_EQ((*history)[7].undoes, 7);
  EXPECT_FALSE((*history)[0].undoes.has_value());
}

TEST(GeometricDatabase, OpeningTheFileAgainContinuesTheSession) {
  igms::testing::ScratchDir dir;
  const std::string path = dir.File("session.db");
  std::int64_t a = 0;
  std::int64_t b = 0;
  std::int64_t first_session = 0;
  {
    auto db = OpenOrFail(path);
    ASSERT_TRUE(db);
    first_session = db->session_id();
    a = db->AddModel(SampleCylinder(1)).value();
    b = db->AddModel(SampleBox(2)).value();
    ASSERT_TRUE(db->RemoveModel(a).ok());
  }
  auto db = OpenOrFail(path);
  ASSERT_TRUE(db);
  EXPECT_GT(db->session_id(), first_session);
  auto list = db->ListModels();
  ASSERT_TRUE(list.ok()) << list.error();
  ASSERT_EQ(list->size(), 1u);
  EXPECT_EQ((*list)[0].id, b);
  EXPECT_EQ((*list)[0].session_id, first_session);
  EXPECT_EQ((*list)[0].record.box.texture_png(), SampleBox(2).box.texture_png());
  auto history = db->History();
  ASSERT_TRUE(history.ok());
  ASSERT_EQ(history->size(), 3u);
  EXPECT_EQ((*history)[2].kind, ChangeKind::kRemove);

  auto sessions = db->Sessions();
  ASSERT_TRUE(sessions.ok()) << sessions.error();
  ASSERT_EQ(sessions->size(), 2u);
  EXPECT_EQ((*sessions)[0].id, first_session);
  EXPECT_TRUE((*sessions)[0].closed_unix_ns.has_value());
  EXPECT_FALSE((*sessions)[1].closed_unix_ns.has_value());
  EXPECT_EQ((*sessions)[1].program, "database_test");
  EXPECT_EQ((*sessions)[1].pid, getpid());

  // Undo reaches into the earlier session: the removal of a.
  auto undo = db->Undo();
  ASSERT_TRUE(undo.ok()) << undo.error();
  EXPECT_EQ(undo->kind, ChangeKind::kUndoRemove);
  EXPECT_EQ(undo->model_id, a);
  EXPECT_EQ(undo->session_id, db->session_id());
  EXPECT_EQ(db->ListModels()->size(), 2u);
  const std::int64_t c = db->AddModel(SampleCylinder(3)).value();
  EXPECT_GT(c, b);
}

TEST(GeometricDatabase, ASecondOpenOfTheSameFileIsRefusedWhileTheFirstHoldsIt) {
  igms::testing::ScratchDir dir;
  const std::string path = dir.File("one-operator.db");
  {
    auto first = OpenOrFail(path);
    ASSERT_TRUE(first);
    // The same file by another name is the same database.
    auto second = GeometricDatabase::Open(dir.File("./x/../one-operator.db"));
    ASSERT_FALSE(second.ok());
    EXPECT_EQ(second.code(), DatabaseErrorCode::kInUse);
    EXPECT_NE(second.error().find("is in use by another session"), std::string::npos)
        << second.error();
    EXPECT_NE(second.error().find("pid " + std::to_string(getpid())), std::string::npos)
        << second.error();
    // The holder goes on writing.
    EXPECT_TRUE(first->AddModel(SampleCylinder()).ok());
  }
  EXPECT_FALSE(std::filesystem::exists(path + ".lock"));
  auto again = GeometricDatabase::Open(path);
  ASSERT_TRUE(again.ok()) << again.error();
  EXPECT_EQ((*again)->ListModels()->size(), 1u);
}

TEST(GeometricDatabase, AReaderOpensReadOnlyBesideTheSessionAndSeesItsCommits) {
  igms::testing::ScratchDir dir;
  const std::string path = dir.File("shared.db");
  // Nothing to read: refused, and no file made.
  auto none = GeometricDatabase::OpenReadOnly(path);
  ASSERT_FALSE(none.ok());
  EXPECT_NE(none.error().find("no database at"), std::string::npos) << none.error();
  EXPECT_FALSE(std::filesystem::exists(path));

  auto writer = OpenOrFail(path);
  ASSERT_TRUE(writer);
  ASSERT_TRUE(writer->AddModel(SampleCylinder()).ok());
  auto reader = GeometricDatabase::OpenReadOnly(path);
  ASSERT_TRUE(reader.ok()) << reader.error();
  EXPECT_TRUE((*reader)->read_only());
  EXPECT_EQ((*reader)->ListModels()->size(), 1u);
  const std::int64_t before = *(*reader)->DataVersion();
  EXPECT_EQ(*(*reader)->DataVersion(), before);  // nothing committed since
  // The writer goes on, and the reader sees it commit.
  ASSERT_TRUE(writer->AddModel(SampleBox()).ok());
  EXPECT_NE(*(*reader)->DataVersion(), before);
  EXPECT_EQ((*reader)->ListModels()->size(), 2u);
  // A reader writes nothing: no session of its own, and a change is refused.
  EXPECT_FALSE((*reader)->AddModel(SampleCylinder()).ok());
  EXPECT_EQ((*reader)->Sessions()->size(), 1u);
  reader->reset();
  EXPECT_EQ(writer->Sessions()->size(), 1u);
}

TEST(GeometricDatabase, ANewFileIsMadeWithItsFolderInWriteAheadLogMode) {
  igms::testing::ScratchDir dir;
  const std::string path = dir.File("a/b/new.db");
  {
    auto db = OpenOrFail(path);
    ASSERT_TRUE(db);
    EXPECT_EQ(db->path(), path);
    EXPECT_TRUE(std::filesystem::exists(path + ".lock"));
  }
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  auto query = [&](const char* sql) {
    sqlite3_stmt* s = nullptr;
    std::string answer;
    if (sqlite3_prepare_v2(raw, sql, -1, &s, nullptr) == SQLITE_OK && sqlite3_step(s) == SQLITE_ROW)
      answer = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
    sqlite3_finalize(s);
    return answer;
  };
  EXPECT_EQ(query("PRAGMA journal_mode"), "wal");
  EXPECT_EQ(query("PRAGMA application_id"), std::to_string(GeometricDatabase::kApplicationId));
  EXPECT_EQ(query("PRAGMA user_version"), std::to_string(GeometricDatabase::kSchemaVersion));
  sqlite3_close(raw);
}

}  // namespace
}  // namespace igms::control
