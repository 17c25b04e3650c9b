// igms-object-server and igms-video-server as real processes on loopback: locating the
// simulated testbed's objects from generated marks, request validation, and what happens
// while the video server is gone and after it returns.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <opencv2/imgcodecs.hpp>

#include "common/calibration/calibration_file.h"
#include "common/calibration/calibration_hash.h"
#include "common/sim/marks.h"
#include "common/sim/testbed.h"
#include "igms/object.pb.h"
#include "igms/video.pb.h"
#include "object_server/object_service.h"
#include "tests/support/video_server_process.h"

namespace igms::object {
namespace {

using namespace std::chrono_literals;
using video::testing::TestClient;

std::string Calibration() { return igms::testing::ThesisCalibration(); }

// Any IGMS server program, stopped with SIGTERM when destroyed.
class Process : public igms::testing::ChildProcess {
 public:
  Process(const std::string& program, std::vector<std::string> args)
      : ChildProcess(program, std::move(args)) {}
  ~Process() { Stop(); }
  uint16_t WaitPort() { return WaitListening(); }
  void Stop() {
    if (!Exited()) Terminate();
  }
};

std::vector<std::string> VideoArgs(uint16_t port) {
  return {"--name", "video",
          "--port", std::to_string(port),
          "--set",  "processes.video.backend=sim",
          "--set",  "lab.calibration=" + Calibration()};
}

LocateRequest RequestFor(const site::Shape& shape, uint64_t frame_id, uint64_t seed) {
  auto cal = calibration::LoadCalibration(Calibration());
  auto marks = site::GenerateMarks(shape, cal->left.Camera(), seed);
  LocateRequest request;
  request.set_type(std::holds_alternative<site::Cylinder>(shape) ? OBJECT_TYPE_CYLINDER
                                                                 : OBJECT_TYPE_BOX);
  MarksToProto(*marks, &request);
  request.set_frame_id(frame_id);
  return request;
}

uint64_t Grab(uint16_t video_port) {
  TestClient client(video_port);
  auto grab = client->CallSync<video::GrabResponse>("igms.video.VideoService.Grab",
                                                    video::GrabRequest{}, 60s);
  EXPECT_TRUE(grab.ok()) << grab.status.message;
  return grab.value.frame_id();
}

const std::string kLocate = "igms.object.ObjectService.Locate";

class ObjectServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    video_ = std::make_unique<Process>("igms-video-server", VideoArgs(0));
    video_port_ = video_->WaitPort();
    ASSERT_NE(video_port_, 0);
    object_ = std::make_unique<Process>(
        "igms-object-server",
        std::vector<std::string>{"--name", "object", "--port", "0", "--set",
                                 "processes.video.port=" + std::to_string(video_port_), "--set",
                                 "processes.object.fetch_timeout_ms=1500", "--set",
                                 "lab.calibration=" + Calibration()});
    object_port_ = object_->WaitPort();
    ASSERT_NE(object_port_, 0);
  }
  std::unique_ptr<Process> video_, object_;
  uint16_t video_port_ = 0, object_port_ = 0;
};

TEST_F(ObjectServerTest, LocatesTheTestbedsFirstCylinderAndBox) {
  const uint64_t frame = Grab(video_port_);
  const site::Scene scene = site::DefaultTestbedScene();
  TestClient client(object_port_);
  int cylinders = 0, boxes = 0;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const auto* cyl = std::get_if<site::Cylinder>(&scene.objects[i].shape);
    const auto* box = std::get_if<site::Box>(&scene.objects[i].shape);
    if ((cyl && cylinders++ > 0) || (box && boxes++ > 0) || (!cyl && !box)) continue;
    auto got = client->CallSync<LocateResponse>(kLocate,
                                                RequestFor(scene.objects[i].shape, frame, i), 60s);
    ASSERT_TRUE(got.ok()) << got.status.message;
    ASSERT_TRUE(got.value.found()) << scene.objects[i].name << ": " << got.value.detail();
    if (cyl) {
      const auto& c = got.value.cylinder();
      EXPECT_LT(
          (Eigen::Vector3d(c.center().x(), c.center().y(), c.center().z()) - cyl->center).norm(),
          0.5);
      EXPECT_NEAR(c.radius(), cyl->radius, 0.1);
      EXPECT_NEAR(c.height(), cyl->height, 0.3);
    } else {
      const auto& b = got.value.box();
      const Eigen::Vector3d mid = 0.5 * (Eigen::Vector3d(b.min().x(), b.min().y(), b.min().z()) +
                                         Eigen::Vector3d(b.max().x(), b.max().y(), b.max().z()));
      EXPECT_LT((mid - box->center).norm(), 0.6);
      // The texture patch: the left image's pixels of the texture rectangle.
      const std::string& png = b.texture_png();
      const cv::Mat texture =
          cv::imdecode(std::vector<uint8_t>(png.begin(), png.end()), cv::IMREAD_UNCHANGED);
      ASSERT_FALSE(texture.empty());
      EXPECT_EQ(texture.cols, b.texture_u1() - b.texture_u0() + 1);
      EXPECT_EQ(texture.rows, b.texture_v1() - b.texture_v0() + 1);
      EXPECT_GT(cv::mean(texture)[0], 60.0);  // mostly the white block, not the dark table
      // Marked again with its model known (as the control client sends the database), it
      // is that model found again, named.
      LocateRequest again = RequestFor(scene.objects[i].shape, frame, i);
      auto* known = again.add_known();
      known->set_name("box 1");
      known->set_type(OBJECT_TYPE_BOX);
      *known->mutable_box() = b;
      known->mutable_box()->clear_texture_png();
      const auto refused = client->CallSync<LocateResponse>(kLocate, again, 60s);
      ASSERT_TRUE(refused.ok()) << refused.status.message;
      EXPECT_FALSE(refused.value.found());
      EXPECT_EQ(refused.value.reason(), FAILURE_ALREADY_MODELLED) << refused.value.detail();
      EXPECT_NE(refused.value.detail().find("box 1"), std::string::npos);
    }
  }
  EXPECT_EQ(cylinders > 0 && boxes > 0, true);
}

// Every object of the testbed asked for at once, on a frame not yet fetched: the workers
// race for the frame and the cache, and every request gets its own object back.
TEST_F(ObjectServerTest, SeveralRequestsAtOnceEachGetTheirObject) {
  const uint64_t frame = Grab(video_port_);
  const site::Scene scene = site::DefaultTestbedScene();
  TestClient client(object_port_);
  struct Pending {
    const site::Shape* shape;
    std::atomic<bool> done{false};
    net::Result<LocateResponse> result;
  };
  std::vector<std::unique_ptr<Pending>> pending;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const auto& shape = scene.objects[i].shape;
    if (!std::holds_alternative<site::Cylinder>(shape) && !std::holds_alternative<site::Box>(shape))
      continue;
    auto p = std::make_unique<Pending>();
    p->shape = &shape;
    Pending* raw = p.get();
    client->Call<LocateResponse>(kLocate, RequestFor(shape, frame, i), 60s,
                                 [raw](net::Result<LocateResponse> r) {
                                   raw->result = std::move(r);
                                   raw->done.store(true);
                                   raw->done.notify_one();
                                 });
    pending.push_back(std::move(p));
  }
  ASSERT_GE(pending.size(), 4u);
  for (auto& p : pending) {
    p->done.wait(false);
    ASSERT_TRUE(p->result.ok()) << p->result.status.message;
    ASSERT_TRUE(p->result.value.found()) << p->result.value.detail();
    if (const auto* cyl = std::get_if<site::Cylinder>(p->shape)) {
      const auto& c = p->result.value.cylinder();
      EXPECT_LT(
          (Eigen::Vector3d(c.center().x(), c.center().y(), c.center().z()) - cyl->center).norm(),
          0.5);
      EXPECT_NEAR(c.radius(), cyl->radius, 0.1);
    } else {
      const auto& box = std::get<site::Box>(*p->shape);
      const auto& b = p->result.value.box();
      EXPECT_LT(
          (Eigen::Vector3d(b.center().x(), b.center().y(), b.center().z()) - box.center).norm(),
          0.6);
    }
  }
}

TEST_F(ObjectServerTest, BadRequestsAndUnknownFrames) {
  const uint64_t frame = Grab(video_port_);
  const site::Scene scene = site::DefaultTestbedScene();
  TestClient client(object_port_);
  LocateRequest good = RequestFor(scene.objects[0].shape, frame, 1);

  LocateRequest three = good;
  three.mutable_marks()->RemoveLast();
  auto got = client->CallSync<LocateResponse>(kLocate, three, 10s);
  EXPECT_EQ(got.status.code, igms::BAD_REQUEST) << got.status.message;

  LocateRequest nan = good;
  nan.mutable_marks(2)->set_y(std::numeric_limits<double>::quiet_NaN());
  got = client->CallSync<LocateResponse>(kLocate, nan, 10s);
  EXPECT_EQ(got.status.code, igms::BAD_REQUEST) << got.status.message;
  LocateRequest inf = good;
  inf.mutable_marks(0)->set_x(std::numeric_limits<double>::infinity());
  got = client->CallSync<LocateResponse>(kLocate, inf, 10s);
  EXPECT_EQ(got.status.code, igms::BAD_REQUEST);

  LocateRequest untyped = good;
  untyped.set_type(OBJECT_TYPE_UNSPECIFIED);
  got = client->CallSync<LocateResponse>(kLocate, untyped, 10s);
  EXPECT_EQ(got.status.code, igms::BAD_REQUEST);

  LocateRequest unknown = good;
  unknown.set_frame_id(frame + 1000);
  got = client->CallSync<LocateResponse>(kLocate, unknown, 10s);
  EXPECT_EQ(got.status.code, igms::NOT_FOUND) << got.status.message;

  // A range: the calibration's ranger map (nominal) makes it used and checked against the
  // located object, whether or not the beam meets that object.
  LocateRequest ranged = good;
  ranged.set_range(50);
  got = client->CallSync<LocateResponse>(kLocate, ranged, 60s);
  ASSERT_TRUE(got.ok()) << got.status.message;
  EXPECT_TRUE(got.value.range().used());
  EXPECT_EQ(got.value.range().measured(), 50);
  if (got.value.found()) {
    EXPECT_TRUE(got.value.range().agrees() || !got.value.range().detail().empty());
  }
  LocateRequest negative = good;
  negative.set_range(-1);
  got = client->CallSync<LocateResponse>(kLocate, negative, 10s);
  EXPECT_EQ(got.status.code, igms::BAD_REQUEST);

  // A known solid that is no solid is refused by name; a good one is used.
  LocateRequest known = good;
  auto* pipe = known.add_known();
  pipe->set_name("cylinder 7");
  pipe->set_type(OBJECT_TYPE_CYLINDER);
  pipe->mutable_cylinder()->mutable_axis()->set_z(1);
  pipe->mutable_cylinder()->set_radius(1);
  pipe->mutable_cylinder()->set_height(std::numeric_limits<double>::quiet_NaN());
  got = client->CallSync<LocateResponse>(kLocate, known, 10s);
  EXPECT_EQ(got.status.code, igms::BAD_REQUEST);
  EXPECT_NE(got.status.message.find("cylinder 7"), std::string::npos) << got.status.message;
  pipe->mutable_cylinder()->set_height(4);
  pipe->mutable_cylinder()->mutable_center()->set_x(-200);  // far out of view
  got = client->CallSync<LocateResponse>(kLocate, known, 60s);
  EXPECT_TRUE(got.ok()) << got.status.message;

  // After all that the server still answers.
  got = client->CallSync<LocateResponse>(kLocate, good, 60s);
  EXPECT_TRUE(got.ok()) << got.status.message;
}

TEST_F(ObjectServerTest, VideoServerGoneIsUnavailableAndItsReturnIsNoticed) {
  const uint64_t first = Grab(video_port_);
  const site::Scene scene = site::DefaultTestbedScene();
  TestClient client(object_port_);
  video_->Stop();
  auto got =
      client->CallSync<LocateResponse>(kLocate, RequestFor(scene.objects[0].shape, first, 1), 20s);
  EXPECT_EQ(got.status.code, igms::UNAVAILABLE) << got.status.message;

  video_ = std::make_unique<Process>("igms-video-server", VideoArgs(video_port_));
  ASSERT_EQ(video_->WaitPort(), video_port_);
  const uint64_t second = Grab(video_port_);
  // The object server reconnects to the video server on its own: asked again until then.
  const bool found = igms::testing::WaitUntil(
      [&] {
        got = client->CallSync<LocateResponse>(kLocate,
                                               RequestFor(scene.objects[0].shape, second, 1), 60s);
        return got.ok() && got.value.found();
      },
      120s, 500ms);
  EXPECT_TRUE(found) << got.status.message;
}

// Both servers report the hash of the calibration file they loaded, the library's, and the
// object server names the video server it fetches from.
TEST_F(ObjectServerTest, BothServersReportTheHashOfTheirCalibration) {
  const auto calibration = calibration::LoadCalibration(Calibration());
  ASSERT_TRUE(calibration.ok()) << calibration.error();
  const std::string hash = calibration::CalibrationHash(*calibration);
  ASSERT_EQ(hash.size(), 64u);

  TestClient video(video_port_);
  auto video_status = video->CallSync<video::StatusResponse>("igms.video.VideoService.GetStatus",
                                                             video::StatusRequest(), 10s);
  ASSERT_TRUE(video_status.ok()) << video_status.status.message;
  EXPECT_EQ(video_status.value.calibration_sha256(), hash);
  EXPECT_EQ(std::filesystem::path(video_status.value.calibration_file()).lexically_normal(),
            std::filesystem::path(Calibration()).lexically_normal());

  TestClient object(object_port_);
  StatusResponse status;
  ASSERT_TRUE(igms::testing::WaitUntil([&] {
    auto got =
        object->CallSync<StatusResponse>("igms.object.ObjectService.Status", StatusRequest(), 10s);
    status = got.value;
    return got.ok() && status.video_connected();
  })) << status.video_detail();
  EXPECT_EQ(status.calibration_sha256(), hash);
  EXPECT_EQ(std::filesystem::path(status.calibration_file()).lexically_normal(),
            std::filesystem::path(Calibration()).lexically_normal());
  EXPECT_TRUE(status.calibration_has_platform());
  EXPECT_TRUE(status.calibration_has_ranger());
  EXPECT_EQ(status.video(), "127.0.0.1:" + std::to_string(video_port_));
  EXPECT_EQ(status.fetch_timeout_ms(), 1500u);
}

// A TCP port where nothing listens: a socket bound to it but not listening, so a connection
// to it is refused for as long as the socket is open.
class RefusingPort {
 public:
  RefusingPort() {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t length = sizeof address;
    if (fd_ >= 0 && ::bind(fd_, reinterpret_cast<sockaddr*>(&address), length) == 0 &&
        ::getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &length) == 0) {
      port_ = ntohs(address.sin_port);
    }
  }
  ~RefusingPort() {
    if (fd_ >= 0) ::close(fd_);
  }
  uint16_t port() const { return port_; }

 private:
  int fd_ = -1;
  uint16_t port_ = 0;
};

// The video server down: a Locate is answered UNAVAILABLE at once, naming the video server
// and why. The fetch timeout (20 s) is far past the caller's own (2 s), so an answer that
// waited for either would come as the caller's TIMEOUT instead.
TEST(ObjectServerWithoutVideo, LocateIsUnavailableAtOnceNamingTheVideoServer) {
  RefusingPort video;
  ASSERT_NE(video.port(), 0);
  const std::string where = "127.0.0.1:" + std::to_string(video.port());
  Process object("igms-object-server", {"--name", "object", "--port", "0", "--set",
                                        "processes.video.port=" + std::to_string(video.port()),
                                        "--set", "processes.object.fetch_timeout_ms=20000", "--set",
                                        "lab.calibration=" + Calibration()});
  const uint16_t port = object.WaitPort();
  ASSERT_NE(port, 0) << object.Log();
  TestClient client(port);
  const site::Scene scene = site::DefaultTestbedScene();
  for (int attempt = 0; attempt < 3; ++attempt) {  // each one answered, none left to time out
    auto got =
        client->CallSync<LocateResponse>(kLocate, RequestFor(scene.objects[0].shape, 7, 1), 2s);
    EXPECT_EQ(got.status.code, igms::UNAVAILABLE) << got.status.ToString();
    EXPECT_NE(got.status.message.find("video server at " + where), std::string::npos)
        << got.status.message;
    EXPECT_NE(got.status.message.find("refused"), std::string::npos) << got.status.message;
    EXPECT_NE(got.status.message.find("frame 7"), std::string::npos) << got.status.message;
  }
  auto status =
      client->CallSync<StatusResponse>("igms.object.ObjectService.Status", StatusRequest(), 2s);
  ASSERT_TRUE(status.ok()) << status.status.ToString();
  EXPECT_FALSE(status.value.video_connected());
  EXPECT_EQ(status.value.video(), where);
  EXPECT_NE(status.value.video_detail().find("refused"), std::string::npos)
      << status.value.video_detail();
}

}  // namespace
}  // namespace igms::object
