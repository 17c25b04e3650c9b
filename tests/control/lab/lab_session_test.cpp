// The operator's session end to end: the whole lab as real processes on loopback (simulated
// devices and site), a session planned by igms-plan and played by igms-control through the
// device simulators' serial lines, then the database read back and checked against the truth
// (igms-truth-table) and against the object server itself (each stored model located again
// from its own provenance).
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <chrono>
#include <set>

#include "common/calibration/calibration_file.h"
#include "common/calibration/calibration_hash.h"
#include "control/database/geometric_database.h"
#include "igms/devices.pb.h"
#include "igms/object.pb.h"
#include "tests/support/child_process.h"
#include "tests/support/lab_on_loopback.h"
#include "tests/support/wait_for.h"

namespace igms::testing {
namespace {

using namespace std::chrono_literals;

Eigen::Vector3d V(const object::Vec3& v) { return {v.x(), v.y(), v.z()}; }

// Another client commanding the platform: refused while a session holds control.
net::Status MoveAsIntruder(const LabOnLoopback& lab) {
  TestClient intruder(lab.port("platform"), "intruder");
  devices::SetOrientationRequest set;
  set.set_yaw_ticks(1);
  return intruder
      ->CallSync<devices::SetOrientationResponse>("igms.devices.PlatformService.SetOrientation",
                                                  set, 5s)
      .status;
}

std::string PlatformController(const LabOnLoopback& lab) {
  TestClient reader(lab.port("platform"), "reader");
  return reader
      ->CallSync<devices::LinkStatus>("igms.devices.PlatformService.Status",
                                      devices::GetStatusRequest(), 5s)
      .value.controller();
}

// The planner's script for these objects of the simulated site.
std::string Plan(const LabOnLoopback& lab, const std::string& objects, const std::string& out) {
  // No names: every cylinder and box of the site.
  const ShellRun plan =
      RunShell(BinDir() + "/igms-plan --config " + lab.file() +
               (objects.empty() ? "" : " --objects " + objects) + " --out " + out + " 2>&1");
  EXPECT_EQ(plan.status, 0) << plan.out;
  return plan.out;
}

TEST(LabSession, PlannedSessionModelsEveryObjectWithItsProvenance) {
  // A faster pointer: the session is the same, only shorter.
  LabOnLoopback lab("    pointer_speed: 12\n");
  ASSERT_TRUE(lab.Start()) << lab.error();
  ScratchDir dir;
  const std::string script = dir.File("session.yaml"), db = dir.File("igms.db");
  Plan(lab, "", script);

  ChildProcess control("igms-control",
                       {"--config", lab.file(), "--database", db, "--script", script});
  // The object server dies after the first model and comes back on its port: the session
  // hears it go and return, and models the second object with the new one.
  ASSERT_TRUE(control.WaitForLog("stored in", 120s)) << control.Log();
  lab.Kill("object");
  ASSERT_TRUE(control.WaitForLog("lost object (127.0.0.1:", 30s)) << control.Log();
  ASSERT_TRUE(lab.Restart("object")) << lab.error();
  ASSERT_EQ(control.Wait(180s), 0) << control.Log();

  // Every object of the site is modelled, close to its truth.
  const ShellRun table = RunShell(BinDir() + "/igms-truth-table --config " + lab.file() +
                                  " --database " + db + " --require-all 2>&1");
  EXPECT_EQ(table.status, 0) << table.out;

  auto opened = control::GeometricDatabase::Open(db, {"lab_session_test", ""});
  ASSERT_TRUE(opened.ok()) << opened.error();
  auto models = (*opened)->ListModels();
  ASSERT_TRUE(models.ok()) << models.error();
  ASSERT_EQ(models->size(), 7u);  // the default site: five cylinders, two boxes
  std::set<int> types;
  for (const auto& m : *models) types.insert(m.record.type);
  EXPECT_EQ(types, (std::set<int>{object::OBJECT_TYPE_CYLINDER, object::OBJECT_TYPE_BOX}));

  const auto calibration = calibration::LoadCalibration(ThesisCalibration());
  ASSERT_TRUE(calibration.ok()) << calibration.error();
  TestClient object(lab.port("object"));
  for (const auto& m : *models) {
    const auto& p = m.record.provenance;
    SCOPED_TRACE("model " + std::to_string(m.id));
    EXPECT_TRUE(m.present);
    EXPECT_NE(p.frame_id, 0u);
    EXPECT_GT(p.left_capture_unix_ns, 0);
    EXPECT_GT(p.right_capture_unix_ns, 0);
    ASSERT_EQ(p.marks.size(), 4u);
    // The planner takes a range once the marks are in; the object server reports on it.
    EXPECT_GT(p.range, 0);
    EXPECT_TRUE(p.range_report.has_value());
    EXPECT_EQ(p.calibration_hash, calibration::CalibrationHash(*calibration));
    std::set<std::string> servers;
    for (const auto& s : p.servers) servers.insert(s.name + "=" + s.program);
    EXPECT_TRUE(servers.count("video=igms-video-server")) << p.servers.size();
    EXPECT_TRUE(servers.count("object=igms-object-server")) << p.servers.size();
    EXPECT_GT(p.locate_ms, 0);

    // The provenance is enough to make the model again: the same frame (still in the video
    // server's store), marks and range give the same model.
    object::LocateRequest again;
    again.set_type(m.record.type);
    again.set_frame_id(p.frame_id);
    again.set_range(p.range);
    for (const auto& mark : p.marks) *again.add_marks() = mark;
    auto got =
        object->CallSync<object::LocateResponse>("igms.object.ObjectService.Locate", again, 60s);
    ASSERT_TRUE(got.ok()) << got.status.message;
    ASSERT_TRUE(got.value.found()) << got.value.detail();
    if (m.record.type == object::OBJECT_TYPE_CYLINDER) {
      EXPECT_LT((V(got.value.cylinder().center()) - V(m.record.cylinder.center())).norm(), 0.01);
      EXPECT_NEAR(got.value.cylinder().radius(), m.record.cylinder.radius(), 0.01);
      EXPECT_NEAR(got.value.cylinder().height(), m.record.cylinder.height(), 0.01);
    } else {
      EXPECT_LT((V(got.value.box().center()) - V(m.record.box.center())).norm(), 0.01);
      EXPECT_LT((V(got.value.box().size()) - V(m.record.box.size())).norm(), 0.01);
    }
  }
}

TEST(LabSession, KilledClientLosesNoModelAndTheNextContinuesItsDatabase) {
  // The client also keeps every export format current (export_dir, beside the lab file).
  LabOnLoopback lab("    pointer_speed: 12\n    export_dir: exports\n");
  ASSERT_TRUE(lab.Start()) << lab.error();
  ScratchDir dir;
  const std::string db = dir.File("igms.db");
  Plan(lab, "upright_1 lying_0", dir.File("first.yaml"));
  Plan(lab, "upright_2", dir.File("second.yaml"));
  {
    // Killed (SIGKILL, as a pulled plug) the moment the first model is stored.
    ChildProcess control("igms-control", {"--config", lab.file(), "--database", db, "--script",
                                          dir.File("first.yaml")});
    ASSERT_TRUE(control.WaitForLog("stored in", 120s)) << control.Log();
    // The session holds the platform: another client is refused, the holder named.
    const net::Status refused = MoveAsIntruder(lab);
    EXPECT_EQ(refused.code, igms::PERMISSION_DENIED) << refused.ToString();
    EXPECT_NE(refused.message.find("controlled by control at 127.0.0.1:"), std::string::npos)
        << refused.message;
    control.Kill();
    control.Wait();
  }
  // The killed client's connection closed with it: the next session gets control, and
  // gets it again from a platform daemon restarted under it.
  ChildProcess next("igms-control", {"--config", lab.file(), "--database", db, "--script",
                                     dir.File("second.yaml")});
  ASSERT_TRUE(WaitFor(
      "the next session in control",
      [&] { return PlatformController(lab).starts_with("control at"); }, 60s))
      << next.Log();
  lab.Kill("platform");
  ASSERT_TRUE(next.WaitForLog("lost platform (127.0.0.1:", 30s)) << next.Log();
  ASSERT_TRUE(lab.Restart("platform")) << lab.error();
  ASSERT_TRUE(WaitFor(
      "control of the restarted platform",
      [&] { return PlatformController(lab).starts_with("control at"); }, 60s))
      << next.Log();
  ASSERT_EQ(next.Wait(180s), 0) << next.Log();
  EXPECT_EQ(next.Log().find("does not obey this session"), std::string::npos) << next.Log();

  auto opened = control::GeometricDatabase::Open(db, {"lab_session_test", ""});
  ASSERT_TRUE(opened.ok()) << opened.error();
  auto models = (*opened)->ListModels();
  ASSERT_TRUE(models.ok()) << models.error();
  ASSERT_GE(models->size(), 2u);  // the first session's model(s), and the second's
  auto sessions = (*opened)->Sessions();
  ASSERT_TRUE(sessions.ok()) << sessions.error();
  // Ours is the third: the killed one never closed, the second did.
  ASSERT_EQ(sessions->size(), 3u);
  EXPECT_FALSE((*sessions)[0].closed_unix_ns.has_value());
  EXPECT_TRUE((*sessions)[1].closed_unix_ns.has_value());
  EXPECT_EQ(models->back().session_id, (*sessions)[1].id);
  EXPECT_EQ(models->front().session_id, (*sessions)[0].id);

  // The exports hold every model of the database, both sessions' (written as the second
  // session started with the first's models, then as it added its own).
  EXPECT_NE(next.Log().find("exports: " + std::to_string(models->size()) + " models in"),
            std::string::npos)
      << next.Log();
  const ShellRun urdf = RunShell("cat " + lab.dir().File("exports/models.urdf"));
  for (const auto& m : *models) {
    EXPECT_NE(urdf.out.find("model_" + std::to_string(m.id) + "\""), std::string::npos) << urdf.out;
  }
  if (std::system("command -v check_urdf >/dev/null 2>&1") == 0) {
    const ShellRun checked =
        RunShell("check_urdf " + lab.dir().File("exports/models.urdf") + " 2>&1");
    EXPECT_EQ(checked.status, 0) << checked.out;
  }
}

TEST(LabSession, TheRecogniserHearsTheSpokenTypes) {
  // The voice daemon listens through its recogniser, not a simulated Dragon: each `say` is
  // spoken by espeak-ng and must really be decoded (the wav is a moment of silence that
  // starts it listening).
  ScratchDir dir;
  const std::string silence = dir.File("silence.wav");
  ASSERT_EQ(RunShell("sox -n -r 16000 -c 1 -b 16 " + silence + " trim 0 0.2 2>&1").status, 0);
  LabOnLoopback lab("    pointer_speed: 12\n");
  // espeak-ng's en-us "cylinder" scores 0.16 against the untrained model's default floor of
  // 0.2 (docs/voice.md: enrol every operator); this lab takes it at 0.1.
  lab.Set("voice", "", {"--wav", silence, "--wav-interval-ms", "0", "--min-confidence", "0.1"});
  ASSERT_TRUE(lab.Start()) << lab.error();
  const std::string db = dir.File("igms.db");
  Plan(lab, "upright_1 box_1", dir.File("session.yaml"));
  ChildProcess control("igms-control", {"--config", lab.file(), "--database", db, "--script",
                                        dir.File("session.yaml")});
  ASSERT_EQ(control.Wait(180s), 0) << control.Log() << lab.process("voice").Log();
  const ShellRun table =
      RunShell(BinDir() + "/igms-truth-table --config " + lab.file() + " --database " + db +
               " --objects upright_1 box_1 --require-all 2>&1");
  EXPECT_EQ(table.status, 0) << table.out;
  // The words went through the recogniser.
  EXPECT_NE(lab.process("voice").Log().find("cylinder"), std::string::npos)
      << lab.process("voice").Log();
}

TEST(LabSession, MissingRequiredPeerIsNamedWithItsAddress) {
  // Nothing started: the lab file names ports where no one listens.
  LabOnLoopback lab("    call_timeout_ms: 300\n");
  lab.WriteWithoutStarting();
  ChildProcess control("igms-control",
                       {"--config", lab.file(), "--database", lab.dir().File("igms.db")});
  EXPECT_EQ(control.Wait(60s), 1) << control.Log();
  EXPECT_NE(control.Log().find("video"), std::string::npos) << control.Log();
  EXPECT_NE(control.Log().find("127.0.0.1:"), std::string::npos) << control.Log();
}

TEST(LabSession, ScriptErrorNamesItsLineAndStartsNothing) {
  LabOnLoopback lab;
  lab.WriteWithoutStarting();
  const std::string script = lab.dir().File("bad.yaml");
  RunShell("printf -- '- look: {yaw: 0}\\n- jump: 3\\n' > " + script);
  ChildProcess control("igms-control", {"--config", lab.file(), "--database",
                                        lab.dir().File("igms.db"), "--script", script});
  EXPECT_EQ(control.Wait(30s), 2) << control.Log();
  EXPECT_NE(control.Log().find("bad.yaml:2"), std::string::npos) << control.Log();
}

}  // namespace
}  // namespace igms::testing
