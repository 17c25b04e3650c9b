#include "control/database/database_path.h"

#include <pwd.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "common/config/keys.h"

namespace igms::control {

namespace fs = std::filesystem;

UserFolders UserFolders::FromEnvironment() {
  UserFolders folders;
  if (const char* xdg = std::getenv("XDG_DATA_HOME")) folders.xdg_data_home = xdg;
  if (const char* home = std::getenv("HOME"); home && *home) {
    folders.home = home;
  } else if (const passwd* entry = getpwuid(getuid()); entry && entry->pw_dir) {
    folders.home = entry->pw_dir;
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
