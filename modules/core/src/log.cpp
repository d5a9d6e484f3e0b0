#include "specht/core/log.h"

#include <spdlog/sinks/stdout_color_sinks.h>

#include "specht/core/error.h"

namespace specht {

void InitLogging(const std::string& level) {
  auto logger = spdlog::get("specht");
  if (!logger) {
    logger = spdlog::stderr_color_mt("specht");
    logger->set_pattern("[%^%l%$] %v");
    spdlog::set_default_logger(logger);
  }
  const auto parsed = spdlog::level::from_str(level);
  if (parsed == spdlog::level::off && level != "off") {
    throw InputError("--log-level: unknown level '" + level + "' (debug, info, warn, error, off)");
  }
  spdlog::set_level(parsed);
}

}  // namespace specht
