// igms: the lab's command, git-style. `igms SUB ARGS...` runs `igms-SUB ARGS...`, looked up
// beside this executable first and then on PATH; `igms help` lists what is installed.
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "common/base/errno_text.h"
#include "common/config/exit_codes.h"
#include "common/process/process.h"
#include "common/version/version.h"

namespace fs = std::filesystem;

namespace {

bool Executable(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec) && access(p.c_str(), X_OK) == 0;
}

int Help() {
  std::set<std::string> subs;
  for (const auto& dir : igms::ProgramSearchDirs()) {
    std::error_code ec;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      const std::string name = entry.path().filename().string();
      if (name.rfind("igms-", 0) == 0 && Executable(entry.path())) subs.insert(name.substr(5));
    }
  }
  std::cout << "usage: igms COMMAND [ARGS...]   (igms COMMAND --help for its options)\n"
               "       igms --version\n\n"
               "Installed commands:\n";
  for (const auto& s : subs) std::cout << "  " << s << "\n";
  std::cout << "\nThe fake client of every server is igmsctl.\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "help" || std::string(argv[1]) == "--help" ||
      std::string(argv[1]) == "-h") {
    return Help();
  }
  if (std::string(argv[1]) == "--version") {
    std::cout << igms::version::Line("igms") << "\n";
    return 0;
  }
  const std::string sub = argv[1];
  if (sub.find('/') != std::string::npos || sub.empty() || sub[0] == '-') {
    std::cerr << "igms: '" << sub << "' is not a command (see igms help)\n";
    return igms::kExitUsage;
  }
  const fs::path program = igms::FindProgram("igms-" + sub);
  if (!program.empty()) {
    std::vector<char*> args;
    std::string arg0 = "igms-" + sub;
    args.push_back(arg0.data());
    for (int i = 2; i < argc; ++i) args.push_back(argv[i]);
    args.push_back(nullptr);
    execv(program.c_str(), args.data());
    std::cerr << "igms: cannot run " << program << ": " << igms::ErrnoText(errno) << "\n";
    return igms::kExitUsage;
  }
  std::cerr << "igms: no command '" << sub << "' (looked for igms-" << sub
            << " beside igms and on PATH; see igms help)\n";
  return igms::kExitUsage;
}
