// apps/specht/run_setup.h: what every command does before it computes anything:
// load and validate parameters (nothing is written when they are wrong), then
// create the output directory and write the effective parameters into it.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "specht/core/params.h"

namespace specht::app {

struct CommonArgs {
  std::vector<std::string> param_files;
  std::vector<std::string> overrides;  // key=value
  std::string out_dir;
  std::string data_dir;
  bool quiet = false;
};

// Adds -p/--params, --set, -o/--out, --data-dir, --quiet to a subcommand.
void AddCommonOptions(CLI::App& cmd, CommonArgs& args, const std::string& default_out);

// Defaults, then each file, then each --set. Throws InputError on any problem.
params::Params LoadParams(const CommonArgs& args);

// "--seeds N" or "A-B" (A <= B); `fallback` when empty. Throws InputError.
std::pair<uint64_t, uint64_t> ParseSeedRange(const std::string& text, uint64_t fallback);

// The data directory of --data-dir, else $SPECHT_DATA_DIR, else "" (io/data_dir.h).
std::string DataDir(const CommonArgs& args);

// Creates args.out_dir and writes params.yaml (the effective parameters) there.
void PrepareOutputDir(const CommonArgs& args, const params::Params& params);

}  // namespace specht::app
