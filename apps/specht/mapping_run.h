// apps/specht/mapping_run.h: the flags `specht replay` and `specht slam` share, and
// the one call they make (pipeline/replay.h runs the dataset through the stack).
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "run_setup.h"

namespace specht::app {

struct MappingArgs {
  CommonArgs common;
  std::string dataset;
  std::string ground_truth;
  std::string relations;
  std::string reference_map;
  std::string map_dir;       // localization on a saved map when set
  std::string continue_dir;  // continuing a saved map when set
  std::string model_dir;     // the trajectory classifier on the perceived tracks
  std::optional<double> rate, from_s, to_s;
  bool list = false;  // print a bag's topics and stop
  std::string mcap = "run.mcap";
  bool no_mcap = false;
};

// Adds the dataset positional and
// --ground-truth/--relations/--reference-map/--map/--continue/--model/--rate/--from/--to.
void AddMappingOptions(CLI::App& cmd, MappingArgs& args, const std::string& default_out);

// Runs the pipeline; returns the exit code (2 when the input broke off midway).
int RunMapping(MappingArgs args, const std::string& command);

}  // namespace specht::app
