// tests/support/report.h: a command's report.json, as the suites that run the binary read it.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "test_support.h"

namespace specht {

// <dir>/report.json, parsed.
inline nlohmann::json Report(const std::string& dir) {
  return nlohmann::json::parse(testing::ReadFile(dir + "/report.json"));
}

}  // namespace specht
