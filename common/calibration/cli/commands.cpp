#include "common/calibration/cli/commands.h"

#include <boost/program_options.hpp>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "common/calibration/calibration_file.h"
#include "common/calibration/chessboard.h"
#include "common/calibration/cli/json.h"
#include "common/calibration/dlt.h"
#include "common/calibration/platform_calibration.h"
#include "common/geometry/decomposition.h"
#include "common/geometry/gl_camera.h"
#include "common/sim/synthetic_platform.h"
#include "common/version/version.h"

namespace igms::calibration::cli {
namespace po = boost::program_options;
namespace {

constexpr int kBadInput = 2;

// A usage or input error: reported with exit status 2.
struct BadInput : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw BadInput(path + ": cannot open");
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// "9x6" -> {9, 6}
std::pair<int, int> ParsePair(const std::string& text, const std::string& what) {
  int a = 0, b = 0;
  char x = 0, extra = 0;
  std::istringstream in(text);
  if (!(in >> a >> x >> b) || (x != 'x' && x != 'X') || (in >> extra) || a <= 0 || b <= 0) {
    throw BadInput(what + ": expected WxH with positive integers, got '" + text + "'");
  }
  return {a, b};
}

po::variables_map Parse(int argc, const char* const argv[], const po::options_description& opts,
                        const po::positional_options_description& positional = {}) {
  po::variables_map vm;
  try {
    po::store(po::command_line_parser(argc, argv).options(opts).positional(positional).run(), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    throw BadInput(e.what());
  }
  return vm;
}

std::string Fixed(double v, int digits) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(digits) << v;
  return s.str();
}

void Save(const StereoCalibration& c, const std::string& path, std::ostream& err) {
  std::string why;
  if (!SaveCalibration(c, path, &why)) throw BadInput(why);
  err << "igms calibrate: wrote " << path << "\n";
}

// --- points ---------------------------------------------------------------------------

int Points(int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
  po::options_description opts("igms calibrate points");
  opts.add_options()("help,h", "this help")("left", po::value<std::string>(),
                                            "correspondences of the left camera (x y z u v lines)")(
      "right", po::value<std::string>(), "correspondences of the right camera")(
      "method", po::value<std::string>()->default_value("normalized"), "thesis | normalized")(
      "image-size", po::value<std::string>()->default_value("512x480"), "WxH of the images")(
      "output", po::value<std::string>(), "write a calibration file (needs --left and --right)")(
      "json", "print one JSON object");
  po::positional_options_description pos;
  pos.add("left", 1);
  const auto vm = Parse(argc, argv, opts, pos);
  if (vm.count("help")) {
    out << opts;
    return 0;
  }
  if (!vm.count("left")) throw BadInput("points: give a correspondence file (--left FILE)");
  const std::string m = vm["method"].as<std::string>();
  if (m != "thesis" && m != "normalized") throw BadInput("--method must be thesis or normalized");
  const DltMethod method = m == "thesis" ? DltMethod::kThesis : DltMethod::kNormalized;
  const auto [w, h] = ParsePair(vm["image-size"].as<std::string>(), "--image-size");
  if (vm.count("output") && !vm.count("right")) throw BadInput("--output needs --left and --right");

  Json json = Json::Object();
  json.Add("method", Json::String(ToString(method)));
  StereoCalibration cal;
  for (const char* side : {"left", "right"}) {
    if (!vm.count(side)) continue;
    const std::string path = vm[side].as<std::string>();
    const auto points = ParseCorrespondences(ReadFile(path));
    if (!points.ok()) throw BadInput(path + ": " + points.error());
    const auto result = CalibrateDlt(*points, method);
    if (!result.ok()) throw BadInput(path + ": " + result.error());
    CameraCalibration& camera = std::string(side) == "left" ? cal.left : cal.right;
    camera.P = result->P;
    camera.image_size = {w, h};
    json.Add(side, Json::Object()
                       .Add("file", Json::String(path))
                       .Add("points", Json::Number(static_cast<double>(points->size())))
                       .Add("P", Json::Matrix(result->P))
                       .Add("rms", Json::Number(result->rms))
                       .Add("max", Json::Number(result->max))
                       .Add("residuals", Json::Vector(result->residuals))
                       .str());
    if (!vm.count("json")) {
      out << side << " camera (" << path << ", " << points->size() << " points, " << m
          << " DLT):\nP =\n"
          << result->P << "\nresiduals (px):";
      for (double r : result->residuals) out << " " << Fixed(r, 3);
      out << "\nrms " << Fixed(result->rms, 4) << " px, max " << Fixed(result->max, 4) << " px\n";
    }
  }
  if (vm.count("output")) Save(cal, vm["output"].as<std::string>(), err);
  if (vm.count("json")) out << json.str() << "\n";
  return 0;
}

// --- chessboard -----------------------------------------------------------------------

int Chessboard(int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
  po::options_description opts("igms calibrate chessboard");
  opts.add_options()("help,h", "this help")(
      "left", po::value<std::vector<std::string>>()->multitoken(), "left images")(
      "right", po::value<std::vector<std::string>>()->multitoken(), "right images, same order")(
      "board", po::value<std::string>()->default_value("9x6"), "inner corners, COLSxROWS")(
      "square", po::value<double>()->default_value(1.0), "square size in world units")(
      "procedure", po::value<std::string>()->default_value("joint"),
      "joint | fixed | opencv-sample")("output", po::value<std::string>(),
                                       "calibration file to write")("json",
                                                                    "print one JSON object");
  const auto vm = Parse(argc, argv, opts);
  if (vm.count("help")) {
    out << opts;
    return 0;
  }
  if (!vm.count("left") || !vm.count("right"))
    throw BadInput("chessboard: give --left and --right images");
  ChessboardOptions options;
  std::tie(options.cols, options.rows) = ParsePair(vm["board"].as<std::string>(), "--board");
  options.square = vm["square"].as<double>();
  const std::string proc = vm["procedure"].as<std::string>();
  if (proc == "joint") {
    options.procedure = ChessboardOptions::Procedure::kJoint;
  } else if (proc == "fixed") {
    options.procedure = ChessboardOptions::Procedure::kFixed;
  } else if (proc == "opencv-sample") {
    options.procedure = ChessboardOptions::Procedure::kOpenCvSample;
  } else {
    throw BadInput("--procedure must be joint, fixed or opencv-sample");
  }
  const auto r = CalibrateChessboard(
      vm["left"].as<std::vector<std::string>>(), vm["right"].as<std::vector<std::string>>(),
      options, [&](const std::string& msg) { err << "igms calibrate: " << msg << "\n"; });
  if (!r.ok()) throw BadInput(r.error());
  for (const auto& s : r->skipped) err << "igms calibrate: skipped " << s << "\n";
  if (vm.count("output")) Save(r->calibration, vm["output"].as<std::string>(), err);
  if (vm.count("json")) {
    Json skipped = Json::Array();
    for (const auto& s : r->skipped) skipped.Add(Json::String(s));
    out << Json::Object()
               .Add("pairs_used", Json::Number(r->pairs_used))
               .Add("skipped", skipped.str())
               .Add("procedure", Json::String(proc))
               .Add("left_rms", Json::Number(r->left_rms))
               .Add("right_rms", Json::Number(r->right_rms))
               .Add("stereo_rms", Json::Number(r->stereo_rms))
               .Add("epipolar_error", Json::Number(r->epipolar_error))
               .Add("epipolar_error_per_image", Json::Number(r->epipolar_error_per_image))
               .Add("baseline", Json::Number(r->t.norm()))
               .Add("R", Json::Matrix(r->R))
               .Add("t", Json::Vector(r->t))
               .Add("left_K", Json::Matrix(*r->calibration.left.K))
               .Add("left_dist", Json::Vector(r->calibration.left.dist))
               .Add("right_K", Json::Matrix(*r->calibration.right.K))
               .Add("right_dist", Json::Vector(r->calibration.right.dist))
               .str()
        << "\n";
  } else {
    out << "pairs used: " << r->pairs_used << " (" << r->skipped.size() << " skipped)\n"
        << "left camera RMS:  " << Fixed(r->left_rms, 4) << " px\n"
        << "right camera RMS: " << Fixed(r->right_rms, 4) << " px\n"
        << "stereo RMS:       " << Fixed(r->stereo_rms, 4) << " px\n"
        << "average epipolar error: " << Fixed(r->epipolar_error, 4)
        << " px (both images summed per corner pair, as OpenCV's stereo_calib; "
        << Fixed(r->epipolar_error_per_image, 4) << " px per image)\n"
        << "baseline: " << Fixed(r->t.norm(), 4) << " (world units)\n";
  }
  return 0;
}

// --- decompose ------------------------------------------------------------------------

// The message of the first failed result (the graphics camera's first: it also checks the
// image size).
template <class... R>
std::string FirstError(const R&... results) {
  std::string why;
  ((why.empty() && !results.ok() ? why = results.error() : why), ...);
  return why;
}

std::string DecompositionJson(const geometry::Matrix34& P, geometry::ImageSize size) {
  const auto t = geometry::DecomposeThesis(P);
  const auto rq = geometry::DecomposeRq(P);
  const auto gl = geometry::MakeGlCamera(P, size, 1.0, 1000.0);
  if (!t.ok() || !rq.ok() || !gl.ok()) throw BadInput(FirstError(gl, rq, t));
  constexpr double kDeg = 180.0 / M_PI;
  return Json::Object()
      .Add("thesis", Json::Object()
                         .Add("ku", Json::Number(t->ku))
                         .Add("kv", Json::Number(t->kv))
                         .Add("u0", Json::Number(t->u0))
                         .Add("v0", Json::Number(t->v0))
                         .Add("center", Json::Vector(t->center))
                         .Add("theta", Json::Number(t->theta))
                         .Add("phi", Json::Number(t->phi))
                         .Add("psi", Json::Number(t->psi))
                         .Add("printed_theta", Json::Number(t->printed_theta))
                         .Add("printed_psi", Json::Number(t->printed_psi))
                         .Add("skew", Json::Number(t->skew))
                         .str())
      .Add("rq", Json::Object()
                     .Add("K", Json::Matrix(rq->K))
                     .Add("R", Json::Matrix(rq->R))
                     .Add("center", Json::Vector(rq->center))
                     .str())
      .Add("graphics", Json::Object()
                           .Add("fovy_degrees", Json::Number(gl->fovy_degrees))
                           .Add("fovx_degrees", Json::Number(gl->fovx_degrees))
                           .Add("aspect", Json::Number(gl->aspect))
                           .Add("principal_offset", Json::Vector(gl->principal_offset))
                           .Add("view_direction_deg_from_x",
                                Json::Number(std::atan2(rq->R(2, 1), rq->R(2, 0)) * kDeg))
                           .str())
      .str();
}

void DecompositionText(const std::string& side, const geometry::Matrix34& P,
                       geometry::ImageSize size, std::ostream& out) {
  const auto t = geometry::DecomposeThesis(P);
  const auto rq = geometry::DecomposeRq(P);
  const auto gl = geometry::MakeGlCamera(P, size, 1.0, 1000.0);
  if (!t.ok() || !rq.ok() || !gl.ok()) throw BadInput(side + ".P: " + FirstError(gl, rq, t));
  out << side << " camera\n"
      << "  thesis (Ganapathy): ku=" << Fixed(t->ku, 2) << " kv=" << Fixed(t->kv, 2)
      << " u0=" << Fixed(t->u0, 1) << " v0=" << Fixed(t->v0, 1) << "\n"
      << "    centre x=" << Fixed(t->center.x(), 2) << ", y=" << Fixed(t->center.y(), 2)
      << ", z=" << Fixed(t->center.z(), 2) << "\n"
      << "    theta=" << Fixed(t->theta, 4) << " phi=" << Fixed(t->phi, 4)
      << " psi=" << Fixed(t->psi, 4)
      << " (as the thesis prints them: theta=" << Fixed(t->printed_theta, 3)
      << ", psi=" << Fixed(t->printed_psi, 3) << ")"
      << " skew=" << Fixed(t->skew, 5) << " rad\n"
      << "  RQ: fx=" << Fixed(rq->fx(), 2) << " fy=" << Fixed(rq->fy(), 2)
      << " cx=" << Fixed(rq->cx(), 1) << " cy=" << Fixed(rq->cy(), 1)
      << " skew=" << Fixed(rq->skew(), 3) << " centre (" << Fixed(rq->center.x(), 2) << ", "
      << Fixed(rq->center.y(), 2) << ", " << Fixed(rq->center.z(), 2) << ")\n"
      << "  graphics: fovy=" << Fixed(gl->fovy_degrees, 2)
      << " deg, fovx=" << Fixed(gl->fovx_degrees, 2) << " deg, aspect=" << Fixed(gl->aspect, 4)
      << ", principal offset (" << Fixed(gl->principal_offset.x(), 1) << ", "
      << Fixed(gl->principal_offset.y(), 1) << ") px\n";
}

int Decompose(int argc, const char* const argv[], std::ostream& out, std::ostream&) {
  po::options_description opts("igms calibrate decompose");
  opts.add_options()("help,h", "this help")("calibration", po::value<std::string>(),
                                            "calibration file")("json", "print one JSON object");
  po::positional_options_description pos;
  pos.add("calibration", 1);
  const auto vm = Parse(argc, argv, opts, pos);
  if (vm.count("help")) {
    out << opts;
    return 0;
  }
  if (!vm.count("calibration")) throw BadInput("decompose: give a calibration file");
  const auto cal = LoadCalibration(vm["calibration"].as<std::string>());
  if (!cal.ok()) throw BadInput(cal.error());
  if (vm.count("json")) {
    out << Json::Object()
               .Add("left", DecompositionJson(cal->left.P, cal->left.image_size))
               .Add("right", DecompositionJson(cal->right.P, cal->right.image_size))
               .str()
        << "\n";
  } else {
    DecompositionText("left", cal->left.P, cal->left.image_size, out);
    DecompositionText("right", cal->right.P, cal->right.image_size, out);
  }
  return 0;
}

// --- platform -------------------------------------------------------------------------

std::string PlatformJson(const geometry::PlatformModel& m) {
  Json joints = Json::Array();
  for (const auto& j : m.joints) {
    joints.Add(Json::Object()
                   .Add("name", Json::String(j.name))
                   .Add("theta_offset", Json::Number(j.theta_offset))
                   .Add("d", Json::Number(j.d))
                   .Add("a", Json::Number(j.a))
                   .Add("alpha", Json::Number(j.alpha))
                   .Add("radians_per_tick", Json::Number(j.radians_per_tick))
                   .str());
  }
  return Json::Object()
      .Add("world_from_base", Json::Matrix(m.world_from_base.matrix()))
      .Add("joints", joints.str())
      .str();
}

int Platform(int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
  po::options_description opts("igms calibrate platform");
  opts.add_options()("help,h", "this help")(
      "calibration", po::value<std::string>(),
      "calibration file: cameras at the zero pose and the initial `platform` model")(
      "observations", po::value<std::string>(), "camera t1..tn x y z u v lines")(
      "estimate-scales", "estimate the encoders' radians per tick too")(
      "max-iterations", po::value<int>()->default_value(100), "Levenberg-Marquardt iterations")(
      "output", po::value<std::string>(), "calibration file to write with the fitted platform")(
      "synthetic", "calibrate a synthetic head with known parameters and report the recovery")(
      "noise", po::value<double>()->default_value(0.3), "pixel noise of --synthetic")(
      "json", "print one JSON object");
  const auto vm = Parse(argc, argv, opts);
  if (vm.count("help")) {
    out << opts;
    return 0;
  }
  PlatformCalibrationOptions options;
  options.estimate_scales = vm.count("estimate-scales") > 0;
  options.max_iterations = vm["max-iterations"].as<int>();
  auto progress = [&](int it, double rms) {
    err << "igms calibrate: iteration " << it << ": rms " << Fixed(rms, 4) << " px\n";
  };
  std::string why;
  if (vm.count("synthetic")) {
    const double noise = vm["noise"].as<double>();
    if (!(noise >= 0) || !std::isfinite(noise)) throw BadInput("--noise must be >= 0");
    const auto s = MakePlatformScenario(noise, 1);
    const auto r =
        CalibratePlatform(s.P0[0], s.P0[1], s.nominal, s.observations, options, progress);
    if (!r.ok()) throw BadInput(r.error());
    const auto before = CompareToTruth(s, s.nominal, 2);
    const auto after = CompareToTruth(s, r->model, 2);
    if (vm.count("json")) {
      out << Json::Object()
                 .Add("observations", Json::Number(static_cast<double>(s.observations.size())))
                 .Add("noise_px", Json::Number(noise))
                 .Add("initial_rms", Json::Number(r->initial_rms))
                 .Add("rms", Json::Number(r->rms))
                 .Add("iterations", Json::Number(r->iterations))
                 .Add("max_axis_angle_deg", Json::Number(after.max_axis_angle_deg))
                 .Add("max_axis_offset", Json::Number(after.max_axis_offset))
                 .Add("max_scale_error", Json::Number(after.max_scale_error))
                 .Add("prediction_rms_px_before", Json::Number(before.prediction_rms_px))
                 .Add("prediction_rms_px", Json::Number(after.prediction_rms_px))
                 .str()
          << "\n";
    } else {
      out << "synthetic head: " << s.observations.size() << " observations at 27 poses, noise "
          << noise << " px\n"
          << "reprojection rms: " << Fixed(r->initial_rms, 3) << " px (nominal model) -> "
          << Fixed(r->rms, 3) << " px in " << r->iterations << " iterations\n"
          << "recovery: joint axes within " << Fixed(after.max_axis_angle_deg, 4) << " deg and "
          << Fixed(after.max_axis_offset, 4) << " in; tick scales within "
          << Fixed(after.max_scale_error * 100, 3) << "%\n"
          << "prediction at 200 new poses: " << Fixed(before.prediction_rms_px, 3)
          << " px (nominal) -> " << Fixed(after.prediction_rms_px, 4) << " px rms\n";
    }
    return 0;
  }
  if (!vm.count("calibration") || !vm.count("observations")) {
    throw BadInput("platform: give --calibration and --observations (or --synthetic)");
  }
  auto cal = LoadCalibration(vm["calibration"].as<std::string>());
  if (!cal.ok()) throw BadInput(cal.error());
  if (!cal->platform) {
    throw BadInput(vm["calibration"].as<std::string>() +
                   ": platform: missing (an initial model is needed; see docs/calibration.md)");
  }
  const std::string obs_path = vm["observations"].as<std::string>();
  const auto obs =
      ParsePlatformObservations(ReadFile(obs_path), static_cast<int>(cal->platform->joints.size()));
  if (!obs.ok()) throw BadInput(obs_path + ": " + obs.error());
  const auto r =
      CalibratePlatform(cal->left.P, cal->right.P, *cal->platform, *obs, options, progress);
  if (!r.ok()) throw BadInput(obs_path + ": " + r.error());
  cal->platform = r->model;
  if (vm.count("output")) Save(*cal, vm["output"].as<std::string>(), err);
  if (vm.count("json")) {
    out << Json::Object()
               .Add("observations", Json::Number(static_cast<double>(obs->size())))
               .Add("parameters", Json::Number(r->parameters))
               .Add("initial_rms", Json::Number(r->initial_rms))
               .Add("rms", Json::Number(r->rms))
               .Add("max", Json::Number(r->max))
               .Add("iterations", Json::Number(r->iterations))
               .Add("platform", PlatformJson(r->model))
               .Add("residuals", Json::Vector(r->residuals))
               .str()
        << "\n";
  } else {
    out << obs->size() << " observations, " << r->parameters << " parameters\n"
        << "reprojection rms " << Fixed(r->initial_rms, 4) << " px -> " << Fixed(r->rms, 4)
        << " px (max " << Fixed(r->max, 4) << ") in " << r->iterations << " iterations\n";
    for (const auto& j : r->model.joints) {
      out << "  " << j.name << ": theta_offset=" << j.theta_offset << " d=" << j.d << " a=" << j.a
          << " alpha=" << j.alpha << " radians_per_tick=" << j.radians_per_tick << "\n";
    }
  }
  return 0;
}

void Usage(std::ostream& out) {
  out << "usage: igms calibrate points|chessboard|decompose|platform [options] (--help for each)\n"
         "  points      DLT calibration from x y z u v correspondences\n"
         "  chessboard  stereo calibration from chessboard image pairs\n"
         "  decompose   camera parameters of a calibration file's matrices\n"
         "  platform    Denavit-Hartenberg calibration of the camera platform\n"
         "       igms calibrate --version\n";
}

}  // namespace

int RunCalibrate(int argc, const char* const argv[], std::ostream& out, std::ostream& err) {
  if (argc < 2) {
    Usage(err);
    return kBadInput;
  }
  const std::string sub = argv[1];
  if (sub == "--help" || sub == "-h" || sub == "help") {
    Usage(out);
    return 0;
  }
  if (sub == "--version") {
    out << igms::version::Line("igms-calibrate") << "\n";
    return 0;
  }
  try {
    // Each subcommand parses its own options, with argv[1] standing in for the program name.
    if (sub == "points") return Points(argc - 1, argv + 1, out, err);
    if (sub == "chessboard") return Chessboard(argc - 1, argv + 1, out, err);
    if (sub == "decompose") return Decompose(argc - 1, argv + 1, out, err);
    if (sub == "platform") return Platform(argc - 1, argv + 1, out, err);
    err << "igms calibrate: unknown subcommand '" << sub << "'\n";
    Usage(err);
    return kBadInput;
  } catch (const BadInput& e) {
    err << "igms calibrate " << sub << ": " << e.what() << "\n";
    return kBadInput;
  }
}

}  // namespace igms::calibration::cli
