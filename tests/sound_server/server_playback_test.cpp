// Every sound of the lab's bank, played through the real igms-sound-server process over
// TCP, comes out of OpenAL's wave output as generated: same audible length, level, shape.
// Real time: the bank is split over two tests (two CTest entries) to keep each short.
#include <gtest/gtest.h>

#include <functional>

#include "tests/sound_server/sound_checks.h"
#include "tests/support/sound_bank.h"
#include "tests/support/sound_server_process.h"
#include "tests/support/wait_for.h"

namespace igms::sound {
namespace {

using namespace std::chrono_literals;

void PlayEachAndCompare(const std::string& name,
                        const std::function<bool(const BankEntry&)>& pick) {
  const std::filesystem::path dir = igms::testing::FreshTempDir(name);
  const std::filesystem::path wave = dir / "capture.wav";
  // The default bank: ../share/igms/sounds next to the binary, as the build puts it.
  testing::ServerProcess server({"--output", "wave", "--wave-file", wave.string()});
  const uint16_t port = server.WaitListening();
  ASSERT_NE(port, 0) << server.Log();
  testing::SoundClient client(port);
  net::Result<ListBankResponse> bank =
      client.Call<ListBankResponse>(kListBankMethod, ListBankRequest());
  ASSERT_TRUE(bank.ok()) << bank.status.ToString();
  net::Result<StatusResponse> status = client.Status();
  ASSERT_TRUE(status.ok() && status.value.sample_rate() > 0) << status.status.ToString();
  // 0.3 s of the output's own clock (its sample count in the file): a gap between sounds,
  // and what was mixed before it, the writer's buffer included, is in the file.
  const int64_t gap = status.value.sample_rate() * 3 / 10;
  struct Played {
    BankEntry entry;
    int64_t from = 0, to = 0;  // capture frames
  };
  std::vector<Played> played;
  for (const BankEntry& entry : bank.value.sounds()) {
    if (!pick(entry)) continue;
    ASSERT_TRUE(entry.available()) << entry.key() << ": " << entry.error();
    if (!played.empty()) played.back().to = CapturedFrames(wave);
    played.push_back({entry, CapturedFrames(wave), 0});
    net::Result<PlayResponse> r = client.Play(entry.key());
    ASSERT_TRUE(r.ok()) << entry.key() << ": " << r.status.ToString();
    EXPECT_EQ(r.value.id(), entry.id());
    EXPECT_FALSE(r.value.queued());
    ASSERT_TRUE(client.WaitIdle()) << entry.key();
    const int64_t target = CapturedFrames(wave) + gap;
    ASSERT_TRUE(igms::testing::WaitFor("the gap after " + entry.key(),
                                       [&] { return CapturedFrames(wave) >= target; }));
  }
  ASSERT_FALSE(played.empty());
  played.back().to = CapturedFrames(wave);
  EXPECT_EQ(server.Terminate(), 0) << server.Log();
  std::optional<Capture> capture = ReadCapture(wave);
  ASSERT_TRUE(capture);
  const std::filesystem::path folder = std::filesystem::path(bank.value.manifest()).parent_path();
  Result<Manifest> manifest = LoadManifest(bank.value.manifest());
  ASSERT_TRUE(manifest.ok()) << manifest.error();
  for (const Played& p : played) {
    Result<AudioClip> source = ReadAudioFile(manifest->FileOf(*manifest->FindId(p.entry.id())));
    ASSERT_TRUE(source.ok()) << source.error();
    ASSERT_EQ(source->sample_rate, capture->sample_rate);
    const std::vector<int16_t> window(
        capture->samples.begin() + p.from,
        capture->samples.begin() +
            std::min<int64_t>(p.to, static_cast<int64_t>(capture->samples.size())));
    testing::ExpectSameSound(window, *source, 1.0, p.entry.key());
  }
  std::filesystem::remove_all(dir);
}

TEST(ServerPlayback, CuesAndTheThesisMessages) {
  int count = 0;
  PlayEachAndCompare("cues", [&](const BankEntry& e) {
    const bool pick = e.kind() == CUE || e.id() < 40;
    count += pick ? 1 : 0;
    return pick;
  });
  EXPECT_EQ(count, 18);  // tables 2.5 and 2.6, unmark and no_echo
}

TEST(ServerPlayback, FailureAndHealthMessages) {
  int count = 0;
  PlayEachAndCompare("messages", [&](const BankEntry& e) {
    const bool pick = e.kind() == SPEECH && e.id() >= 40;
    count += pick ? 1 : 0;
    return pick;
  });
  EXPECT_EQ(count, 16);  // twelve failure reasons, four health messages
}

}  // namespace
}  // namespace igms::sound
