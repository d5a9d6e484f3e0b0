// specht: one executable, one subcommand per job. See README.md.
#include <CLI/CLI.hpp>
#include <iostream>

#include "commands.h"
#include "specht/core/error.h"
#include "specht/core/interrupt.h"
#include "specht/core/log.h"

int main(int argc, char** argv) {
  CLI::App app{"specht: an autonomy stack for small autonomous cars (mapping, perception, planning)"};
  app.require_subcommand(1);
  specht::InitLogging("info");
  specht::InstallInterruptHandlers();
  app.add_option_function<std::string>(
      "--log-level", [](const std::string& level) { specht::InitLogging(level); },
      "debug, info, warn, error or off (default info)");
  int exit_code = 0;
  specht::app::AddReplayCommand(app, exit_code);
  specht::app::AddParamsCommand(app, exit_code);
  specht::app::AddEvalCommand(app, exit_code);
  specht::app::AddSlamCommand(app, exit_code);
  specht::app::AddConvertCommand(app, exit_code);
  specht::app::AddSimCommand(app, exit_code);
  specht::app::AddStereoCommand(app, exit_code);
  specht::app::AddDetectCommand(app, exit_code);
  specht::app::AddTrackCommand(app, exit_code);
  specht::app::AddClassifyCommand(app, exit_code);
  specht::app::AddTuneCommand(app, exit_code);
  specht::app::AddPlanCommand(app, exit_code);
  specht::app::AddRunCommand(app, exit_code);
  specht::app::AddAisCommand(app, exit_code);
  specht::app::AddNodeCommand(app, exit_code);
  specht::app::AddLaunchCommand(app, exit_code);
  specht::app::AddCommandsCommand(app, exit_code);
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "specht: " << e.what() << "\n";
    return specht::ExitCodeFor(e);
  }
  return exit_code;
}
