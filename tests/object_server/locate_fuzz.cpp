// Feeds arbitrary requests to the locator: a type, four marks (near the cameras' view, or
// raw doubles: NaN, infinities, huge values), a range, known solids (near the marks, or raw
// doubles), and a stereo pair drawn from the
// input (a few filled shapes, the right image's shifted by a disparity), sometimes empty
// or of the wrong size. Every input must give a result, found or a failure with a reason:
// no crash, no hang and no undefined behaviour (the fuzz build runs ASan and UBSan).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <opencv2/imgproc.hpp>

#include "object_server/locate.h"

namespace {

using igms::geometry::Matrix34;
using igms::geometry::ProjectiveCamera;

// 256 x 192 pixels, focal length 400 px, at (x, 0, 0) looking along the world's +y with the
// world's z up: a small stereo rig whose views overlap from about 20 in out.
ProjectiveCamera Camera(double x) {
  Eigen::Matrix3d K, R;
  K << 400, 0, 127.5, 0, 400, 95.5, 0, 0, 1;
  R << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  Matrix34 P;
  P.leftCols<3>() = K * R;
  P.col(3) = -K * R * Eigen::Vector3d(x, 0, 0);
  return ProjectiveCamera(P, {256, 192});
}

// Reads the input front to back; past its end, zeros.
class Reader {
 public:
  Reader(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  uint8_t Byte() { return at_ < size_ ? data_[at_++] : 0; }
  double Signed(double scale) {  // a 16-bit signed value times scale
    const int16_t v = static_cast<int16_t>(Byte() | (Byte() << 8));
    return v * scale;
  }
  double Raw() {
    double v = 0;
    if (at_ + sizeof v <= size_) std::memcpy(&v, data_ + at_, sizeof v);
    at_ += sizeof v;
    return v;
  }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t at_ = 0;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace igms::object;
  static const ProjectiveCamera left_camera = Camera(-3), right_camera = Camera(3);
  Reader in(data, size);
  const uint8_t flags = in.Byte();
  LocateInput input;
  input.type = flags & 1 ? SolidType::kBox : SolidType::kCylinder;
  input.left_camera = left_camera;
  input.right_camera = right_camera;

  cv::Mat left(192, 256, CV_8U, cv::Scalar(in.Byte())), right = left.clone();
  for (int shapes = in.Byte() % 4; shapes > 0; --shapes) {
    const int kind = in.Byte() % 2, grey = in.Byte(), disparity = in.Byte() % 64;
    const cv::Point corner(in.Byte(), in.Byte() % 192);
    const cv::Size extent(1 + in.Byte() / 2, 1 + in.Byte() / 2);
    for (const int shift : {0, disparity}) {
      cv::Mat& image = shift == 0 ? left : right;
      const cv::Point at = corner - cv::Point(shift, 0);
      if (kind == 0)
        cv::rectangle(image, cv::Rect(at, extent), cv::Scalar(grey), cv::FILLED);
      else
        cv::ellipse(image, at + cv::Point(extent.width / 2, extent.height / 2), extent * 2 / 4, 0,
                    0, 360, cv::Scalar(grey), cv::FILLED);
    }
  }
  input.left = left;
  input.right = right;
  if (flags & 2) input.left = cv::Mat();                         // no image
  if (flags & 4) input.right = cv::Mat(100, 100, CV_8U, 128.0);  // the wrong size
  if (flags & 8) input.left_edges = cv::Mat(192, 256, CV_8U, cv::Scalar(flags & 16 ? 255 : 0));

  // Marks: around a point ahead of the rig, within +-32 in, or raw doubles.
  const Eigen::Vector3d ahead(in.Signed(1e-3), 20 + std::abs(in.Signed(4e-3)), in.Signed(1e-3));
  for (auto& mark : input.marks) {
    if (flags & 32)
      mark = Eigen::Vector3d(in.Raw(), in.Raw(), in.Raw());
    else
      mark = ahead + Eigen::Vector3d(in.Signed(1e-3), in.Signed(1e-4), in.Signed(1e-3));
  }
  if (flags & 64) {
    input.range = flags & 128 ? in.Raw() : std::abs(in.Signed(2e-3));
    input.ranger_origin = Eigen::Vector3d(in.Signed(1e-3), in.Signed(1e-3), in.Signed(1e-3));
    input.ranger_axis = Eigen::Vector3d(in.Signed(1e-4), 1.0, in.Signed(1e-4));
  }
  // Known solids: near the marks, or raw doubles.
  for (int k = in.Byte() % 3; k > 0; --k) {
    const uint8_t how = in.Byte();
    KnownShape known{"known", how & 1 ? SolidType::kBox : SolidType::kCylinder, Eigen::VectorXd(7)};
    // Near: a cylinder's two end centres, or a box's centre, about `ahead`.
    const bool cylinder = known.type == SolidType::kCylinder;
    for (int i = 0; i < 7; ++i) {
      const double near = i < 3 ? ahead[i] : cylinder && i < 6 ? ahead[i - 3] : 0.0;
      known.params[i] = how & 2 ? in.Raw() : near + in.Signed(1e-3);
    }
    input.known.push_back(known);
  }
  input.want_trace = (flags & 24) == 24;

  const LocateResult result = Locate(input);
  // A found solid has finite, positive dimensions; a failure says why.
  if (result.found) {
    const bool finite = result.type == SolidType::kCylinder
                            ? std::isfinite(result.cylinder.radius) &&
                                  std::isfinite(result.cylinder.height) &&
                                  result.cylinder.radius > 0 && result.cylinder.center.allFinite()
                            : result.box.size.allFinite() && result.box.size.minCoeff() > 0 &&
                                  result.box.center.allFinite();
    if (!finite) __builtin_trap();
  } else if (result.detail.empty()) {
    __builtin_trap();
  }
  return 0;
}
