// `specht launch FILE [--host H] [--domain N] -o DIR`: the nodes a launch file lists
// for this computer, as child processes (net/launch.h).
#include <unistd.h>

#include <climits>

#include "commands.h"
#include "specht/core/error.h"
#include "specht/net/launch.h"

namespace specht::app {
namespace {

struct LaunchArgs {
  CommonArgs common;
  std::string file;
  net::LaunchOptions options;
};

std::string ThisExecutable() {
  char path[PATH_MAX];
  const ssize_t n = readlink("/proc/self/exe", path, sizeof(path) - 1);
  if (n <= 0) throw RuntimeError("launch: cannot find the specht executable (/proc/self/exe)");
  return std::string(path, static_cast<size_t>(n));
}

// The stages `specht node` has: the launch file may name these.
std::vector<std::string> NodeStages(CLI::App& app) {
  std::vector<std::string> stages;
  for (const CLI::App* stage : app.get_subcommand("node")->get_subcommands({})) stages.push_back(stage->get_name());
  return stages;
}

}  // namespace

void AddLaunchCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<LaunchArgs>();
  CLI::App* cmd = app.add_subcommand("launch", "start the nodes a launch file lists for this computer (net/launch.h)");
  cmd->add_option("file", args->file, "launch file (YAML: nodes, the host each runs on; params/launch/*.yaml)")
      ->required();
  cmd->add_option("--host", args->options.host, "start the nodes of this host of the file")->capture_default_str();
  cmd->add_option("--domain", args->options.domain,
                  "DDS domain id of every node (over the file's): runs apart never meet");
  cmd->add_option("--shutdown-timeout", args->options.shutdown_timeout_s,
                  "seconds a node has to end after SIGINT before it is killed")
      ->capture_default_str();
  AddCommonOptions(*cmd, args->common, "specht-out/launch");
  cmd->callback([args, &app, &exit_code] {
    const net::LaunchFile file = net::LoadLaunchFile(args->file, NodeStages(app));
    LoadParams(args->common);  // every node gets them: wrong ones stop the launch before it starts
    net::LaunchOptions& o = args->options;
    o.executable = ThisExecutable();
    o.out_dir = args->common.out_dir;
    o.param_files = args->common.param_files;
    o.overrides = args->common.overrides;
    o.quiet = args->common.quiet;
    exit_code = net::Launch(file, o);
  });
}

}  // namespace specht::app
