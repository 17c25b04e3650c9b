// Declared keys: unknown ones are named with file, line and the likely intended key; values
// of the wrong type or out of their choices are problems; bound fields take flag over file
// over default; the log level comes from the flag, the process's own key, then lab.log_level.
#include "common/config/keys.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/config/lab_config.h"
#include "common/config/process_options.h"

namespace igms::config {
namespace {

const char* kLab = R"(lab:
  token: ""
  log_level: debug
  calibrashun: cal.yaml
processes:
  video:
    program: igms-video-server
    port: 7301
    edge_thread: 4
    edges:
      sigma: 1.5
      hihg: 100
  sound:
    whatever: 1
)";

Keys VideoLikeKeys() {
  Keys keys = CommonKeys();
  keys.Add("edge_threads", KeyType::kInt, "2", "threads");
  keys.Add("edges.sigma", KeyType::kNumber, "1.06", "sigma");
  keys.Add("edges.high", KeyType::kNumber, "150", "high threshold");
  keys.Choice("encoding", {"png", "raw"}, "png", "encoding");
  return keys;
}

std::vector<std::string> Texts(const std::vector<KeyProblem>& problems) {
  std::vector<std::string> texts;
  texts.reserve(problems.size());
  for (const auto& p : problems) texts.push_back(p.Text());
  return texts;
}

TEST(Keys, UnknownKeysAreNamedWithFileLineAndTheLikelyKey) {
  const auto config = LabConfig::FromString(kLab, "lab.yaml");
  const auto problems = Texts(UnknownKeys(config, "video", VideoLikeKeys()));
  // The sound section belongs to another program and is not judged here.
  EXPECT_EQ(problems, (std::vector<std::string>{
                          "lab.yaml:4: unknown key lab.calibrashun (did you mean lab.calibration?)",
                          "lab.yaml:9: unknown key processes.video.edge_thread (did you mean "
                          "processes.video.edge_threads?)",
                          "lab.yaml:12: unknown key processes.video.edges.hihg (did you mean "
                          "processes.video.edges.high?)",
                      }));
}

TEST(Keys, AKeyFarFromEveryDeclaredOneHasNoSuggestion) {
  const auto config =
      LabConfig::FromString("processes:\n  video:\n    colour_space: yuv\n", "f.yaml");
  const auto problems = Texts(UnknownKeys(config, "video", VideoLikeKeys()));
  EXPECT_EQ(problems,
            (std::vector<std::string>{"f.yaml:3: unknown key processes.video.colour_space"}));
}

TEST(Keys, WrongTypesAndChoicesAreProblems) {
  const auto config = LabConfig::FromString(
      "lab:\n  log_level: loud\nprocesses:\n  video:\n    edge_threads: many\n"
      "    encoding: jpeg\n    edges: {sigma: [1, 2]}\n",
      "bad.yaml");
  const auto problems = Texts(BadValues(config, "video", VideoLikeKeys(), false));
  EXPECT_EQ(problems,
            (std::vector<std::string>{
                "bad.yaml:2: lab.log_level must be one of trace, debug, info, warn, error, "
                "critical, off (found 'loud')",
                "bad.yaml:5: processes.video.edge_threads must be an integer (found 'many')",
                "bad.yaml:7: processes.video.edges.sigma must be a number",
                "bad.yaml:6: processes.video.encoding must be one of png, raw (found 'jpeg')",
            }));
}

TEST(Keys, PathKeysMustNameFilesThatExist) {
  const auto dir = std::filesystem::temp_directory_path() / "igms_keys_test";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "here.yaml") << "a: 1\n";
  std::ofstream(dir / "lab.yaml") << "lab:\n  calibration: here.yaml\n";
  EXPECT_TRUE(
      BadValues(LabConfig::Load((dir / "lab.yaml").string()), "x", CommonKeys(), true).empty());
  std::ofstream(dir / "lab.yaml") << "lab:\n  calibration: missing.yaml\n";
  const auto problems =
      Texts(BadValues(LabConfig::Load((dir / "lab.yaml").string()), "x", CommonKeys(), true));
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("lab.yaml:2: lab.calibration names "), std::string::npos)
      << problems[0];
  EXPECT_NE(problems[0].find("missing.yaml, which does not exist"), std::string::npos)
      << problems[0];
  std::filesystem::remove_all(dir);
}

// Runs ParseProcessOptions on a lab file with these extra arguments.
struct Parsed {
  std::optional<ProcessOptions> process;
  int exit_code = -1;
};

Parsed Parse(const std::string& lab_text, std::vector<std::string> args, const Keys& keys,
             const boost::program_options::options_description& extra =
                 boost::program_options::options_description("extra")) {
  const auto dir = std::filesystem::temp_directory_path() / "igms_keys_parse_test";
  std::filesystem::create_directories(dir);
  const std::string file = (dir / "lab.yaml").string();
  std::ofstream(file) << lab_text;
  args.insert(args.begin(), {"prog", "--config", file});
  std::vector<char*> argv;
  argv.reserve(args.size());
  for (auto& a : args) argv.push_back(a.data());
  Parsed parsed;
  parsed.process = ParseProcessOptions(static_cast<int>(argv.size()), argv.data(), "video", "test",
                                       extra, keys, &parsed.exit_code);
  std::filesystem::remove_all(dir);
  return parsed;
}

TEST(ProcessKeys, AnUnknownKeyStopsTheProcessUnlessAllowed) {
  const std::string lab = "processes:\n  video:\n    edge_thread: 4\n";
  Keys keys;
  keys.Add("edge_threads", KeyType::kInt, "2", "threads");
  Parsed refused = Parse(lab, {"--name", "video"}, keys);
  EXPECT_FALSE(refused.process);
  EXPECT_EQ(refused.exit_code, 2);
  Parsed allowed = Parse(lab, {"--name", "video", "--allow-unknown-keys"}, keys);
  ASSERT_TRUE(allowed.process);
  EXPECT_EQ(allowed.exit_code, 0);
  // Another process's section is not this process's business.
  Parsed other = Parse(lab, {"--name", "object"}, keys);
  EXPECT_TRUE(other.process);
  // A --set that names no key is refused like a key in the file.
  Parsed set = Parse("processes: {}\n", {"--set", "processes.video.edge_thread=4"}, keys);
  EXPECT_FALSE(set.process);
  EXPECT_EQ(set.exit_code, 2);
}

TEST(ProcessKeys, BoundFieldsTakeTheFlagOverTheFileOverTheDefault) {
  namespace po = boost::program_options;
  double poll_hz = 50;
  bool stream = false;
  std::string path = "default";
  Keys keys;
  keys.Bind("poll_hz", &poll_hz, "rate", "poll-hz");
  keys.Bind("stream", &stream, "stream", "stream");
  keys.Bind("path", &path, "path");
  po::options_description extra("extra");
  extra.add_options()("poll-hz", po::value<double>(), "rate")("stream", po::bool_switch(),
                                                              "stream");
  const std::string lab = "processes:\n  video: {poll_hz: 20, stream: true}\n";
  ASSERT_TRUE(Parse(lab, {"--name", "video"}, keys, extra).process);
  EXPECT_EQ(poll_hz, 20);
  EXPECT_TRUE(stream);
  EXPECT_EQ(path, "default");
  ASSERT_TRUE(Parse(lab, {"--name", "video", "--poll-hz", "5"}, keys, extra).process);
  EXPECT_EQ(poll_hz, 5);
  EXPECT_EQ(Parse("processes:\n  video: {poll_hz: fast}\n", {}, keys, extra).exit_code, 2);
}

TEST(ProcessKeys, BoundPathsChoicesAndLists) {
  namespace po = boost::program_options;
  std::string bank, record, backend = "files";
  std::vector<double> pose;
  Keys keys;
  keys.BindPath("bank", &bank, "sounds", "bank");
  keys.BindPath("record", &record, "written", "", KeyType::kOutputPath);
  keys.BindChoice("backend", &backend, {"files", "camera"}, "where from");
  keys.Bind("pose", &pose, "x y z", "pose");
  EXPECT_EQ(keys.Find("pose")->type, KeyType::kList);
  EXPECT_EQ(keys.Find("backend")->default_value, "files");
  po::options_description extra("extra");
  extra.add_options()("bank", po::value<std::string>(), "")("pose", po::value<std::string>(), "");
  const std::string lab =
      "processes:\n  video: {bank: b/bank.yaml, record: /tmp/r.log, backend: camera, "
      "pose: [1, 2.5]}\n";
  ASSERT_TRUE(Parse(lab, {}, keys, extra).process);
  // Relative to the file's folder; the flag's as given.
  EXPECT_EQ(bank, (std::filesystem::temp_directory_path() / "igms_keys_parse_test/b/bank.yaml")
                      .lexically_normal()
                      .string());
  EXPECT_EQ(record, "/tmp/r.log");
  EXPECT_EQ(backend, "camera");
  EXPECT_EQ(pose, (std::vector<double>{1, 2.5}));
  ASSERT_TRUE(Parse(lab, {"--bank", "here.yaml", "--pose", "3, 4 5"}, keys, extra).process);
  EXPECT_EQ(bank, "here.yaml");
  EXPECT_EQ(pose, (std::vector<double>{3, 4, 5}));
  EXPECT_EQ(Parse("processes:\n  video: {backend: tape}\n", {}, keys, extra).exit_code, 2);
  EXPECT_EQ(Parse("processes:\n  video: {pose: 3}\n", {}, keys, extra).exit_code, 2);
  EXPECT_EQ(Parse(lab, {"--pose", "3 x"}, keys, extra).exit_code, 2);
}

TEST(ProcessKeys, TheLogLevelIsTheFlagsThenTheProcesssThenTheLabs) {
  const Keys none;
  const std::string lab_only = "lab: {log_level: debug}\nprocesses:\n  video: {port: 1}\n";
  const std::string both = "lab: {log_level: debug}\nprocesses:\n  video: {log_level: warn}\n";
  EXPECT_EQ(Parse(lab_only, {}, none).process->log_level, "debug");
  EXPECT_EQ(Parse(both, {}, none).process->log_level, "warn");
  EXPECT_EQ(Parse(both, {"--log-level", "error"}, none).process->log_level, "error");
  EXPECT_EQ(Parse("processes: {}\n", {}, none).process->log_level, "info");
}

TEST(ProcessKeys, TheSharedKeysAreReadIntoLabAndEntry) {
  const Keys none;
  const std::string lab =
      "lab: {token: t0k, tls: 'off', certs: keys, calibration: cal/thesis.yaml, "
      "database: ~/models/igms.db}\n"
      "processes:\n  video: {program: igms-video-server, host: 10.0.0.2, bind: 0.0.0.0}\n";
  const Parsed parsed = Parse(lab, {}, none);
  ASSERT_TRUE(parsed.process);
  const ProcessOptions& p = *parsed.process;
  const auto folder = std::filesystem::temp_directory_path() / "igms_keys_parse_test";
  EXPECT_EQ(p.lab.token, "t0k");
  EXPECT_EQ(p.lab.tls, "off");
  // Paths beside the lab file; the database as written ("~/" is the home's, resolved later).
  EXPECT_EQ(p.lab.calibration, (folder / "cal/thesis.yaml").lexically_normal().string());
  EXPECT_EQ(p.lab.certs, (folder / "keys").lexically_normal().string());
  EXPECT_EQ(p.lab.database, "~/models/igms.db");
  EXPECT_EQ(p.entry.program, "igms-video-server");
  EXPECT_EQ(p.entry.host, "10.0.0.2");
  EXPECT_EQ(p.entry.bind, "0.0.0.0");
  // No port in the file: the program's own.
  EXPECT_FALSE(p.entry.port.has_value());
  EXPECT_EQ(p.Port(7301), 7301);
  // --port is a shorthand for the key.
  const Parsed flagged = Parse(lab, {"--port", "7400"}, none);
  ASSERT_TRUE(flagged.process);
  EXPECT_EQ(flagged.process->Port(7301), 7400);
  const Parsed far = Parse("processes:\n  video: {port: 70000}\n", {}, none);
  ASSERT_TRUE(far.process);
  EXPECT_THROW(far.process->Port(7301), ConfigError);

  // A tool that reads the file without being one of its processes reads the same keys.
  const LabOptions alone = LabOptionsOf(LabConfig::FromString(lab, "lab.yaml"));
  EXPECT_EQ(alone.token, "t0k");
  EXPECT_EQ(alone.database, "~/models/igms.db");
  EXPECT_EQ(alone.log_level, "info");
}

TEST(ProcessKeys, CheckConfigMarksTheProcessAndNeedsAFile) {
  const Keys none;
  Parsed check = Parse("processes:\n  video: {port: 1}\n", {"--check-config"}, none);
  ASSERT_TRUE(check.process);
  EXPECT_TRUE(check.process->check_only);
  Parsed missing = Parse("processes:\n  sound: {port: 1}\n", {"--check-config"}, none);
  EXPECT_FALSE(missing.process) << "no processes.video to check";
  EXPECT_EQ(missing.exit_code, 2);
}

}  // namespace
}  // namespace igms::config
