// `specht replay [dataset]`: replays a dataset through the whole stack. Today that is
// mapping (graph SLAM); perception joins when the dataset has stereo images.
#include "commands.h"
#include "mapping_run.h"

namespace specht::app {

void AddReplayCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<MappingArgs>();
  CLI::App* cmd = app.add_subcommand("replay", "replay a dataset into a map, a trajectory and a report");
  AddMappingOptions(*cmd, *args, "specht-out/replay");
  cmd->callback([args, &exit_code] { exit_code = RunMapping(*args, "replay"); });
}

}  // namespace specht::app
