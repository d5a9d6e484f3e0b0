// `specht sim <scenario.yaml> -o DIR [--seed N] [--duration S]`: a simulated drive
// recorded as a real run would be, with its ground truth (pipeline/simulation.h).
#include "commands.h"
#include "specht/pipeline/simulation.h"

namespace specht::app {

void AddSimCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<pipeline::SimulationOptions>();
  args->out_dir = "specht-out/sim";
  CLI::App* cmd = app.add_subcommand("sim", "simulate a scenario: sensor rawlog plus ground truth");
  cmd->add_option("scenario", args->scenario, "scenario YAML (see datasets/scenarios/)")->required();
  cmd->add_option("-o,--out", args->out_dir, "output directory")->capture_default_str();
  cmd->add_option("--seed", args->seed, "random seed (default: the scenario's)");
  cmd->add_option("--duration", args->duration_s, "seconds to simulate (default: the scenario's)");
  cmd->add_flag("-q,--quiet", args->quiet, "no progress line");
  cmd->add_option("--data-dir", args->data_dir, "data directory with sprites/ (default: $SPECHT_DATA_DIR)");
  cmd->add_option(
         "--sprites", args->sprites,
         "agents in the camera: auto (photographs when the data has them), tuning, held_out, all, none (boxes)")
      ->capture_default_str();
  cmd->add_flag("--no-camera", args->no_camera,
                "leave the scenario's stereo camera out (LiDAR, odometry and IMU only)");
  cmd->callback([args, &exit_code] { exit_code = pipeline::RecordSimulation(*args); });
}

}  // namespace specht::app
