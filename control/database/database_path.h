// Where the geometric database lives (docs/database.md):
//   1. --database FILE, relative to the working folder;
//   2. else lab.database in the lab file, relative to the file's folder ("~/" is the home);
//   3. else (an installed lab, whose file leaves lab.database out or empty) the operator's
//      data folder: $XDG_DATA_HOME/igms/igms.db, or ~/.local/share/igms/igms.db. The
//      operator's, not a service's: the models are the operator's work.
#pragma once

#include <string>

#include "common/config/lab_config.h"
#include "control/database/geometric_database.h"

namespace igms::control {

// The part of the environment the default depends on, passed in so tests need no setenv.
struct UserFolders {
  std::string xdg_data_home;  // $XDG_DATA_HOME; ignored unless absolute (XDG spec)
  std::string home;           // $HOME, else the password database's home folder
  // Reads the environment (getenv): call it before other threads start.
  static UserFolders FromEnvironment();
};

inline constexpr const char* kDatabaseFileName = "igms.db";

// The operator's data folder's database, or an error when neither folder is known.
DatabaseResult<std::string> DefaultDatabasePath(const UserFolders& folders);

// `flag` is --database's value (empty when not given). The result is absolute.
DatabaseResult<std::string> ResolveDatabasePath(const config::LabConfig& config,
                                                const std::string& flag,
                                                const UserFolders& folders);

}  // namespace igms::control
