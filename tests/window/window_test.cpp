// The control client's window: a real GLFW window under a virtual X server (xvfb-run), and
// the same drawing offscreen. Its screenshots are PNG files whose pixels show the models
// where the cameras' matrices put them, the video through the black, and each stereo
// layout; the session's view becomes the right draw list; the keys are the session's
// commands.
#include "control/window/window.h"

#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thread>

#include "common/calibration/thesis_calibration.h"
#include "common/geometry/platform.h"
#include "control/database/geometric_database.h"
#include "control/window/keys.h"
#include "control/window/view_from_session.h"
#include "control/window/window_loop.h"
#include "tests/support/child_process.h"
#include "tests/support/wait_for.h"

namespace igms::control {
namespace {

const calibration::StereoCalibration& Cal() { return calibration::ThesisCalibration(); }

SessionModel Cylinder(uint64_t id) {
  SessionModel m;
  m.id = id;
  m.type = object::OBJECT_TYPE_CYLINDER;
  auto* c = m.cylinder.mutable_center();
  c->set_x(21);
  c->set_y(-48);
  c->set_z(3);
  m.cylinder.mutable_axis()->set_z(1);
  m.cylinder.set_radius(1.5);
  m.cylinder.set_height(6);
  return m;
}

SessionView Verification() {
  SessionView view;
  view.mode = Mode::kVerification;
  for (bool& up : view.peer_up) up = true;
  view.models.push_back(Cylinder(1));
  return view;
}

StereoFrame GreyFrame(int level) {
  StereoFrame f;
  f.left = cv::Mat(480, 512, CV_8UC1, cv::Scalar(level));
  f.right = cv::Mat(480, 512, CV_8UC1, cv::Scalar(level));
  f.sequence = 7;
  f.joints = {0, 0, 0};
  return f;
}

cv::Point Pixel(const geometry::Matrix34& P, const Eigen::Vector3d& X) {
  const auto p = geometry::ProjectiveCamera(P, {512, 480}).Project(X);
  return {static_cast<int>(std::lround(p->x())), static_cast<int>(std::lround(p->y()))};
}

bool IsPng(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  return std::string(magic, 8) == std::string("\x89PNG\r\n\x1a\n", 8);
}

bool Greenish(const cv::Vec3b& bgr) { return bgr[1] > 120 && bgr[1] > bgr[2] + 60; }

// Checks a side-by-side screenshot: the model in both eyes where P says, video elsewhere.
void ExpectSideBySide(const cv::Mat& shot) {
  ASSERT_EQ(shot.cols, 1024);
  ASSERT_EQ(shot.rows, 480);
  const Eigen::Vector3d centre(21, -48, 3);
  const cv::Point left = Pixel(Cal().left.P, centre);
  const cv::Point right = Pixel(Cal().right.P, centre) + cv::Point(512, 0);
  EXPECT_TRUE(Greenish(shot.at<cv::Vec3b>(left))) << shot.at<cv::Vec3b>(left);
  EXPECT_TRUE(Greenish(shot.at<cv::Vec3b>(right))) << shot.at<cv::Vec3b>(right);
  // Far from the model and the HUD, the video's grey shows through.
  EXPECT_EQ(shot.at<cv::Vec3b>(470, 500), cv::Vec3b(90, 90, 90));
  EXPECT_EQ(shot.at<cv::Vec3b>(470, 1010), cv::Vec3b(90, 90, 90));
}

TEST(WindowKeys, KeysAndButtonsAreTheSessionsCommands) {
  EXPECT_EQ(MapKey(GLFW_KEY_F, 0).command, CommandKind::kFreeze);
  EXPECT_EQ(MapKey(GLFW_KEY_U, 0).command, CommandKind::kUnfreeze);
  EXPECT_EQ(MapKey(GLFW_KEY_SPACE, 0).command, CommandKind::kMark);
  EXPECT_EQ(MapKey(GLFW_KEY_C, 0).command, CommandKind::kIdentifyCylinder);
  EXPECT_EQ(MapKey(GLFW_KEY_B, 0).command, CommandKind::kIdentifyBox);
  EXPECT_EQ(MapKey(GLFW_KEY_W, 0).command, CommandKind::kToggleWireframe);
  EXPECT_EQ(MapKey(GLFW_KEY_Z, 0).command, CommandKind::kUndo);
  EXPECT_EQ(MapKey(GLFW_KEY_ESCAPE, 0).action, WindowAction::kQuit);
  EXPECT_EQ(MapKey(GLFW_KEY_LEFT, GLFW_MOD_SHIFT).offset, Eigen::Vector2i(-10, 0));
  EXPECT_EQ(MapKey(GLFW_KEY_Q, 0).action, WindowAction::kNone);
  const KeyAction click = MapMouseButton(GLFW_MOUSE_BUTTON_LEFT);
  EXPECT_EQ(click.command, CommandKind::kMark);
  EXPECT_EQ(click.source, CommandSource::kMouse);
  const PointerDrive d =
      DriveFromKeys([](int key) { return key == GLFW_KEY_L || key == GLFW_KEY_PAGE_UP; }, true, 5);
  EXPECT_EQ(d.right, 0.25);
  EXPECT_EQ(d.forward, 0.25);
  EXPECT_EQ(d.up, 0.0);
}

TEST(ViewFromSession, TheViewBecomesWhatIsDrawn) {
  SessionView view = Verification();
  view.models.push_back(Cylinder(2));
  view.models.back().removed = true;
  view.marks = {{1, 2, 3}};
  view.pointer = Eigen::Vector3d(4, 5, 6);
  view.notices.push_back({NoticeLevel::kWarning, "the ranger is lost", 1});
  view.peer_up[static_cast<int>(Peer::kRanger)] = false;
  ViewExtras extras;
  extras.frame = GreyFrame(90);
  extras.video_lost = true;
  auto list = ViewFromSession(view, Cal(), extras);
  EXPECT_EQ(list.models.size(), 1u) << "removed models are not drawn";
  EXPECT_TRUE(list.marks.empty()) << "marks only while frozen";
  EXPECT_FALSE(list.pointer);
  EXPECT_TRUE(list.eyes[0].P.isApprox(Cal().left.P, 1e-9))
      << "the zero pose: the calibration's matrix";
  EXPECT_NE(list.hud[0].text.find("verification"), std::string::npos);
  bool down = false, notice = false;
  for (const auto& l : list.hud) {
    down |= l.text.find("down: ranger") != std::string::npos;
    notice |= l.text == "the ranger is lost" && l.level == render::HudLevel::kWarning;
  }
  EXPECT_TRUE(down);
  EXPECT_TRUE(notice);
  EXPECT_FALSE(list.banner.empty());

  view.mode = Mode::kModelBuilding;
  view.frozen = FrozenView{};
  view.frozen->left_P = Cal().right.P;  // any other matrix: the grab's pose's
  view.frozen->right_P = Cal().left.P;
  list = ViewFromSession(view, Cal(), extras);
  EXPECT_EQ(list.eyes[0].P, Cal().right.P) << "frozen: the grab's cameras";
  EXPECT_EQ(list.marks.size(), 1u);
  EXPECT_TRUE(list.pointer);
}

TEST(Window, AWindowDrawsTheSessionAndItsScreenshotIsAPng) {
  WindowOptions options;
  options.vsync = false;
  auto window = Window::Open(Cal(), options);
  ASSERT_TRUE(window.ok()) << window.error();
  EXPECT_EQ((*window)->frame_size().width, 1024);
  (*window)->SetFrame(GreyFrame(90));
  igms::testing::ScratchDir dir;
  const std::string path = dir.File("shots/window.png");
  const auto input = (*window)->Poll(1);
  EXPECT_TRUE(input.commands.empty());
  EXPECT_FALSE(input.quit);
  ASSERT_TRUE((*window)->Draw(Verification(), path).ok());
  ASSERT_TRUE(IsPng(path));
  ExpectSideBySide(cv::imread(path, cv::IMREAD_COLOR));

  // Wireframe: the model's outline, the video inside it.
  SessionView wire = Verification();
  wire.wireframe = true;
  ASSERT_TRUE((*window)->Draw(wire, path).ok());
  const cv::Mat shot = cv::imread(path, cv::IMREAD_COLOR);
  EXPECT_EQ(shot.at<cv::Vec3b>(Pixel(Cal().left.P, {21, -48, 3})), cv::Vec3b(90, 90, 90));
}

TEST(Window, AnaglyphAndQuadBufferWindows) {
  WindowOptions options;
  options.vsync = false;
  options.stereo = render::StereoMode::kAnaglyph;
  {
    auto window = Window::Open(Cal(), options);
    ASSERT_TRUE(window.ok()) << window.error();
    EXPECT_EQ((*window)->frame_size().width, 512);
    StereoFrame f = GreyFrame(90);
    f.right = cv::Mat(480, 512, CV_8UC1, cv::Scalar(200));
    (*window)->SetFrame(f);
    igms::testing::ScratchDir dir;
    ASSERT_TRUE((*window)->Draw(Verification(), dir.File("a.png")).ok());
    const cv::Mat shot = cv::imread(dir.File("a.png"), cv::IMREAD_COLOR);
    EXPECT_EQ(shot.at<cv::Vec3b>(470, 500), cv::Vec3b(200, 200, 90));  // BGR: left in red
  }
  // Xvfb offers no stereo visual: a clear message and side by side.
  options.stereo = render::StereoMode::kQuadBuffer;
  auto window = Window::Open(Cal(), options);
  ASSERT_TRUE(window.ok()) << window.error();
  if ((*window)->stereo() != render::StereoMode::kQuadBuffer) {
    EXPECT_EQ((*window)->stereo(), render::StereoMode::kSideBySide);
    EXPECT_NE((*window)->notice().find("quad-buffer"), std::string::npos);
    EXPECT_EQ((*window)->frame_size().width, 1024);
  }
}

TEST(Window, OffscreenItDrawsTheSameWithoutADisplay) {
  WindowOptions options;
  options.offscreen = true;
  auto window = Window::Open(Cal(), options);
  ASSERT_TRUE(window.ok()) << window.error();
  (*window)->SetFrame(GreyFrame(90));
  igms::testing::ScratchDir dir;
  ASSERT_TRUE((*window)->Draw(Verification(), dir.File("off.png")).ok());
  ASSERT_TRUE(IsPng(dir.File("off.png")));
  ExpectSideBySide(cv::imread(dir.File("off.png"), cv::IMREAD_COLOR));
}

// The screenshots in `dir` named igms-every-*.png.
int PeriodicShots(const igms::testing::ScratchDir& dir) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.File(""))) {
    if (e.path().filename().string().rfind("igms-every-", 0) == 0) ++n;
  }
  return n;
}

// --screenshot-every: igms-control's display loop, with a session (no peers: it waits for
// them) and a real window or offscreen drawing, takes a screenshot every 0.2 s of wall clock.
void ExpectPeriodicScreenshots(bool offscreen) {
  ControlAppOptions app_options;
  app_options.session.wait_for_peers = true;
  auto app = ControlApp::Make(app_options, Cal(), nullptr);
  ASSERT_TRUE(app.ok()) << app.error();
  WindowOptions options;
  options.vsync = false;
  options.offscreen = offscreen;
  auto window = Window::Open(Cal(), options);
  ASSERT_TRUE(window.ok()) << window.error();
  igms::testing::ScratchDir dir;
  DisplayLoopOptions loop;
  loop.screenshot_folder = dir.File("");
  loop.screenshot_every_s = 0.2;
  int frames = 0;
  loop.on_frame = [&](const SessionView&, int64_t) { ++frames; };
  (*app)->Start();
  ScreenshotQueue shots;
  std::atomic<bool> stop = false;
  std::atomic<bool> three = false;
  const auto start = std::chrono::steady_clock::now();
  std::chrono::steady_clock::duration third{};
  std::thread watcher([&] {
    three =
        igms::testing::WaitUntil([&] { return PeriodicShots(dir) >= 3; }, std::chrono::seconds(20));
    third = std::chrono::steady_clock::now() - start;
    stop = true;
  });
  RunDisplayLoop(**app, **window, nullptr, shots, stop, loop, offscreen);
  watcher.join();
  ASSERT_TRUE(three) << "fewer than 3 periodic screenshots in 20 s";
  // Three periods at least: seconds, not frames (the window draws many frames a period).
  EXPECT_GE(third, std::chrono::milliseconds(600));
  if (!offscreen) {
    EXPECT_GT(frames, PeriodicShots(dir));
  }
  for (const char* name : {"igms-every-0001.png", "igms-every-0002.png", "igms-every-0003.png"}) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(IsPng(dir.File(name)));
    const cv::Mat shot = cv::imread(dir.File(name), cv::IMREAD_COLOR);
    EXPECT_EQ(shot.cols, 1024);
    EXPECT_EQ(shot.rows, 480);
  }
}

TEST(Window, ScreenshotEveryNSecondsFromTheDisplayLoop) { ExpectPeriodicScreenshots(false); }

TEST(Window, ScreenshotEveryNSecondsOffscreen) { ExpectPeriodicScreenshots(true); }

// A box as the locator stores it, whose texture patch is red on its pixels in the left image
// of a grab taken with the platform panned by `pan` rad, and blue around them.
ModelRecord TexturedBox(double pan) {
  ModelRecord r;
  r.type = object::OBJECT_TYPE_BOX;
  auto set = [](object::Vec3* v, double x, double y, double z) {
    v->set_x(x);
    v->set_y(y);
    v->set_z(z);
  };
  set(r.box.mutable_center(), 21, -48, 3);
  set(r.box.mutable_size(), 4, 4, 4);
  set(r.box.mutable_center_sigma(), 0.01, 0.01, 0.01);
  set(r.box.mutable_size_sigma(), 0.01, 0.01, 0.01);
  const std::vector<double> joints = {pan, 0, 0};
  const auto P = geometry::CameraAtPose(Cal().left.P, *Cal().platform, joints);
  std::vector<cv::Point> corners;
  corners.reserve(8);
  for (int i = 0; i < 8; ++i) {
    corners.push_back(
        Pixel(P, {21.0 + (i & 1 ? 2 : -2), -48.0 + (i & 2 ? 2 : -2), 3.0 + (i & 4 ? 2 : -2)}));
  }
  const cv::Rect rect = cv::boundingRect(corners) & cv::Rect(0, 0, 512, 480);
  r.box.set_texture_u0(rect.x);
  r.box.set_texture_v0(rect.y);
  r.box.set_texture_u1(rect.x + rect.width - 1);
  r.box.set_texture_v1(rect.y + rect.height - 1);
  // Red on the box's own pixels, blue around them: a patch placed through the wrong camera
  // shows blue on the box.
  cv::Mat patch(rect.height, rect.width, CV_8UC3, cv::Scalar(220, 30, 30));
  std::vector<cv::Point> hull;
  cv::convexHull(corners, hull);
  for (cv::Point& c : hull) c -= rect.tl();
  cv::fillConvexPoly(patch, hull, cv::Scalar(30, 30, 220));
  std::vector<uchar> png;
  cv::imencode(".png", patch, png);
  r.box.set_texture_png(std::string(png.begin(), png.end()));
  auto& p = r.provenance;
  p.frame_id = 9;
  p.left_capture_unix_ns = p.right_capture_unix_ns = 1;
  for (double j : joints) p.platform_pose.add_joints_rad(j);
  p.marks.resize(4);
  p.calibration_hash = "test";
  return r;
}

// The fraction of the left eye's pixels inside the box's outline (the platform at rest) that
// show the texture's red (or, with `blue`, its blue).
double ColourInBox(const cv::Mat& shot, bool blue) {
  std::vector<cv::Point> corners;
  corners.reserve(8);
  for (int i = 0; i < 8; ++i) {
    corners.push_back(Pixel(
        Cal().left.P, {21.0 + (i & 1 ? 2 : -2), -48.0 + (i & 2 ? 2 : -2), 3.0 + (i & 4 ? 2 : -2)}));
  }
  std::vector<cv::Point> hull;
  cv::convexHull(corners, hull);
  cv::Mat inside(480, 512, CV_8UC1, cv::Scalar(0));
  cv::fillConvexPoly(inside, hull, cv::Scalar(255));
  int red = 0, all = 0;
  for (int v = 0; v < 480; ++v) {
    for (int u = 0; u < 512; ++u) {
      if (!inside.at<uchar>(v, u)) continue;
      ++all;
      const cv::Vec3b& bgr = shot.at<cv::Vec3b>(v, u);
      const int hot = blue ? 0 : 2, cold = blue ? 2 : 0;
      if (bgr[hot] > 150 && bgr[1] < 90 && bgr[cold] < 90) ++red;
    }
  }
  return all ? static_cast<double>(red) / all : 0;
}

// A continued session (igms-control --database FILE) draws the texture patch each box was
// stored with, through the left camera of the grab it was taken from (the provenance's pose).
TEST(Window, AContinuedSessionDrawsTheBoxTextureItStored) {
  igms::testing::ScratchDir dir;
  const std::string db = dir.File("igms.db");
  {
    auto writer = GeometricDatabase::Open(db, {"window_test", ""});
    ASSERT_TRUE(writer.ok()) << writer.error();
    ASSERT_TRUE((*writer)->AddModel(TexturedBox(-0.15)).ok());
  }
  auto opened = GeometricDatabase::Open(db, {"window_test", ""});
  ASSERT_TRUE(opened.ok()) << opened.error();
  ControlAppOptions app_options;
  app_options.session.wait_for_peers = true;
  auto app = ControlApp::Make(app_options, Cal(), std::move(*opened));
  ASSERT_TRUE(app.ok()) << app.error();
  (*app)->Start();
  SessionView view;
  ASSERT_TRUE((*app)->board().WaitFor([](const SessionView& v) { return v.models.size() == 1; },
                                      std::chrono::seconds(10), &view));
  app->reset();
  ASSERT_FALSE(view.models[0].left_P_at_grab.isZero());

  WindowOptions options;
  options.offscreen = true;
  auto window = Window::Open(Cal(), options);
  ASSERT_TRUE(window.ok()) << window.error();
  (*window)->SetFrame(GreyFrame(90));
  const std::string path = dir.File("continued.png");
  ASSERT_TRUE((*window)->Draw(view, path).ok());
  ASSERT_TRUE(IsPng(path));
  const cv::Mat textured_shot = cv::imread(path, cv::IMREAD_COLOR);
  const double textured = ColourInBox(textured_shot, false);
  const double misplaced = ColourInBox(textured_shot, true);
  // Without the grab's camera the box would be flat: no red at all.
  view.models[0].left_P_at_grab.setZero();
  ASSERT_TRUE((*window)->Draw(view, path).ok());
  const double flat = ColourInBox(cv::imread(path, cv::IMREAD_COLOR), false);
  EXPECT_GT(textured, 0.8) << "misplaced " << misplaced << ", flat " << flat;
  EXPECT_LT(misplaced, 0.02) << "textured " << textured;  // the grab's camera, not today's
  EXPECT_EQ(flat, 0);
}

}  // namespace
}  // namespace igms::control
