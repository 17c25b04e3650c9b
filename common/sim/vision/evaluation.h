// Locating every object of simulated scenes from generated operator marks, and comparing
// with the ground truth: the accuracy test, the accuracy benchmark and the demo's table
// share this. Needs the site simulator (common/sim); the locator itself never sees it.
#pragma once

#include <string>
#include <vector>

#include "common/sim/scene.h"
#include "object_server/locate.h"

namespace igms::object {

struct ObjectEvaluation {
  std::string scene_name;
  std::string object_name;
  std::string kind;  // cylinder (upright or lying) or box
  bool lying = false;
  double distance = 0;  // from the left camera centre to the object's centre
  // A lying cylinder's axis against the left image's rows, in space: 0 across the view, 90
  // pointing straight at the camera (the rule judges a pipe's length by a fixed figure
  // within 60 degrees, by its sigma beyond).
  double axis_from_rows_deg = 0;
  // The share of its silhouette the cameras see (the lesser of the two; renderer.h's
  // VisibleFractions): under 1 when another object hides part of it or part is out of view.
  double visible = 1;
  LocateResult result;
  // Found, but not this object: a position or a dimension far beyond any target (WrongModel).
  bool wrong = false;
  // Errors, world units (valid when result.found).
  double radius_error = 0, height_error = 0, position_error = 0;
  double axis_error_deg = 0;  // cylinder: axis direction; box: yaw
  // box: |found - true| per axis of the box's own frame (x, y after matching the yaws).
  Eigen::Vector3d size_error = Eigen::Vector3d::Zero();
  // Signed (found - true), to tell a bias from scatter.
  double radius_signed = 0, height_signed = 0;
  Eigen::Vector3d size_signed = Eigen::Vector3d::Zero();
  // Each reported dimension's error over its reported standard deviation (cylinder: radius,
  // height; box: size x, y, z; both: centre x, y, z), to tell whether the uncertainty can be
  // believed.
  std::vector<double> z_scores;
};

// Objects at least this visible count as in full view: refusing one is a miss; refusing a
// less visible one is a correct answer (it cannot be measured whole).
inline constexpr double kFullView = 0.95;

// A dimension the images may leave open (a lying pipe's length pointing away, a block's
// depth seen square on) off by more than 0.5 in and by more than 3 of its reported sigma: a
// wrong dimension, not one the result says is ill seen.
bool OffBeyondSigma(double error, double sigma);

// Whether a found result is another solid than the object: centre off by more than 1 in, a
// radius by 0.15 in, an upright pipe's height by 0.5 in, or a lying pipe's length or a box's
// size off beyond its sigma (OffBeyondSigma).
bool WrongModel(const ObjectEvaluation& e);

// The locator's options as the simulated lab configures its object server: the site's floor
// is the table top, z = 0 (deploy/lab.yaml, floor_height).
LocateOptions SiteLocateOptions();

// Renders the scene's stereo pair, generates marks for each cylinder and box from the
// ground truth (seeded by mark_seed and the object's index), locates and compares. The objects
// are marked in the scene's order (a pipe before its supports) and, with `database`, each
// locate knows those found before it (LocateInput::known), as in a session. With a debug_dir,
// writes each object's debug image (debug_image.h) there as SCENE_OBJECT.png.
std::vector<ObjectEvaluation> EvaluateScene(const site::Scene& scene, const std::string& scene_name,
                                            uint64_t mark_seed,
                                            const LocateOptions& options = SiteLocateOptions(),
                                            const std::string& debug_dir = "",
                                            bool database = true);

// Requests with nothing to find (the "nothing there"): marks around bare table, marks
// around a gap between objects, and each object in full view asked for as the other type (a
// cylinder called a box, a box called a cylinder). Every one should be refused.
struct NothingThereEvaluation {
  std::string scene_name;
  std::string what;         // "bare", "gap" or "wrong_type"
  std::string object_name;  // the object asked for as the other type (wrong_type)
  LocateResult result;
};
// `count` bare-or-gap requests (marks around a phantom block 1-4 in wide whose silhouette
// clears every object's by 16 px or more, "gap" when an object lies within 30 px), and the
// wrong-type requests. With a debug_dir, writes each wrong-type request's debug image there as
// SCENE_OBJECT_as_TYPE.png.
std::vector<NothingThereEvaluation> EvaluateNothingThere(
    const site::Scene& scene, const std::string& scene_name, uint64_t seed, int count,
    const LocateOptions& options = SiteLocateOptions(), const std::string& debug_dir = "");

struct Summary {
  int count = 0, found = 0;
  // In full view (visible >= kFullView): how many, found, found wrong. Partly hidden: how
  // many, refused (a correct answer), found wrong.
  int full = 0, full_found = 0, full_wrong = 0;
  int hidden = 0, hidden_refused = 0, hidden_wrong = 0;
  double full_found_rate = 0;
  double found_rate = 0;
  double radius_median = 0, radius_p90 = 0, height_median = 0, height_p90 = 0;
  double position_median = 0, position_p90 = 0;
  Eigen::Vector3d size_median = Eigen::Vector3d::Zero(), size_p90 = Eigen::Vector3d::Zero();
  double axis_median_deg = 0, axis_p90_deg = 0;  // cylinder axis or box yaw
  double within_2_sigma = 0;  // share of the z-scores under 2 (about 95% if believable)
  double time_median_ms = 0;
};
// Statistics over the evaluations whose kind matches ("" = all; "upright", "lying", "box").
Summary Summarize(const std::vector<ObjectEvaluation>& all, const std::string& which);

}  // namespace igms::object
