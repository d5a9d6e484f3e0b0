// specht/core/log.h: logging to stderr through spdlog. Apps call InitLogging once;
// modules call spdlog::info/warn/error (fmt-style formatting) directly.
#pragma once

#include <string>

#include <spdlog/spdlog.h>

namespace specht {

// level: "debug", "info", "warn", "error" or "off".
void InitLogging(const std::string& level);

}  // namespace specht
