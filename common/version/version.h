// Which IGMS a program is: the project's version (CMake's project version) and the git
// revision it was built from, when it was built from a git checkout. Every program prints it
// for --version and every server reports it in igms.Server.Ping, so a client can record which
// servers made a model.
#pragma once

#include <string>
#include <string_view>

namespace igms::version {

// The project's version: "0.1.0".
std::string_view Project();
// The git commit built from ("5e97445a1b2c", "5e97445a1b2c-dirty" with uncommitted changes),
// or "" when built without git (a source tarball).
std::string_view Revision();
// What a server reports: "0.1.0", or "0.1.0+g5e97445a1b2c" (".dirty" appended when dirty).
std::string Full();
// This process's program name ("igms-video-server").
std::string ProgramName();
// The line --version prints: "igms-video-server 0.1.0+g5e97445a1b2c".
std::string Line(std::string_view program);

}  // namespace igms::version
