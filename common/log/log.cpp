#include "common/log/log.h"

#include <spdlog/sinks/stdout_sinks.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <string>

#include "common/base/environment.h"

namespace igms::log {

bool Init(const std::string& process_name, const std::string& level) {
  // spdlog's registry refuses a name twice, and a process (a test) may call Init again.
  static std::atomic<int> loggers_made{0};
  auto logger = spdlog::stderr_logger_mt(process_name + "-" + std::to_string(++loggers_made));
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
