// The exit status of every IGMS program (docs/configuration.md, "Exit status"). Scripts, the
// launcher, systemd and the tests read these, so a number keeps its meaning in every program.
#pragma once

namespace igms {

enum ExitCode : int {
  kExitOk = 0,           // done; for a query, found (igms config get, igms locate)
  kExitFailure = 1,      // a runtime failure; for a query, not found
  kExitUsage = 2,        // bad command line or configuration: fix the input, not the machine
  kExitUnavailable = 3,  // a device or resource the program needs could not be opened, or an
                         // unexpected internal error of a one-shot tool (igms locate)
};

}  // namespace igms
