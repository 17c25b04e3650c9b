#include "common/log/log.h"

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <cstdlib>

#include "common/base/environment.h"

namespace igms::log {

bool Init(const std::string& process_name, const std::string& level) {
  auto logger = spdlog::stderr_logger_mt(process_name + "-" + std::to_string(std::rand()));
  const bool timestamps = EnvironmentVariable("IGMS_LOG_TIMESTAMPS") != "0";
  logger->set_pattern(timestamps ? "%Y-%m-%d %H:%M:%S.%e [" + process_name + "] [%l] %v"
                                 : "[" + process_name + "] [%l] %v");
  spdlog::set_default_logger(logger);
  const auto parsed = spdlog::level::from_str(level);
  const bool known = parsed != spdlog::level::off || level == "off";
  spdlog::set_level(known ? parsed : spdlog::level::info);
  spdlog::flush_on(spdlog::level::info);
  if (!known) spdlog::warn("unknown log level '{}', using info", level);
  return known;
}

}  // namespace igms::log
