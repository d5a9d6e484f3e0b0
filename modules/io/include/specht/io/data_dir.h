// specht/io/data_dir.h: where the evaluation data lives. specht never copies data
// into its tree; it reads it from a directory given by --data-dir or the
// SPECHT_DATA_DIR environment variable (datasets/manifest.yaml lists what is there).
#pragma once

#include <optional>
#include <string>

namespace specht::io {

// The data directory: `cli_value` if given, else $SPECHT_DATA_DIR, else nullopt.
// Throws InputError when the chosen directory does not exist.
std::optional<std::string> ResolveDataDir(const std::string& cli_value = "");

// The built-in default dataset: the real rawlog shipped by Debian's mrpt-common.
std::string DefaultRawlog();

}  // namespace specht::io
