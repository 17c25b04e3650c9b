// Enrolment: AdaptModel's refusals in-process, and igms-voice-adapt as a process on real
// recordings, its model then loaded by igms-voice-decode.
#include "device_daemons/voice/adaptation.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include "device_daemons/voice/command_language.h"
#include "device_daemons/voice/speech_synth.h"
#include "tests/device_daemons/voice/pulse_sink.h"
#include "tests/support/child_process.h"

namespace igms::voice {
namespace {

namespace fs = std::filesystem;

using Result = testing::ShellRun;

// Runs a shell command; its stderr joins stdout unless `log` is false (then it is dropped).
Result Exec(const std::string& command, bool log = true) {
  return testing::RunShell(command + (log ? " 2>&1" : " 2>/dev/null"));
}

std::string Bin(const char* name) { return testing::BinDir() + "/" + name; }

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

class AdaptationTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("igms_adapt_" + std::to_string(getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::vector<AdaptationUtterance> Commands(int copies) {
    std::vector<AdaptationUtterance> out;
    auto audio = Synthesize({"freeze", "en-us", 175});
    EXPECT_TRUE(audio.ok()) << audio.error();
    for (int i = 0; audio.ok() && i < copies; ++i) out.push_back({*audio, "freeze"});
    return out;
  }
  AdaptationOptions Options() {
    AdaptationOptions options;
    options.out_dir = (dir_ / "adapted").string();
    return options;
  }
  fs::path dir_;
};

TEST_F(AdaptationTest, RefusesWhatCannotBeAdaptedAndLeavesNoModel) {
  auto expect_refused = [&](const std::vector<AdaptationUtterance>& utterances,
                            const AdaptationOptions& options, const std::string& why) {
    const AdaptationReport report = AdaptModel(utterances, options);
    EXPECT_NE(report.error.find(why), std::string::npos) << report.error;
    EXPECT_FALSE(fs::exists(options.out_dir)) << why;
  };
  expect_refused(Commands(3), Options(), "at least 10 utterances");
  auto unknown = Commands(12);
  unknown[4].text = "freeze qxzvbn";
  expect_refused(unknown, Options(), "no pronunciation for 'qxzvbn'");
  // Capitals and punctuation are not words; an unknown word still is.
  auto punctuated = Commands(12);
  punctuated[5].text = "Freeze, qxzvbn!";
  expect_refused(punctuated, Options(), "no pronunciation for 'qxzvbn'");
  auto silent = Commands(12);
  silent[2].text = "  ";
  expect_refused(silent, Options(), "utterance 3 has no transcript");
  auto rate = Commands(12);
  rate[0].audio.sample_rate = 8000;
  expect_refused(rate, Options(), "utterance 1 is at 8000 Hz");
  AdaptationOptions no_tools = Options();
  no_tools.sphinxtrain_dir = (dir_ / "nowhere").string();
  expect_refused(Commands(12), no_tools, "sphinxtrain's bw is not in");
  AdaptationOptions no_model = Options();
  no_model.model_dir = (dir_ / "nowhere").string();
  expect_refused(Commands(12), no_model, "no acoustic model folder");
  // A model already in the destination survives a failed adaptation.
  fs::create_directories(dir_ / "adapted");
  std::ofstream(dir_ / "adapted/marker") << "previous model";
  EXPECT_FALSE(AdaptModel(unknown, Options()).ok());
  EXPECT_EQ(ReadAll(dir_ / "adapted/marker"), "previous model");
  AdaptationOptions in_place;
  in_place.out_dir = in_place.model_dir;
  EXPECT_NE(AdaptModel(Commands(12), in_place).error.find("must not replace"), std::string::npos);
}

TEST_F(AdaptationTest, TheToolAdaptsFromRecordingsAndTheDecoderUsesTheResult) {
  // Recordings of the prompts in one voice, listed as an operator's would be.
  const Result prompts = Exec(Bin("igms-voice-adapt") + " --print-prompts");
  ASSERT_EQ(prompts.status, 0);
  std::ofstream list(dir_ / "list.txt");
  std::istringstream lines(prompts.out);
  int n = 0;
  for (std::string line; std::getline(lines, line);) {
    const fs::path wav = dir_ / ("p" + std::to_string(++n) + ".wav");
    ASSERT_EQ(Exec("espeak-ng -v en-gb+m3 -s 160 -w " + wav.string() + " '" + line + "'").status,
              0);
    list << wav.string() << '\t' << line << '\n';
  }
  list.close();
  ASSERT_GE(n, 40);
  const fs::path out = dir_ / "model";
  // Written "DIR/", as a shell's completion leaves it.
  const Result adapt = Exec(Bin("igms-voice-adapt") + " --out " + out.string() + "/ --list " +
                            (dir_ / "list.txt").string());
  ASSERT_EQ(adapt.status, 0) << adapt.out;
  EXPECT_NE(adapt.out.find("adapted to " + std::to_string(n) + " utterances"), std::string::npos);
  // The means moved; the decoder loads the folder and hears a command with it.
  const std::string source = "/usr/share/pocketsphinx/model/en-us";
  ASSERT_TRUE(fs::exists(out / "en-us/means"));
  EXPECT_NE(ReadAll(out / "en-us/means"), ReadAll(source + "/en-us/means"));
  EXPECT_TRUE(fs::exists(out / "cmudict-en-us.dict"));
  // Its record makes it an adapted model, which brings the settings for enrolled operators;
  // the stock model is not one.
  EXPECT_NE(ReadAll(out / kAdaptationRecord).find("utterances: " + std::to_string(n)),
            std::string::npos);
  EXPECT_TRUE(IsAdaptedModel(out.string()));
  EXPECT_FALSE(IsAdaptedModel(source));
  EXPECT_EQ(RecognizerOptionsFor(out.string()).decoys.max_per_command, 15);
  EXPECT_EQ(RecognizerOptionsFor(out.string()).fillers.count, 10000);
  EXPECT_EQ(RecognizerOptionsFor(source).decoys.max_per_command, 0);
  EXPECT_EQ(RecognizerOptionsFor(source).fillers.count, 0);
  const fs::path freeze = dir_ / "freeze.wav";
  ASSERT_EQ(Exec("espeak-ng -v en-gb+m3 -s 150 -w " + freeze.string() + " freeze").status, 0);
  const Result decode = Exec(
      Bin("igms-voice-decode") + " --model-dir " + out.string() + " " + freeze.string(), false);
  EXPECT_EQ(decode.status, 0);
  EXPECT_EQ(decode.out, "01\n");
  const Result logged =
      Exec(Bin("igms-voice-decode") + " --model-dir " + out.string() + " " + freeze.string());
  EXPECT_NE(logged.out.find("15 decoys per command"), std::string::npos) << logged.out;
  EXPECT_NE(logged.out.find("10000 common words at 0.01"), std::string::npos) << logged.out;
  // Bad invocations: no source (2), a list naming a missing file (1), and the model the
  // first run wrote is still there afterwards.
  EXPECT_EQ(Exec(Bin("igms-voice-adapt") + " --out " + out.string()).status, 2);
  std::ofstream(dir_ / "bad.txt") << "/nonexistent.wav\tfreeze\n";
  EXPECT_EQ(Exec(Bin("igms-voice-adapt") + " --out " + out.string() + " --list " +
                 (dir_ / "bad.txt").string())
                .status,
            1);
  EXPECT_TRUE(fs::exists(out / "en-us/means"));
  // No capture device: a clear error and status 1, no hang.
  const Result no_microphone = Exec("ALSOFT_DRIVERS=null " + Bin("igms-voice-adapt") + " --out " +
                                    out.string() + " --record");
  EXPECT_EQ(no_microphone.status, 1) << no_microphone.out;
  EXPECT_TRUE(fs::exists(out / "en-us/means"));
}

// --record for real: the prompts (here the eleven commands, from --prompts) are said one
// after another into a PulseAudio null sink whose monitor is the capture device.
TEST_F(AdaptationTest, RecordsEachPromptFromTheMicrophone) {
  ASSERT_TRUE(testing::PulseSink::ToolsPresent()) << "deploy/install-deps.sh installs them";
  testing::PulseSink sink;
  ASSERT_TRUE(sink.WaitReady()) << sink.Log();
  std::vector<std::string> phrases;
  std::ofstream prompts(dir_ / "prompts.txt");
  for (const CommandInfo& info : AllCommands()) {
    phrases.emplace_back(info.phrase);
    prompts << info.phrase << '\n';
    const fs::path wav = dir_ / (std::to_string(phrases.size()) + ".wav");
    ASSERT_EQ(Exec("espeak-ng -v en-us+m3 -s 170 -w " + wav.string() + " '" +
                   std::string(info.phrase) + "'")
                  .status,
              0);
  }
  prompts.close();
  const fs::path out = dir_ / "recorded";
  testing::ChildProcess adapt("igms-voice-adapt", {"--out", out.string(), "--record", "--prompts",
                                                   (dir_ / "prompts.txt").string()});
  for (size_t i = 0; i < phrases.size(); ++i) {
    const std::string prompt =
        "[" + std::to_string(i + 1) + "/" + std::to_string(phrases.size()) + "] say: " + phrases[i];
    testing::WaitUntil(
        [&] { return adapt.Output().find(prompt) != std::string::npos || adapt.Exited(); },
        std::chrono::seconds(30), std::chrono::milliseconds(20));
    ASSERT_NE(adapt.Output().find(prompt), std::string::npos) << adapt.Output() << adapt.Log();
    ASSERT_TRUE(sink.Play((dir_ / (std::to_string(i + 1) + ".wav")).string())) << sink.Log();
  }
  ASSERT_EQ(adapt.Wait(std::chrono::seconds(120)), 0) << adapt.Output() << adapt.Log();
  EXPECT_NE(adapt.Log().find("adapted to 11 utterances"), std::string::npos) << adapt.Log();
  EXPECT_EQ(adapt.Output().find("nothing heard"), std::string::npos) << adapt.Output();
  EXPECT_TRUE(fs::exists(out / "en-us/means"));
}

}  // namespace
}  // namespace igms::voice
