// The geometric database (Cooke, *Interactive Graphical Model Building using Virtual Reality*
// (1993), sections 2.3 and 2.4): the models the operator has built, each with where it came
// from, in one SQLite file that outlives the session. Schema and guarantees: docs/database.md.
//
//   auto db = GeometricDatabase::Open(ResolveDatabasePath(...).value(), {"igms-control", "0.1"});
//   if (!db.ok()) { log(db.error()); return 1; }
//   auto id = (*db)->AddModel(MakeModelRecord(grab, request, response, hash, servers));
//
// - Every change is one transaction, committed (WAL, synchronous=FULL) before the call
//   returns: an id returned is on disk, whatever happens to the process next.
// - Removing marks a model removed; nothing is ever deleted, so undo and history stay, across
//   sessions: opening an existing file continues it.
// - One writer: the file is locked while open; a second Open, from this process or another,
//   is refused. Readers (a robot's planner, sqlite3) may read it at any time.
// - A file that is not an SQLite database, is damaged, or holds another schema or a newer
//   version of this one is refused with a message, and left as it was.
// - Bad input (NaN, a missing field) is refused before anything is written.
//
// One thread uses a GeometricDatabase at a time.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/base/result.h"
#include "igms/object.pb.h"
#include "igms/video.pb.h"

namespace igms::control {

// Why a database call failed; message() says it for a person.
enum class DatabaseErrorCode {
  kInUse,          // another session holds the file
  kNotDatabase,    // not an SQLite file
  kDamaged,        // an SQLite file that fails its integrity check
  kForeignSchema,  // an SQLite file of some other application
  kNewerSchema,    // a newer schema version than this program knows
  kBadInput,       // a model or provenance refused before anything was written
  kNoSuchModel,
  kAlreadyRemoved,
  kNothingToUndo,
  kStorage,  // the file could not be read or written (disk full, I/O error, folder)
};

struct DatabaseError {
  DatabaseErrorCode code;
  std::string message;
};

// igms::Result with the code that callers and tests switch on (a second writer refused as
// kInUse, ...).
template <class T>
class [[nodiscard]] DatabaseResult : public Result<T> {
 public:
  DatabaseResult(T value) : Result<T>(std::move(value)) {}
  DatabaseResult(DatabaseError error)
      : Result<T>(ErrorMessage{std::move(error.message)}), code_(error.code) {}
  // Meaningful only when !ok().
  DatabaseErrorCode code() const { return code_; }

 private:
  DatabaseErrorCode code_ = DatabaseErrorCode::kStorage;
};

// A server the model came through, as its Ping and --version give it.
struct ServerVersion {
  std::string name;     // its entry in the lab file: "video", "object"
  std::string program;  // "igms-video-server"
  std::string version;  // may be empty when the server does not report one
};

// Where a model came from.
struct ModelProvenance {
  // The grab (video.GrabResponse): its frame, when each side was captured, and the camera
  // platform's pose then. joints_rad is empty or (pan, tilt, roll).
  std::uint64_t frame_id = 0;
  std::int64_t left_capture_unix_ns = 0;
  std::int64_t right_capture_unix_ns = 0;
  video::PlatformPose platform_pose;
  // The operator's four marks (world units), the ultrasonic range sent (0 when none), and
  // the object server's report on it (present when a range was sent).
  std::vector<object::Vec3> marks;
  double range = 0;
  std::optional<object::RangeReport> range_report;
  // The calibration's hash (its SHA-256 in hex) the peers agreed on.
  std::string calibration_hash;
  // The locator's residuals and timings (object.LocateResponse), and the client's round trip
  // of the Locate call (0 when not measured).
  std::int32_t boundary_pixels = 0;
  double ssd_rms = 0;
  std::int32_t outline_samples = 0;
  double rms_left_px = 0;
  double rms_right_px = 0;
  double locate_ms = 0;
  double fetch_ms = 0;
  double round_trip_ms = 0;
  // The lab's servers at the time, one per name.
  std::vector<ServerVersion> servers;
};

// A model to add: a cylinder or a box (object.proto's values), and its provenance.
struct ModelRecord {
  object::ObjectType type = object::OBJECT_TYPE_UNSPECIFIED;
  object::CylinderModel cylinder;  // when type is OBJECT_TYPE_CYLINDER
  object::BoxModel box;            // when type is OBJECT_TYPE_BOX; texture_png is the texture
  ModelProvenance provenance;
};

// A found Locate, its request and grab, as one record: what the session stores.
ModelRecord MakeModelRecord(const video::GrabResponse& grab, const object::LocateRequest& request,
                            const object::LocateResponse& found, std::string calibration_hash,
                            std::vector<ServerVersion> servers, double round_trip_ms = 0);

// Why a record cannot be stored ("cylinder.center.y is NaN"), or nullopt when it can.
std::optional<std::string> CheckModelRecord(const ModelRecord& record);

struct StoredModel {
  std::int64_t id = 0;
  ModelRecord record;
  bool present = true;  // false once removed (and not restored by an undo)
  std::int64_t added_unix_ns = 0;
  std::optional<std::int64_t> removed_unix_ns;  // the latest removal while not present
  std::int64_t session_id = 0;                  // the session that added it
};

enum class ChangeKind { kAdd, kRemove, kUndoAdd, kUndoRemove };
const char* ChangeKindName(ChangeKind kind);  // "add", "remove", "undo_add", "undo_remove"

// One line of the history: every change ever made, in order.
struct Change {
  std::int64_t seq = 0;  // its place in the history, from 1
  std::int64_t unix_ns = 0;
  ChangeKind kind = ChangeKind::kAdd;
  std::int64_t model_id = 0;
  std::int64_t session_id = 0;
  std::optional<std::int64_t> undoes;  // for an undo: the seq of the change it undid
};

// Who opens the database, recorded with each session.
struct SessionInfo {
  std::string program = "igms-control";
  std::string version;
};

struct DatabaseSession {
  std::int64_t id = 0;
  std::int64_t opened_unix_ns = 0;
  std::optional<std::int64_t> closed_unix_ns;  // none: still open, or the process died
  std::string program;
  std::string version;
  std::string host;
  std::int64_t pid = 0;
};

class GeometricDatabase {
 public:
  // The schema this program writes: PRAGMA application_id and user_version of the file.
  static constexpr std::int32_t kApplicationId = 0x49474D53;  // "IGMS"
  static constexpr std::int32_t kSchemaVersion = 1;

  // Opens `path`, creating it (and its folder) when missing, or continuing the session it
  // holds. Refuses (kInUse, kNotDatabase, kDamaged, kForeignSchema, kNewerSchema) without
  // changing the file.
  static DatabaseResult<std::unique_ptr<GeometricDatabase>> Open(const std::string& path,
                                                                 const SessionInfo& who = {});
  // Opens an existing `path` to read only (exports, planners, the truth table): no lock, no
  // session recorded, nothing written, so it never stands in the operator's way; it reads
  // the committed state while a session writes. Refuses a missing file (kStorage) and the
  // files Open refuses, with the same codes.
  static DatabaseResult<std::unique_ptr<GeometricDatabase>> OpenReadOnly(const std::string& path);
  ~GeometricDatabase();  // records the session's end and releases the lock
  GeometricDatabase(const GeometricDatabase&) = delete;
  GeometricDatabase& operator=(const GeometricDatabase&) = delete;

  // Stores the model; its id once committed. kBadInput (nothing written) names the field.
  DatabaseResult<std::int64_t> AddModel(const ModelRecord& record);
  // Marks a present model removed.
  DatabaseResult<Change> RemoveModel(std::int64_t id);
  // Undoes the latest add or remove not yet undone (this session's or an earlier one's): an
  // add is taken back (the model marked removed), a removal restored. kNothingToUndo when
  // every change is undone.
  DatabaseResult<Change> Undo();

  // The models present now, by id.
  DatabaseResult<std::vector<StoredModel>> ListModels();
  // Any model ever added, present or not.
  DatabaseResult<StoredModel> GetModel(std::int64_t id);
  // Every change, oldest first.
  DatabaseResult<std::vector<Change>> History();
  // Every session that opened the file, oldest first (this one last).
  DatabaseResult<std::vector<DatabaseSession>> Sessions();

  // SQLite's PRAGMA data_version: it changes whenever another connection commits, so a
  // reader polls it to learn that the models may have changed.
  DatabaseResult<std::int64_t> DataVersion();

  const std::string& path() const { return path_; }
  std::int64_t session_id() const { return session_id_; }  // 0 when read-only
  bool read_only() const { return session_id_ == 0; }

  struct Impl;

 private:
  GeometricDatabase(std::string path, std::unique_ptr<Impl> impl, std::int64_t session_id);

  std::string path_;
  std::unique_ptr<Impl> impl_;
  std::int64_t session_id_ = 0;
};

}  // namespace igms::control
