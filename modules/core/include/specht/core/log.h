// specht/core/log.h: logging to stderr through spdlog. Apps call InitLogging once;
// modules call spdlog::info/warn/error (fmt-style formatting) directly.
#pragma once

#include <spdlog/spdlog.h>

#include <string>

namespace specht {

// level: "debug", "info", "warn", "error" or "off".
void InitLogging(const std::string& level);

}  // namespace specht
