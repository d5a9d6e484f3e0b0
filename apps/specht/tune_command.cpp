// `specht tune <tune.yaml> -o DIR [-j N] [--resume]` (pipeline/tuning_run.h).
#include "commands.h"
#include "options_registry.h"
#include "specht/pipeline/tuning_run.h"

namespace specht::app {
namespace {

struct TuneArgs {
  pipeline::TuningInputs in;
  std::string out_dir = "specht-out/tune";
  bool quiet = false;
};

}  // namespace

void AddTuneCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<TuneArgs>();
  CLI::App* cmd = app.add_subcommand("tune", "search parameter values that optimise a metric of a run's report");
  cmd->add_option("tune_file", args->in.tune_file, "tune file (see params/tune/*.yaml)")->required();
  cmd->add_option("-o,--out", args->out_dir, "output directory")->capture_default_str();
  cmd->add_option("-j,--jobs", args->in.jobs, "evaluations in parallel")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  cmd->add_flag("--resume", args->in.resume, "continue from the output directory's evaluations.csv");
  cmd->add_option("--data-dir", args->in.data_dir, "data directory for {data} (default $SPECHT_DATA_DIR)");
  cmd->add_flag("-q,--quiet", args->quiet, "no progress line");
  cmd->add_flag("--check", args->in.check, "only check the tune file and list the search space");
  cmd->callback([args, &exit_code] {
    exit_code = pipeline::RunTuningSearch(AllOptions().Defaults().Describe(), args->in, args->out_dir, args->quiet);
  });
}

}  // namespace specht::app
