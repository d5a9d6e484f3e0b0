#include "mapping_run.h"

#include <cstdio>
#include <sstream>

#include "specht/io/data_dir.h"
#include "specht/io/ros_bag.h"
#include "specht/pipeline/replay.h"

namespace specht::app {
namespace {

std::string Real(double v) {
  std::ostringstream s;
  s.precision(15);
  s << v;
  return s.str();
}

}  // namespace

void AddMappingOptions(CLI::App& cmd, MappingArgs& args, const std::string& default_out) {
  cmd.add_option("dataset", args.dataset,
                 "MRPT rawlog, CARMEN log, ROS 2 bag (a folder with metadata.yaml, or its .db3), ROS 1 bag or MCAP "
                 "file (default: the rawlog shipped by Debian's mrpt-common, " +
                     io::DefaultRawlog() + ")");
  AddCommonOptions(cmd, args.common, default_out);
  cmd.add_option("--ground-truth", args.ground_truth,
                 "reference trajectory (TUM, 't x y theta' or CARMEN log); default <dataset>.GT.txt when present, "
                 "or the corrected poses of a corrected CARMEN log");
  cmd.add_option("--relations", args.relations,
                 "published relations file (t1 t2 x y z roll pitch yaw) to score on; default <log stem>.relations "
                 "beside the dataset, when present");
  cmd.add_option("--reference-map", args.reference_map,
                 "a map of the place (map_server YAML) to score the map against; default a ROS 2 bag folder's own "
                 "map.yaml, when present");
  cmd.add_option("--map", args.map_dir,
                 "localize on the map artefact in this directory (written by `specht slam`) instead of mapping");
  cmd.add_option("--continue", args.continue_dir,
                 "continue the map artefact in this directory: localize the first scan on it, then map on, "
                 "closing loops against it (writes the extended map)")
      ->excludes("--map");
  cmd.add_option("--model", args.model_dir,
                 "classify the perceived tracks online with this `specht classify train` output "
                 "(same as --set perception.classifier_model=DIR)");
  cmd.add_option("--rate", args.rate, "pace at R x real time (same as --set replay.rate=R)");
  cmd.add_option("--mcap", args.mcap,
                 "record the replay as MCAP with ROS 2 schemas (scans, odometry, TF, the map, the trajectory), for "
                 "Foxglove; a bare file name goes into the output folder")
      ->capture_default_str();
  cmd.add_flag("--no-mcap", args.no_mcap, "write no MCAP");
  cmd.add_flag("--list", args.list,
               "print the topics of a ROS 1 or 2 bag or an MCAP file (type, messages, rate) and stop");
  cmd.add_option("--from", args.from_s, "start S seconds into the data (replay.from_s)");
  cmd.add_option("--to", args.to_s, "stop S seconds into the data (replay.to_s)");
}

int RunMapping(MappingArgs a, const std::string& command) {
  if (a.list) {
    std::printf("%-32s %-32s %9s %9s\n", "topic", "type", "messages", "rate_hz");
    for (const auto& t : io::ListRosBag(a.dataset))
      std::printf("%-32s %-32s %9lld %9.2f\n", t.name.c_str(), t.type.c_str(), static_cast<long long>(t.messages),
                  t.rate_hz);
    return 0;
  }
  CommonArgs& common = a.common;
  if (a.rate) common.overrides.push_back("replay.rate=" + Real(*a.rate));
  if (a.from_s) common.overrides.push_back("replay.from_s=" + Real(*a.from_s));
  if (a.to_s) common.overrides.push_back("replay.to_s=" + Real(*a.to_s));
  if (!a.model_dir.empty()) common.overrides.push_back("perception.classifier_model=" + a.model_dir);
  // Everything that can be wrong with the input is checked before anything is written.
  const params::Params params = LoadParams(common);
  pipeline::Replay replay(
      params,
      {a.dataset, a.ground_truth, a.relations, a.reference_map, a.map_dir, a.continue_dir, DataDir(common),
       a.no_mcap ? "" : a.mcap, common.param_files, common.overrides, std::nullopt},
      command);
  PrepareOutputDir(common, params);
  return replay.Run(common.out_dir, common.quiet);
}

}  // namespace specht::app
