#include "device_daemons/serial/recording.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <mutex>

#include "common/base/clock.h"
#include "tests/support/files.h"
#include "tests/support/wait_for.h"

namespace igms::devices {
namespace {

Reading Joy(uint64_t seq, int64_t t_ns, double x) {
  Reading r;
  r.mutable_joystick()->set_x(x);
  r.mutable_joystick()->mutable_stamp()->set_sequence(seq);
  r.mutable_joystick()->mutable_stamp()->set_receive_monotonic_ns(t_ns);
  return r;
}

TEST(Recording, RecordThenReplayReproducesValuesAndSpacing) {
  const std::string path = igms::testing::TempPath("rec");
  RecordingWriter writer;
  std::string error;
  ASSERT_TRUE(writer.Open(path, "joystick", &error)) << error;
  for (int i = 0; i < 10; ++i) ASSERT_TRUE(writer.Append(Joy(i + 1, i * 20'000'000LL, i * 0.1)));

  auto rec = LoadRecording(path);
  ASSERT_TRUE(rec.ok()) << rec.error();
  EXPECT_EQ(rec->header.device(), "joystick");
  ASSERT_EQ(rec->readings.size(), 10u);

  std::mutex mutex;
  std::vector<Reading> got;
  Replayer replayer(*rec, 2.0, false);  // twice as fast: 10 ms apart
  const int64_t start_ns = MonotonicNs();
  replayer.Start([&](const Reading& r) {
    std::lock_guard lock(mutex);
    got.push_back(r);
  });
  ASSERT_TRUE(igms::testing::WaitFor("the replay to finish", [&] { return replayer.finished(); }));
  ASSERT_EQ(got.size(), 10u);
  // 9 gaps of 10 ms, by the stamps the replayer put in its readings.
  EXPECT_GE(got.back().joystick().stamp().receive_monotonic_ns() - start_ns, 85'000'000);
  for (int i = 0; i < 10; ++i) {
    EXPECT_DOUBLE_EQ(got[i].joystick().x(), i * 0.1);
    EXPECT_EQ(got[i].joystick().stamp().sequence(), static_cast<uint64_t>(i) + 1);
  }
  std::filesystem::remove(path);
}

TEST(Recording, TornTailIsDroppedAndGarbageIsAnError) {
  const std::string path = igms::testing::TempPath("torn");
  {
    RecordingWriter writer;
    std::string error;
    ASSERT_TRUE(writer.Open(path, "joystick", &error));
    writer.Append(Joy(1, 0, 0.5));
    writer.Append(Joy(2, 1, 0.6));
  }
  std::filesystem::resize_file(path, std::filesystem::file_size(path) - 3);
  auto rec = LoadRecording(path);
  ASSERT_TRUE(rec.ok()) << rec.error();
  EXPECT_EQ(rec->readings.size(), 1u);

  std::ofstream(path, std::ios::trunc) << "this is not a recording at all";
  const auto not_recording = LoadRecording(path);
  EXPECT_FALSE(not_recording.ok());
  EXPECT_FALSE(not_recording.error().empty());
  EXPECT_FALSE(LoadRecording(path + ".missing").ok());
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace igms::devices
