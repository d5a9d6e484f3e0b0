// `specht node play [dataset]`: a dataset published as ROS 2 topics over DDS.
// `specht node slam`: graph SLAM on ROS 2 topics, publishing the map, TF and the
// trajectory. `specht node sim`: the simulated car, sensors out, drive commands in.
// `specht node stack`: the closed loop's stack on the simulated car's topics (what
// `specht run --nodes` starts). `specht node perception`: its tracker on its own. `specht node record`: ROS 2 topics
// into an MCAP file (pipeline/nodes.h says what each node reads and publishes).
#include <cstdio>

#include "commands.h"
#include "mapping_run.h"
#include "specht/pipeline/nodes.h"
#include "specht/pipeline/replay.h"

namespace specht::app {
namespace {

struct NodeArgs {
  CommonArgs common;
  std::string dataset;
  std::optional<int> domain;
  std::optional<double> rate, idle_end_s;
  std::optional<int> subscribers;
  std::string map_dir, mcap = "run.mcap";
  bool no_mcap = false;
  std::optional<uint64_t> seed;
  std::optional<double> duration_s;
  bool free_run = false;
  std::string mission, stack_mcap;
  bool perception_node = false;
};

void AddNodeOptions(CLI::App& cmd, NodeArgs& args, const std::string& default_out) {
  AddCommonOptions(cmd, args.common, default_out);
  cmd.add_option("--domain", args.domain, "DDS domain id (same as --set dds.domain=N): runs apart never meet");
}

params::Params NodeParams(NodeArgs& a) {
  auto& o = a.common.overrides;
  if (a.domain) o.push_back("dds.domain=" + std::to_string(*a.domain));
  if (a.rate) o.push_back("replay.rate=" + std::to_string(*a.rate));
  if (a.idle_end_s) o.push_back("node.idle_end_s=" + std::to_string(*a.idle_end_s));
  if (a.subscribers) o.push_back("node.subscribers=" + std::to_string(*a.subscribers));
  return LoadParams(a.common);
}

int RunPlay(NodeArgs a) {
  const params::Params params = NodeParams(a);
  PrepareOutputDir(a.common, params);
  return pipeline::PlayDataset(params, {a.dataset, a.common.param_files, a.common.overrides}, a.common.out_dir,
                               a.common.quiet);
}

int RunSlamNode(NodeArgs a) {
  const params::Params params = NodeParams(a);
  const auto& node = params.Get<pipeline::NodeOptions>("node");
  pipeline::ReplayInputs in;
  in.map_dir = a.map_dir;
  in.mcap = a.no_mcap ? "" : a.mcap;
  in.param_files = a.common.param_files;
  in.overrides = a.common.overrides;
  in.data_dir = DataDir(a.common);
  in.node = pipeline::NodeIo{pipeline::NodeParticipant(params),
                             {node.scan_topic, node.odometry_topic, node.settle_s, node.idle_end_s,
                              params.Get<io::ReplayOptions>("replay").on_bad_record == "skip" ? io::OnBadRecord::kSkip
                                                                                              : io::OnBadRecord::kStop},
                             node.map_every_s};
  pipeline::Replay replay(params, std::move(in), "node slam");
  PrepareOutputDir(a.common, params);
  return replay.Run(a.common.out_dir, a.common.quiet);
}

int RunSimNode(NodeArgs a) {
  if (a.free_run) a.common.overrides.push_back("node.lockstep=false");
  const params::Params params = NodeParams(a);
  PrepareOutputDir(a.common, params);
  return pipeline::RunSimulatorNode(params, {a.dataset, a.seed, a.duration_s, a.common.param_files, a.common.overrides},
                                    a.common.out_dir, a.common.quiet);
}

int RunStack(NodeArgs a) {
  const params::Params params = NodeParams(a);
  PrepareOutputDir(a.common, params);
  return pipeline::RunStackNode(params,
                                {a.dataset, a.mission, a.map_dir, a.stack_mcap, a.seed, a.perception_node,
                                 a.common.param_files, a.common.overrides},
                                a.common.out_dir, a.common.quiet);
}

int RunPerception(NodeArgs a) {
  const params::Params params = NodeParams(a);
  PrepareOutputDir(a.common, params);
  return pipeline::RunPerceptionNode(params, {a.common.param_files, a.common.overrides}, a.common.out_dir,
                                     a.common.quiet);
}

int RunRecord(NodeArgs a) {
  const params::Params params = NodeParams(a);
  PrepareOutputDir(a.common, params);
  return pipeline::RecordTopics(params, {a.mcap, a.common.param_files, a.common.overrides}, a.common.out_dir,
                                a.common.quiet);
}

}  // namespace

void AddNodeCommand(CLI::App& app, int& exit_code) {
  CLI::App* node = app.add_subcommand("node", "a stage of the stack as a DDS node that speaks ROS 2");
  node->require_subcommand(1);

  auto play = std::make_shared<NodeArgs>();
  CLI::App* p = node->add_subcommand("play", "publish a dataset's scans, odometry and TF as ROS 2 topics");
  p->add_option("dataset", play->dataset,
                "MRPT rawlog, CARMEN log, ROS 2 or ROS 1 bag, or MCAP file (default: the rawlog shipped by "
                "Debian's mrpt-common)");
  p->add_option("--rate", play->rate, "pace at R x real time (same as --set replay.rate=R; 0 = as fast as possible)");
  p->add_option("--subscribers", play->subscribers,
                "start once N subscribers to the scans matched (same as --set node.subscribers=N; default 1)");
  AddNodeOptions(*p, *play, "specht-out/node-play");
  p->callback([play, &exit_code] { exit_code = RunPlay(*play); });

  auto slam = std::make_shared<NodeArgs>();
  CLI::App* s = node->add_subcommand(
      "slam", "graph SLAM on ROS 2 topics (/scan, /odom, /tf_static), publishing /map, /tf and /trajectory");
  s->add_option("--idle-end", slam->idle_end_s,
                "end after S seconds without a message, once one came (same as --set node.idle_end_s=S; default: "
                "run until Ctrl-C)");
  s->add_option("--map", slam->map_dir, "localize on the map artefact in this directory instead of mapping");
  s->add_option("--mcap", slam->mcap, "also record the run as MCAP (a bare file name goes into the output folder)")
      ->capture_default_str();
  s->add_flag("--no-mcap", slam->no_mcap, "write no MCAP");
  AddNodeOptions(*s, *slam, "specht-out/node-slam");
  s->callback([slam, &exit_code] { exit_code = RunSlamNode(*slam); });

  auto sim = std::make_shared<NodeArgs>();
  CLI::App* m = node->add_subcommand(
      "sim",
      "the simulated car: /scan, /odom, /imu, /tf, /clock, /ground_truth out; AckermannDriveStamped commands in");
  m->add_option("scenario", sim->dataset, "scenario file (datasets/scenarios/*.yaml)")->required();
  m->add_option("--seed", sim->seed, "seed (default: the scenario's)");
  m->add_option("--duration", sim->duration_s, "simulated seconds (default: the scenario's)");
  m->add_flag("--free-run", sim->free_run,
              "no lockstep: run paced by --rate, applying the latest command (same as --set node.lockstep=false)");
  m->add_option("--rate", sim->rate, "with --free-run: pace at R x real time (same as --set replay.rate=R)");
  AddNodeOptions(*m, *sim, "specht-out/node-sim");
  m->callback([sim, &exit_code] { exit_code = RunSimNode(*sim); });

  auto stack = std::make_shared<NodeArgs>();
  CLI::App* k = node->add_subcommand(
      "stack",
      "the closed loop's stack (SLAM, tracking, planning, decisions) on the simulated car's topics: /scan, /odom, "
      "/imu, /detections, /vehicle_state in; /stack/step, /perception/tracks, /drive out (`specht run --nodes` "
      "starts it)");
  k->add_option("scenario", stack->dataset, "scenario file the car drives in (its site: map, bays, the car)")
      ->required();
  k->add_option("--seed", stack->seed, "the drive's seed (default: the scenario's)");
  k->add_option("--mission", stack->mission, "mission file (default: park in the first bay)");
  k->add_option("--map", stack->map_dir, "localise on a mapping drive's map-<seed>/ (closed_loop.localization map)");
  k->add_option("--mcap", stack->stack_mcap, "record the drive as MCAP into this file (default: none)");
  k->add_flag("--perception-node", stack->perception_node,
              "take the tracks from `specht node perception` (/localization/odometry out, /perception/tracks and "
              "/perception/obstacles in) instead of tracking here");
  AddNodeOptions(*k, *stack, "specht-out/node-stack");
  k->callback([stack, &exit_code] { exit_code = RunStack(*stack); });

  auto perception = std::make_shared<NodeArgs>();
  CLI::App* c = node->add_subcommand(
      "perception",
      "the stack's tracker: /detections and /localization/odometry in; /perception/tracks and /perception/obstacles "
      "out (`specht run --nodes --perception-node` starts it)");
  AddNodeOptions(*c, *perception, "specht-out/node-perception");
  c->callback([perception, &exit_code] { exit_code = RunPerception(*perception); });

  auto record = std::make_shared<NodeArgs>();
  CLI::App* r = node->add_subcommand("record", "record the ROS 2 topics specht speaks into an MCAP file");
  r->add_option("--mcap", record->mcap, "the file (a bare file name goes into the output folder)")
      ->capture_default_str();
  r->add_option("--idle-end", record->idle_end_s,
                "end after S seconds without a message, once one came (same as --set node.idle_end_s=S; default: "
                "run until Ctrl-C)");
  AddNodeOptions(*r, *record, "specht-out/node-record");
  r->callback([record, &exit_code] { exit_code = RunRecord(*record); });
}

}  // namespace specht::app
