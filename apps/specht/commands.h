// apps/specht/commands.h: the subcommands of `specht`. Each registers its options
// and a callback that sets the exit code (0 ok, 1 runtime failure, 2 bad input).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "run_setup.h"
#include "specht/pipeline/classifier_runs.h"

namespace specht::app {

void AddReplayCommand(CLI::App& app, int& exit_code);
void AddParamsCommand(CLI::App& app, int& exit_code);
void AddEvalCommand(CLI::App& app, int& exit_code);
// `specht eval perception` (eval_perception_command.cpp), a subcommand of `eval`.
void AddEvalPerceptionCommand(CLI::App& eval, int& exit_code);
void AddSlamCommand(CLI::App& app, int& exit_code);
void AddConvertCommand(CLI::App& app, int& exit_code);
void AddSimCommand(CLI::App& app, int& exit_code);
void AddStereoCommand(CLI::App& app, int& exit_code);
void AddDetectCommand(CLI::App& app, int& exit_code);
void AddTrackCommand(CLI::App& app, int& exit_code);
void AddClassifyCommand(CLI::App& app, int& exit_code);
void AddTuneCommand(CLI::App& app, int& exit_code);
void AddPlanCommand(CLI::App& app, int& exit_code);
void AddRunCommand(CLI::App& app, int& exit_code);
void AddAisCommand(CLI::App& app, int& exit_code);
void AddNodeCommand(CLI::App& app, int& exit_code);
// `specht launch` (launch_command.cpp): reads the stages `node` has; register it after AddNodeCommand.
void AddLaunchCommand(CLI::App& app, int& exit_code);
// `specht commands` (commands_command.cpp): the index of every command above; register it last.
void AddCommandsCommand(CLI::App& app, int& exit_code);

// Registers a training's dataset argument, --resume, the pseudo-label options,
// --train-on and --fine-tune (pipeline/classifier_runs.h trains); `prepare` names the
// command that writes a dataset. Shared by `classify train` and `ais train`.
void AddTrainingOptions(CLI::App& cmd, pipeline::TrainingInputs& args, const std::string& prepare);

// --pseudo-labels V and --pseudo-label-rounds R, for `ais eval`, `classify crossval`
// and both train commands.
void AddPseudoLabelOption(CLI::App& cmd, classify::PseudoLabelOptions& o);

// The flags of a cross-validation with folds disjoint by object (`ais eval`,
// `classify crossval`; pipeline/classifier_runs.h runs it).
struct CrossValidationArgs {
  CommonArgs common;
  pipeline::CrossValidationInputs in;
};
// Registers the dataset argument, --folds, --repeats, --train-fraction, --networks,
// --no-forest, --pseudo-labels, --compare-to, --train-on, --fine-tune and the common options.
void AddCrossValidationOptions(CLI::App& cmd, CrossValidationArgs& args, const pipeline::CrossValidationNames& names);

}  // namespace specht::app
