// The models as the exports draw them: each a cylinder or a box with its pose in the output
// frame and its dimensions in the output units, padded; and their triangle meshes. Every
// writer (export_formats.cpp) starts from these, so the formats agree with each other.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "common/base/result.h"
#include "control/export/export.h"

namespace igms::control::exporting {

struct Solid {
  const StoredModel* model = nullptr;  // the source: id, sigmas, provenance, texture
  std::string name;                    // "model_12"
  bool cylinder = false;
  // The solid's own frame in the output frame: a cylinder's axis is its z, its centre the
  // origin; a box's edges are along its axes, its centre the origin.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  double radius = 0, height = 0;                   // cylinder, output units, padded
  Eigen::Vector3d size = Eigen::Vector3d::Zero();  // box, output units, padded
  int sides = 0;                                   // cylinder: the tessellation's
  bool textured = false;                           // a box with a PNG texture
};

// Checks every model, then converts. `padding` and units from the options.
Result<std::vector<Solid>> MakeSolids(const std::vector<StoredModel>& models,
                                      const ExportOptions& options);

// The tessellation tolerance in output units, and the sides a cylinder of `radius` (output
// units) needs to stay within it: vertices on the circle, so the largest distance is the
// sagitta r (1 - cos(pi / n)).
double ToleranceOut(const ExportOptions& options);
int CylinderSides(double radius, double tolerance);

struct Mesh {
  std::vector<Eigen::Vector3f> positions;  // in the solid's frame
  std::vector<Eigen::Vector3f> normals;    // unit, per vertex
  std::vector<Eigen::Vector2f> uvs;        // glTF's convention: (0, 0) the image's top left
  std::vector<std::uint32_t> indices;      // triangles, counter-clockwise seen from outside
};

Mesh MeshOf(const Solid& solid);

// Roll, pitch, yaw of a rotation as URDF's rpy (R = Rz(yaw) Ry(pitch) Rx(roll)).
Eigen::Vector3d RollPitchYaw(const Eigen::Matrix3d& r);

// A finite double as the shortest text that reads back within 1e-10 relative.
std::string Num(double value);

}  // namespace igms::control::exporting
