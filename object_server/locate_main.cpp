// igms-locate: locate one cylinder or box offline, from a calibration file, a stereo pair of
// image files and four marks. Exit status: 0 found, 1 not found, 2 bad input.
#include <spdlog/spdlog.h>

#include <boost/program_options.hpp>
#include <cmath>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <sstream>

#include "common/calibration/calibration_file.h"
#include "common/config/exit_codes.h"
#include "common/version/version.h"
#include "object_server/debug_image.h"
#include "object_server/locate.h"
#include "object_server/ranger.h"
#include "object_server/result_json.h"

namespace po = boost::program_options;

namespace {

// Exit status: found, not found (docs/configuration.md, "Exit status").
constexpr int kFound = igms::kExitOk, kNotFound = igms::kExitFailure, kBadInput = igms::kExitUsage;

std::optional<Eigen::Vector3d> ParseMark(const std::string& text) {
  std::stringstream ss(text);
  Eigen::Vector3d m;
  char c1 = 0, c2 = 0;
  if (!(ss >> m.x() >> c1 >> m.y() >> c2 >> m.z()) || c1 != ',' || c2 != ',') return std::nullopt;
  std::string rest;
  if (ss >> rest) return std::nullopt;
  return m;
}

int Run(int argc, char** argv) {
  po::options_description desc(
      "igms locate: find a cylinder or box from a stereo pair and four marks\n"
      "Usage: igms locate --calibration FILE --left IMG --right IMG --type cylinder|box "
      "--mark X,Y,Z (four times) [--range D] [--camera-blur PX] [--floor-height Z]\n"
      "[--debug-image FILE] [--json]\n"
      "Options");
  std::string calibration, left_path, right_path, type, debug_image;
  double range = -1;
  igms::object::LocateOptions input_options;
  std::vector<std::string> marks;
  desc.add_options()("help,h", "this help")("version", "print the version and exit")(
      "calibration", po::value(&calibration), "stereo calibration YAML")(
      "left", po::value(&left_path), "left image file")("right", po::value(&right_path),
                                                        "right image file")(
      "type", po::value(&type), "cylinder or box")("mark", po::value(&marks)->composing(),
                                                   "a mark X,Y,Z in world units (give four)")(
      "range", po::value(&range),
      "the ultrasonic range D (world units) along the ranger's axis (the calibration's ranger "
      "map)")("debug-image", po::value(&debug_image),
              "write an image of the edges, measured points and fitted outline over the images "
              "(PNG, JPEG)")("json", "print the result as one JSON object")(
      "camera-blur", po::value(&input_options.camera_blur_px),
      "the cameras' blur as a Gaussian's sigma in pixels (default 0.7, the simulated site's; "
      "measure it for real cameras): curved edges are corrected for it")(
      "floor-height", po::value<double>(),
      "the height (world z) of the floor the objects stand on, when the site has one: an "
      "upright pipe whose foot the images leave open is fitted standing on it too")(
      "verbose,v", "log the pipeline's steps to stderr");
  po::variables_map vm;
  try {
    po::store(po::parse_command_line(argc, argv, desc), vm);
    po::notify(vm);
  } catch (const po::error& e) {
    std::cerr << "igms locate: " << e.what() << "\n" << desc << "\n";
    return kBadInput;
  }
  if (vm.count("help")) {
    std::cout << desc << "\n";
    return igms::kExitOk;
  }
  if (vm.count("version")) {
    std::cout << igms::version::Line("igms-locate") << "\n";
    return 0;
  }
  spdlog::set_level(vm.count("verbose") ? spdlog::level::debug : spdlog::level::warn);
  auto bad = [&](const std::string& msg) {
    std::cerr << "igms locate: " << msg << "\n";
    return kBadInput;
  };
  if (calibration.empty() || left_path.empty() || right_path.empty() || type.empty())
    return bad("--calibration, --left, --right and --type are required (see --help)");
  igms::object::LocateInput input;
  if (type == "cylinder")
    input.type = igms::object::SolidType::kCylinder;
  else if (type == "box")
    input.type = igms::object::SolidType::kBox;
  else
    return bad("--type must be cylinder or box, not '" + type + "'");
  if (marks.size() != 4)
    return bad("give exactly four --mark X,Y,Z (got " + std::to_string(marks.size()) + ")");
  for (size_t i = 0; i < 4; ++i) {
    const auto m = ParseMark(marks[i]);
    if (!m || !m->allFinite())
      return bad("--mark '" + marks[i] + "' is not X,Y,Z with three finite numbers");
    input.marks[i] = *m;
  }
  const auto cal = igms::calibration::LoadCalibration(calibration);
  if (!cal.ok()) return bad(cal.error());
  if (vm.count("range")) {
    if (!std::isfinite(range) || range <= 0) return bad("--range must be a positive distance");
    const auto ranger = igms::object::RangerInWorld(*cal);
    if (!ranger)
      return bad("--range needs a ranger map (origin, axis) in the calibration file " +
                 calibration);
    input.range = range;
    input.ranger_origin = ranger->origin;
    input.ranger_axis = ranger->axis;
  }
  input.want_trace = !debug_image.empty();
  input.left_camera = cal->left.Camera();
  input.right_camera = cal->right.Camera();
  input.left = cv::imread(left_path, cv::IMREAD_GRAYSCALE);
  if (input.left.empty()) return bad("cannot read image " + left_path);
  input.right = cv::imread(right_path, cv::IMREAD_GRAYSCALE);
  if (input.right.empty()) return bad("cannot read image " + right_path);

  if (vm.count("floor-height")) input_options.floor_height = vm["floor-height"].as<double>();
  if (std::string problem; !input_options.Check(&problem)) return bad("options: " + problem);
  const auto result = igms::object::Locate(input, input_options);
  if (!debug_image.empty()) {
    bool written = false;
    try {
      written = cv::imwrite(debug_image, igms::object::DebugImage(input, result));
    } catch (const cv::Exception& e) {
      std::cerr << "igms locate: " << e.what() << "\n";
    }
    if (!written) std::cerr << "igms locate: cannot write the debug image " << debug_image << "\n";
  }
  if (vm.count("json")) {
    std::cout << igms::object::ResultToJson(result) << std::endl;
  } else if (result.found && result.type == igms::object::SolidType::kCylinder) {
    const auto& c = result.cylinder;
    std::cout << "cylinder: center (" << c.center.transpose() << ") axis (" << c.axis.transpose()
              << ") radius " << c.radius << " height " << c.height << "\n";
  } else if (result.found) {
    std::cout << "box: min (" << result.box.min.transpose() << ") max ("
              << result.box.max.transpose() << ")\n";
  } else {
    std::cout << "not found (" << igms::object::FailureName(result.reason) << "): " << result.detail
              << "\n";
  }
  if (!vm.count("json") && result.range.used && !result.range.agrees)
    std::cout << "range disagrees: " << result.range.detail << "\n";
  if (!result.found && result.reason == igms::object::Failure::kBadInput) return kBadInput;
  return result.found ? kFound : kNotFound;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return Run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "igms locate: internal error: " << e.what() << "\n";
    return igms::kExitUnavailable;
  }
}
