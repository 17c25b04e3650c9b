#include "common/base/environment.h"

#include <cstdlib>

namespace igms {

std::optional<std::string> EnvironmentVariable(const char* name) {
  // NOLINTNEXTLINE(concurrency-mt-unsafe): no setenv runs concurrently (see the header)
  const char* value = std::getenv(name);
  if (value == nullptr) return std::nullopt;
  return std::string(value);
}

}  // namespace igms
