// The geometric database's schema, version 1 (docs/database.md describes every column).
// Changing it means a new GeometricDatabase::kSchemaVersion and a migration from the old.
#pragma once

namespace igms::control {

inline constexpr const char* kSchemaSql = R"sql(
CREATE TABLE sessions (
  id INTEGER PRIMARY KEY,
  opened_unix_ns INTEGER NOT NULL,
  closed_unix_ns INTEGER,
  program TEXT NOT NULL,
  version TEXT NOT NULL,
  host TEXT NOT NULL,
  pid INTEGER NOT NULL
);

CREATE TABLE models (
  id INTEGER PRIMARY KEY,
  type TEXT NOT NULL CHECK (type IN ('cylinder', 'box')),
  present INTEGER NOT NULL CHECK (present IN (0, 1)),
  added_unix_ns INTEGER NOT NULL,
  removed_unix_ns INTEGER,
  session_id INTEGER NOT NULL REFERENCES sessions (id),
  frame_id INTEGER NOT NULL,
  left_capture_unix_ns INTEGER NOT NULL,
  right_capture_unix_ns INTEGER NOT NULL,
  platform_from_platform INTEGER NOT NULL,
  platform_pan_rad REAL,
  platform_tilt_rad REAL,
  platform_roll_rad REAL,
  platform_time_unix_ns INTEGER NOT NULL,
  range_sent REAL NOT NULL,
  range_used INTEGER,
  range_constrained INTEGER,
  range_measured REAL,
  range_expected_min REAL,
  range_expected_max REAL,
  range_agrees INTEGER,
  range_detail TEXT,
  calibration_hash TEXT NOT NULL,
  boundary_pixels INTEGER NOT NULL,
  ssd_rms REAL NOT NULL,
  outline_samples INTEGER NOT NULL,
  rms_left_px REAL NOT NULL,
  rms_right_px REAL NOT NULL,
  locate_ms REAL NOT NULL,
  fetch_ms REAL NOT NULL,
  round_trip_ms REAL NOT NULL
);

CREATE TABLE cylinders (
  model_id INTEGER PRIMARY KEY REFERENCES models (id),
  center_x REAL NOT NULL, center_y REAL NOT NULL, center_z REAL NOT NULL,
  axis_x REAL NOT NULL, axis_y REAL NOT NULL, axis_z REAL NOT NULL,
  radius REAL NOT NULL,
  height REAL NOT NULL,
  center_sigma_x REAL NOT NULL, center_sigma_y REAL NOT NULL, center_sigma_z REAL NOT NULL,
  radius_sigma REAL NOT NULL,
  height_sigma REAL NOT NULL
);

CREATE TABLE boxes (
  model_id INTEGER PRIMARY KEY REFERENCES models (id),
  center_x REAL NOT NULL, center_y REAL NOT NULL, center_z REAL NOT NULL,
  size_x REAL NOT NULL, size_y REAL NOT NULL, size_z REAL NOT NULL,
  yaw_deg REAL NOT NULL,
  center_sigma_x REAL NOT NULL, center_sigma_y REAL NOT NULL, center_sigma_z REAL NOT NULL,
  size_sigma_x REAL NOT NULL, size_sigma_y REAL NOT NULL, size_sigma_z REAL NOT NULL,
  yaw_sigma_deg REAL NOT NULL,
  min_x REAL, min_y REAL, min_z REAL,
  max_x REAL, max_y REAL, max_z REAL,
  min_sigma_x REAL, min_sigma_y REAL, min_sigma_z REAL,
  max_sigma_x REAL, max_sigma_y REAL, max_sigma_z REAL,
  texture_u0 INTEGER NOT NULL, texture_v0 INTEGER NOT NULL,
  texture_u1 INTEGER NOT NULL, texture_v1 INTEGER NOT NULL,
  texture_png BLOB NOT NULL
);

CREATE TABLE marks (
  model_id INTEGER NOT NULL REFERENCES models (id),
  mark_index INTEGER NOT NULL,
  x REAL NOT NULL, y REAL NOT NULL, z REAL NOT NULL,
  PRIMARY KEY (model_id, mark_index)
);

CREATE TABLE servers (
  model_id INTEGER NOT NULL REFERENCES models (id),
  name TEXT NOT NULL,
  program TEXT NOT NULL,
  version TEXT NOT NULL,
  PRIMARY KEY (model_id, name)
);

CREATE TABLE changes (
  seq INTEGER PRIMARY KEY,
  unix_ns INTEGER NOT NULL,
  kind TEXT NOT NULL CHECK (kind IN ('add', 'remove', 'undo_add', 'undo_remove')),
  model_id INTEGER NOT NULL REFERENCES models (id),
  session_id INTEGER NOT NULL REFERENCES sessions (id),
  undoes INTEGER REFERENCES changes (seq)
);
CREATE INDEX changes_by_undoes ON changes (undoes);
)sql";

}  // namespace igms::control
