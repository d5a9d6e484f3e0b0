// apps/specht/options_registry.h: every options section specht knows. Loading checks
// a parameter file against all of them, so a misspelled key is caught whichever
// command runs, and `specht params` can dump every default.
#pragma once

#include "specht/core/params.h"

namespace specht::app {

const params::Registry& AllOptions();

// Which params/<file>.yaml holds each section's defaults (the per-module files).
struct DefaultsFile {
  const char* file;
  std::vector<std::string> sections;
};
const std::vector<DefaultsFile>& DefaultsFiles();

}  // namespace specht::app
