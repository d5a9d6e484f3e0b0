#include "run_setup.h"

#include <cstdio>

#include "options_registry.h"
#include "specht/core/error.h"
#include "specht/io/data_dir.h"
#include "specht/pipeline/run_directory.h"

namespace specht::app {

void AddCommonOptions(CLI::App& cmd, CommonArgs& args, const std::string& default_out) {
  args.out_dir = default_out;
  cmd.add_option("-p,--params", args.param_files, "parameter file(s), applied in order over the defaults");
  cmd.add_option("--set", args.overrides, "override one parameter: section.key=value (repeatable)");
  cmd.add_option("-o,--out", args.out_dir, "output directory")->capture_default_str();
  cmd.add_option("--data-dir", args.data_dir, "evaluation data directory (default: $SPECHT_DATA_DIR)");
  cmd.add_flag("-q,--quiet", args.quiet, "no progress line");
}

params::Params LoadParams(const CommonArgs& args) {
  params::ParamTree tree;
  for (const auto& file : args.param_files) tree.MergeFile(file);
  for (const auto& assignment : args.overrides) tree.Set(assignment);
  return AllOptions().Load(tree);
}

std::pair<uint64_t, uint64_t> ParseSeedRange(const std::string& text, uint64_t fallback) {
  if (text.empty()) return {fallback, fallback};
  unsigned long long a = 0, b = 0;
  char dash = 0;
  const int n = std::sscanf(text.c_str(), "%llu%c%llu", &a, &dash, &b);
  if (n == 1) return {a, a};
  if (n == 3 && dash == '-' && b >= a) return {a, b};
  throw InputError("--seeds: \"" + text + "\" is not N or A-B with A <= B");
}

std::string DataDir(const CommonArgs& args) { return io::ResolveDataDir(args.data_dir).value_or(""); }

void PrepareOutputDir(const CommonArgs& args, const params::Params& params) {
  pipeline::PrepareRunDirectory(args.out_dir, params);
}

}  // namespace specht::app
