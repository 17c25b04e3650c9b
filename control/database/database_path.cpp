#include "control/database/database_path.h"

#include <pwd.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "common/base/environment.h"
#include "common/config/keys.h"

namespace igms::control {

namespace fs = std::filesystem;

namespace {

// The password database's home folder of this user ("" when there is none); getpwuid_r, as
// getpwuid's shared result is not thread safe.
std::string PasswordHome() {
  passwd entry{};
  passwd* found = nullptr;
  std::vector<char> buffer(4096);
  int error = 0;
  while ((error = getpwuid_r(getuid(), &entry, buffer.data(), buffer.size(), &found)) == ERANGE &&
         buffer.size() < (std::size_t{1} << 20)) {
    buffer.resize(buffer.size() * 2);
  }
  return error == 0 && found && found->pw_dir ? std::string(found->pw_dir) : std::string();
}

}  // namespace

UserFolders UserFolders::FromEnvironment() {
  UserFolders folders;
  if (auto xdg = EnvironmentVariable("XDG_DATA_HOME")) folders.xdg_data_home = *xdg;
  if (auto home = EnvironmentVariable("HOME"); home && !home->empty()) {
    folders.home = *home;
  } else {
    folders.home = PasswordHome();
  }
  return folders;
}

DatabaseResult<std::string> DefaultDatabasePath(const UserFolders& folders) {
  fs::path data;
  if (!folders.xdg_data_home.empty() && fs::path(folders.xdg_data_home).is_absolute()) {
    data = folders.xdg_data_home;
  } else if (!folders.home.empty()) {
    data = fs::path(folders.home) / ".local" / "share";
  } else {
    return DatabaseError{DatabaseErrorCode::kStorage,
                         "no folder for the geometric database: neither XDG_DATA_HOME nor HOME "
                         "is set; give one with --database FILE or lab.database"};
  }
  return (data / "igms" / kDatabaseFileName).lexically_normal().string();
}

DatabaseResult<std::string> ResolveDatabasePath(const config::LabConfig& config,
                                                const std::string& flag,
                                                const UserFolders& folders) {
  if (!flag.empty()) return fs::absolute(flag).lexically_normal().string();
  std::string from_file;
  try {
    from_file = config::LabOptionsOf(config).database;
  } catch (const config::ConfigError& e) {
    return DatabaseError{DatabaseErrorCode::kStorage, e.what()};
  }
  if (from_file.empty()) return DefaultDatabasePath(folders);
  if (from_file.rfind("~/", 0) == 0) {
    if (folders.home.empty()) {
      return DatabaseError{
          DatabaseErrorCode::kStorage,
          config.source() + ": lab.database '" + from_file + "' starts with ~ but HOME is not set"};
    }
    return (fs::path(folders.home) / from_file.substr(2)).lexically_normal().string();
  }
  return fs::absolute(config.ResolvePath(from_file)).lexically_normal().string();
}

}  // namespace igms::control
