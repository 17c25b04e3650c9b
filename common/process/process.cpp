#include "common/process/process.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>

#include "common/base/environment.h"
#include "common/base/errno_text.h"

extern char** environ;

namespace igms {
namespace {

std::string Join(const std::vector<std::string>& argv) {
  std::string out;
  for (const std::string& a : argv) out += (out.empty() ? "" : " ") + a;
  return out;
}

}  // namespace

std::string RunProgram(const std::vector<std::string>& argv, const std::string& output_path) {
  if (argv.empty()) return "no program to run";
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (!output_path.empty()) {
    posix_spawn_file_actions_addopen(&actions, 1, output_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawn_file_actions_adddup2(&actions, 1, 2);
  }
  pid_t pid = 0;
  const int rc = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) return "cannot run '" + Join(argv) + "': " + ErrnoText(rc);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return "cannot wait for '" + Join(argv) + "': " + ErrnoText(errno);
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
  const std::string where = output_path.empty() ? "" : " (its messages are in " + output_path + ")";
  if (WIFEXITED(status)) {
    return "'" + Join(argv) + "' exited with status " + std::to_string(WEXITSTATUS(status)) + where;
  }
  return "'" + Join(argv) + "' was killed by signal " + std::to_string(WTERMSIG(status)) + where;
}

std::vector<std::filesystem::path> ProgramSearchDirs() {
  std::vector<std::filesystem::path> dirs;
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec) dirs.push_back(self.parent_path());
  if (const std::optional<std::string> path = EnvironmentVariable("PATH")) {
    std::stringstream ss(*path);
    std::string dir;
    while (std::getline(ss, dir, ':')) {
      if (!dir.empty()) dirs.emplace_back(dir);
    }
  }
  return dirs;
}

std::filesystem::path FindProgram(const std::string& name) {
  for (const auto& dir : ProgramSearchDirs()) {
    std::filesystem::path candidate = dir / name;  // not const: returned by move
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec) && access(candidate.c_str(), X_OK) == 0) {
      return candidate;
    }
  }
  return {};
}

}  // namespace igms
