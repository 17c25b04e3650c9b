// A whole operator session, timed: the lab on loopback (every server and daemon, simulated
// devices and site), igms-plan's session for every object of the default site, played by
// igms-control --script at the lab's own settings. Prints, per object:
//   - the session's time for it: from its `look` to its model stored (head turn, platform
//     move, freeze and grab, four pointer moves and marks, a range, the spoken type);
//   - spoken word to model: from the `say` of its type to "model N stored", as the control
//     client logs them;
//   - the baseline of the same run: the Locate call's round trip (the object server's work
//     and the network) from the model's provenance. The difference is what the session adds.
//
// Usage: bench_session [--objects NAME...] [--pointer-speed S]
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "bench/bench_main.h"
#include "common/stats/percentile.h"
#include "control/database/geometric_database.h"
#include "tests/support/child_process.h"
#include "tests/support/lab_on_loopback.h"

namespace {

using namespace std::chrono_literals;
using igms::stats::Percentile;
using igms::testing::BinDir;
using igms::testing::ChildProcess;
using igms::testing::LabOnLoopback;
using igms::testing::RunShell;
using igms::testing::ScratchDir;

// "2026-12-03 06:01:02.345 [control] [info] text": the time of day in ms, and the text.
bool ParseLine(const std::string& line, double* ms, std::string* text) {
  static const std::regex kLine(R"(^\S+ (\d+):(\d+):(\d+)\.(\d+) \[[^\]]*\] \[[a-z]+\] (.*)$)");
  std::smatch m;
  if (!std::regex_match(line, m, kLine)) return false;
  *ms = ((std::stod(m[1]) * 60 + std::stod(m[2])) * 60 + std::stod(m[3])) * 1000 +
        std::stod(m[4]) * std::pow(10.0, 3.0 - static_cast<double>(m[4].length()));
  *text = m[5];
  return true;
}

int RunBenchmark(int argc, char** argv) {
  setenv("IGMS_BIN_DIR", IGMS_BIN_DIR_DEFAULT, 0);
  setenv("IGMS_SOURCE_DIR", IGMS_SOURCE_DIR_DEFAULT, 0);
  std::string objects;
  std::string control_lines;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--pointer-speed" && i + 1 < argc) {
      control_lines = fmt::format("    pointer_speed: {}\n", argv[++i]);
    } else if (a == "--objects") {
      while (i + 1 < argc && argv[i + 1][0] != '-') objects += std::string(" ") + argv[++i];
    } else {
      std::fprintf(stderr, "usage: bench_session [--objects NAME...] [--pointer-speed S]\n");
      return 2;
    }
  }
  LabOnLoopback lab(control_lines);
  if (!lab.Start()) {
    std::fprintf(stderr, "bench_session: %s\n", lab.error().c_str());
    return 1;
  }
  ScratchDir dir;
  const std::string script = dir.File("session.yaml"), db = dir.File("igms.db");
  const auto plan = RunShell(BinDir() + "/igms-plan --config " + lab.file() + " --out " + script +
                             (objects.empty() ? "" : " --objects" + objects) + " 2>&1");
  if (plan.status != 0) {
    std::fprintf(stderr, "bench_session: igms-plan: %s\n", plan.out.c_str());
    return 1;
  }
  const auto start = std::chrono::steady_clock::now();
  ChildProcess control("igms-control",
                       {"--config", lab.file(), "--database", db, "--script", script});
  const int status = control.Wait(30min);
  const double session_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (status != 0) {
    std::fprintf(stderr, "bench_session: igms-control exited %d:\n%s\n", status,
                 control.Log().c_str());
    return 1;
  }

  // The log: each object's look, say and stored model, in order.
  struct Object {
    std::string type;
    double look_ms = -1, say_ms = -1, stored_ms = -1;
    int64_t model = 0;
  };
  std::vector<Object> seen;
  std::istringstream log(control.Log());
  static const std::regex kLook(R"(:\d+: look: )"), kSay(R"(:\d+: say: (\w+))"),
      kStored(R"(^model (\d+) stored in)");
  double pending_look = -1;
  for (std::string line; std::getline(log, line);) {
    double ms;
    std::string text;
    if (!ParseLine(line, &ms, &text)) continue;
    std::smatch m;
    if (std::regex_search(text, kLook)) {
      pending_look = ms;
    } else if (std::regex_search(text, m, kSay)) {
      seen.push_back({m[1], pending_look, ms, -1, 0});
    } else if (std::regex_search(text, m, kStored) && !seen.empty()) {
      seen.back().stored_ms = ms;
      seen.back().model = std::stoll(m[1]);
    }
  }
  auto opened = igms::control::GeometricDatabase::Open(db, {"bench_session", ""});
  if (!opened.ok()) {
    std::fprintf(stderr, "bench_session: %s\n", opened.error().c_str());
    return 1;
  }
  auto models = (*opened)->ListModels();
  std::map<int64_t, double> round_trip;
  if (models.ok()) {
    for (const auto& m : *models) round_trip[m.id] = m.record.provenance.round_trip_ms;
  }

  std::printf("%-4s %-9s %14s %18s %16s %14s\n", "obj", "type", "session s", "word to model ms",
              "Locate rtt ms", "session adds");
  std::vector<double> per_object, word, rtt, added;
  for (size_t i = 0; i < seen.size(); ++i) {
    const Object& o = seen[i];
    if (o.stored_ms < 0) {
      std::printf("%-4zu %-9s (no model)\n", i, o.type.c_str());
      continue;
    }
    const double s = (o.stored_ms - o.look_ms) / 1000, w = o.stored_ms - o.say_ms;
    const double r = round_trip.count(o.model) ? round_trip[o.model] : 0;
    std::printf("%-4zu %-9s %14.2f %18.0f %16.0f %14.0f\n", i, o.type.c_str(), s, w, r, w - r);
    per_object.push_back(s);
    word.push_back(w);
    rtt.push_back(r);
    added.push_back(w - r);
  }
  if (per_object.empty()) return 1;
  std::printf("%-14s %14.2f %18.0f %16.0f %14.0f\n", "median", Percentile(per_object, 0.5),
              Percentile(word, 0.5), Percentile(rtt, 0.5), Percentile(added, 0.5));
  std::printf("%-14s %14.2f %18.0f %16.0f %14.0f\n", "max", Percentile(per_object, 1),
              Percentile(word, 1), Percentile(rtt, 1), Percentile(added, 1));
  std::printf("whole session: %.1f s for %zu models (%.1f s per object, start included)\n",
              session_s, per_object.size(), session_s / static_cast<double>(per_object.size()));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return igms::bench::MainReportingFailures(argc, argv, RunBenchmark);
}
