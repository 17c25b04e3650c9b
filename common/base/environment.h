// The process environment, copied out rather than handed back as getenv's pointer.
#pragma once

#include <optional>
#include <string>

namespace igms {

// The value of the environment variable `name`, copied; nullopt when it is not set (a variable
// set to nothing is ""). Read-only, and safe from any thread: getenv races only with a
// concurrent setenv or putenv, and the programs change their environment only while starting,
// before they start a thread.
std::optional<std::string> EnvironmentVariable(const char* name);

}  // namespace igms
