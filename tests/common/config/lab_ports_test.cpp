// The one port table (common/config/lab_ports.h) against what the lab and its readers are
// told: deploy/lab.yaml, the port table in docs/configuration.md, and every 73xx port in the
// docs and the README.
#include "common/config/lab_ports.h"

#include <gtest/gtest.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <string>
#include <vector>

#include "common/config/lab_config.h"

namespace igms::config {
namespace {

namespace fs = std::filesystem;

fs::path SourceDir() { return std::getenv("IGMS_SOURCE_DIR"); }

// "joystick" -> "JoystickService"
std::string ServiceOf(const std::string& process) {
  std::string s = process;
  s[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(s[0])));
  return s + "Service";
}

struct Line {
  std::string where;  // "docs/x.md:12"
  std::string text;
};

std::vector<Line> DocLines() {
  std::vector<fs::path> files = {SourceDir() / "README.md"};
  for (const auto& entry : fs::directory_iterator(SourceDir() / "docs")) {
    if (entry.path().extension() == ".md") files.push_back(entry.path());
  }
  std::vector<Line> lines;
  for (const auto& file : files) {
    std::ifstream in(file);
    std::string text;
    for (int n = 1; std::getline(in, text); ++n) {
      lines.push_back({fs::relative(file, SourceDir()).string() + ":" + std::to_string(n), text});
    }
  }
  return lines;
}

TEST(LabPorts, EveryProcessHasItsOwnPort) {
  std::set<int> seen;
  for (const auto& p : ports::kLabPorts) EXPECT_TRUE(seen.insert(p.port).second) << p.process;
}

TEST(LabPorts, TheLabFileGivesEveryProcessItsPort) {
  const auto lab = LabConfig::Load((SourceDir() / "deploy/lab.yaml").string());
  std::set<std::string> named;
  for (const auto& p : ports::kLabPorts) {
    named.insert(p.process);
    const std::string key = std::string("processes.") + p.process;
    ASSERT_TRUE(lab.Has(key)) << "deploy/lab.yaml has no " << key;
    EXPECT_EQ(lab.Get<int>(key + ".port"), p.port) << key;
    EXPECT_EQ(lab.Get<std::string>(key + ".program"), p.program) << key;
  }
  // Every process that listens is in the table; the control client listens on nothing.
  for (const auto& name : lab.ProcessNames()) {
    if (!lab.Has("processes." + name + ".port")) continue;
    EXPECT_TRUE(named.count(name))
        << "deploy/lab.yaml's " << name << " is not in common/config/lab_ports.h";
  }
  EXPECT_EQ(lab.Get<std::string>("processes.control.program"), "igms-control");
  EXPECT_FALSE(lab.Has("processes.control.port"));
}

TEST(LabPorts, TheConfigurationPageTablesEveryPort) {
  std::set<std::string> tabled;
  for (const auto& line : DocLines()) {
    if (line.where.rfind("docs/configuration.md:", 0) != 0 || line.text.rfind('|', 0) != 0)
      continue;
    for (const auto& p : ports::kLabPorts) {
      if (line.text.find(std::string("`") + p.program + "`") != std::string::npos &&
          line.text.find("| " + std::to_string(p.port) + " |") != std::string::npos) {
        tabled.insert(p.process);
      }
    }
  }
  for (const auto& p : ports::kLabPorts) {
    EXPECT_TRUE(tabled.count(p.process))
        << "docs/configuration.md has no table row with `" << p.program << "` and " << p.port;
  }
}

// A line that names a program or a service and a lab port must give that process's port; any
// other 73xx number must be one of the table's.
TEST(LabPorts, TheDocsGiveEachProgramItsPort) {
  const std::regex port_pattern(R"(\b73\d\d\b)");
  std::vector<std::regex> names;  // a program's name, not part of a longer one
  for (const auto& p : ports::kLabPorts) {
    names.emplace_back(std::string(R"((^|[^\w-]))") + p.program + R"(($|[^\w-]))");
  }
  for (const auto& line : DocLines()) {
    if (!std::regex_search(line.text, port_pattern)) continue;
    std::set<int> allowed;
    for (std::size_t i = 0; i < std::size(ports::kLabPorts); ++i) {
      const auto& p = ports::kLabPorts[i];
      if (std::regex_search(line.text, names[i]) ||
          line.text.find(ServiceOf(p.process) + ".") != std::string::npos) {
        allowed.insert(p.port);
      }
    }
    if (allowed.empty()) {
      for (const auto& p : ports::kLabPorts) allowed.insert(p.port);
    }
    for (auto it = std::sregex_iterator(line.text.begin(), line.text.end(), port_pattern);
         it != std::sregex_iterator(); ++it) {
      EXPECT_TRUE(allowed.count(std::stoi(it->str())))
          << line.where << ": port " << it->str() << " disagrees with common/config/lab_ports.h\n"
          << "  " << line.text;
    }
  }
}

}  // namespace
}  // namespace igms::config
