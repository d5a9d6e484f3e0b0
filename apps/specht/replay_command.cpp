// `specht replay [dataset]`: replays a dataset through scan-matching odometry and
// writes the occupancy grid (ROS PGM+YAML, MRPT .gridmap, PNG), the trajectory
// (TUM), the effective parameters and a run report.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>

#include "commands.h"
#include "reference.h"
#include "run_setup.h"
#include "specht/core/log.h"
#include "specht/core/progress.h"
#include "specht/core/transform_tree.h"
#include "specht/eval/map_quality.h"
#include "specht/eval/trajectory_error.h"
#include "specht/io/data_dir.h"
#include "specht/io/dataset.h"
#include "specht/io/map_io.h"
#include "specht/io/replay.h"
#include "specht/io/report.h"
#include "specht/io/trajectory_io.h"
#include "specht/slam/scan_matching.h"

namespace specht::app {
namespace {

struct ReplayArgs {
  CommonArgs common;
  std::string dataset;
  std::string ground_truth;
  std::optional<double> rate, from_s, to_s;
};

std::string Real(double v) {
  std::ostringstream s;
  s.precision(15);
  s << v;
  return s.str();
}

// The observations' MRPT class names, counted.
using Counts = std::map<std::string, long>;

struct ReplayResult {
  Counts observations;
  std::optional<Stamp> first, last;
  double wall_s = 0;
};

ReplayResult Drive(io::DatasetSource& source, io::ReplayClock& clock, slam::ScanMatchingMapper& mapper,
                   io::StageTimer& timer, io::RunReport& report, bool quiet, int& exit_code) {
  ReplayResult r;
  ProgressLine progress("replay", "scans", !quiet);
  const auto wall0 = std::chrono::steady_clock::now();
  while (true) {
    std::optional<io::Observation> obs;
    try {
      auto t = timer.Time("read");
      obs = source.Next();
    } catch (const io::DatasetError& e) {
      // A rawlog cannot be resynchronised after a broken record: stop here and keep
      // everything computed so far.
      spdlog::error("{}", e.what());
      report.SetIncomplete(e.what());
      exit_code = 2;
      break;
    }
    if (!obs) break;
    const auto verdict = clock.Classify(obs->stamp);
    if (verdict == io::ReplayClock::Verdict::kBefore) continue;
    if (verdict == io::ReplayClock::Verdict::kAfter) break;
    clock.WaitFor(obs->stamp);
    ++r.observations[obs->data->GetRuntimeClass()->className];
    {
      auto t = timer.Time("scan_matching");
      mapper.Add(obs->stamp, obs->data);
    }
    if (!r.first) r.first = obs->stamp;
    r.last = obs->stamp;
    progress.Update(static_cast<double>(mapper.stats().scans), source.FractionRead(),
                    "data " + std::to_string(static_cast<int>(SecondsBetween(*r.first, *r.last))) + " s");
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  progress.Finish("(" + std::to_string(mapper.stats().keyframes) + " keyframes)");
  return r;
}

int RunReplay(ReplayArgs a) {
  CommonArgs& common = a.common;
  if (a.rate) common.overrides.push_back("replay.rate=" + Real(*a.rate));
  if (a.from_s) common.overrides.push_back("replay.from_s=" + Real(*a.from_s));
  if (a.to_s) common.overrides.push_back("replay.to_s=" + Real(*a.to_s));

  // Everything that can be wrong with the input is checked before anything is written.
  const params::Params params = LoadParams(common);
  const auto& frames_options = params.Get<FramesOptions>("frames");
  const auto& replay_options = params.Get<io::ReplayOptions>("replay");
  const auto& matching_options = params.Get<slam::ScanMatchingOptions>("scan_matching");
  const auto& grid_options = params.Get<slam::GridOptions>("grid");
  io::ResolveDataDir(common.data_dir);
  const std::string dataset = a.dataset.empty() ? io::DefaultRawlog() : a.dataset;
  auto source = io::OpenDataset(dataset);
  std::string gt_path = a.ground_truth;
  if (gt_path.empty() && std::filesystem::exists(dataset + ".GT.txt")) gt_path = dataset + ".GT.txt";
  const Trajectory reference = gt_path.empty() ? Trajectory{} : ReadReference(gt_path);
  PrepareOutputDir(common, params);

  spdlog::info("replay: {} -> {}", dataset, common.out_dir);
  TransformTree frames(frames_options);
  slam::ScanMatchingMapper mapper(matching_options, &frames, frames_options.base_frame);
  io::ReplayClock clock(replay_options);
  io::StageTimer timer;
  io::RunReport report("replay");
  int exit_code = 0;
  const ReplayResult run = Drive(*source, clock, mapper, timer, report, common.quiet, exit_code);

  const Trajectory& trajectory = mapper.trajectory();
  mrpt::maps::COccupancyGridMap2D grid;
  {
    auto t = timer.Time("grid");
    grid = slam::BuildGrid(mapper.keyframes(), grid_options);
  }
  const auto& stats = mapper.stats();
  auto& j = report.json();
  j["inputs"] = {{"dataset", dataset}, {"format", source->Format()}, {"ground_truth", gt_path},
                 {"params_files", common.param_files}, {"overrides", common.overrides}};
  j["counts"] = {{"observations", run.observations}, {"scans", stats.scans}, {"keyframes", stats.keyframes},
                 {"rejected_matches", stats.rejected_matches}, {"odometry", stats.odometry},
                 {"ignored", stats.ignored}};
  const double data_s = run.first ? SecondsBetween(*run.first, *run.last) : 0.0;
  const double matching_ms = timer.TotalMs("scan_matching");
  j["metrics"]["path_length_m"] = PathLength(trajectory);
  const auto walls = eval::MeasureWallThickness(grid);
  j["metrics"]["wall_thickness_p50_m"] = walls.p50_m;
  j["metrics"]["wall_thickness_p95_m"] = walls.p95_m;
  j["metrics"]["map_size_m"] = {grid.getXMax() - grid.getXMin(), grid.getYMax() - grid.getYMin()};

  Trajectory reference_in_map;
  if (!reference.empty() && trajectory.size() >= 2) {
    try {
      const auto ate = eval::AbsoluteTrajectoryError2D(trajectory, reference, 0.05);
      j["metrics"]["ate"] = {{"pairs", ate.pairs}, {"rmse_m", ate.rmse_m}, {"mean_m", ate.mean_m},
                             {"max_m", ate.max_m}, {"rmse_deg", ate.rmse_deg}, {"final_m", ate.final_error_m}};
      reference_in_map = eval::Transform(reference, -ate.alignment);
      spdlog::info("ATE against {}: RMSE {:.3f} m, max {:.3f} m, {:.2f} deg RMSE", gt_path, ate.rmse_m, ate.max_m,
                   ate.rmse_deg);
    } catch (const InputError& e) {
      spdlog::warn("ground truth not used: {}", e.what());
    }
  }

  const std::string out = common.out_dir;
  {
    auto t = timer.Time("write");
    io::WriteRosMap(grid, out + "/map.yaml");
    io::WriteMrptGridmap(grid, out + "/map.gridmap");
    io::WriteTum(trajectory, out + "/trajectory.tum");
    std::vector<io::PathOverlay> paths;
    if (!reference_in_map.empty()) paths.push_back({&reference_in_map, {40, 170, 60}, "ground truth"});
    paths.push_back({&trajectory, {30, 90, 220}, "estimate"});
    io::WriteMapPng(grid, paths, out + "/map.png");
  }
  for (const char* f : {"map.yaml", "map.pgm", "map.gridmap", "map.png", "trajectory.tum", "params.yaml"}) {
    report.AddOutput(f);
  }
  j["timing"] = {{"stages", timer.ToJson()},
                 {"wall_s", run.wall_s},
                 {"data_s", data_s},
                 {"real_time_factor", run.wall_s > 0 ? data_s / run.wall_s : 0.0},
                 {"ms_per_scan", stats.scans > 0 ? matching_ms / stats.scans : 0.0}};
  report.Write(out);
  spdlog::info("replay: {} scans, {} keyframes, {:.1f} m driven, {:.2f} ms/scan, {:.0f}x real time{}", stats.scans,
               stats.keyframes, PathLength(trajectory), stats.scans ? matching_ms / stats.scans : 0.0,
               run.wall_s > 0 ? data_s / run.wall_s : 0.0, exit_code ? " (INCOMPLETE)" : "");
  return exit_code;
}

}  // namespace

void AddReplayCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<ReplayArgs>();
  CLI::App* cmd = app.add_subcommand("replay", "replay a dataset into a map and trajectory");
  cmd->add_option("dataset", args->dataset,
                  "MRPT rawlog (default: the rawlog shipped by Debian's mrpt-common, " + io::DefaultRawlog() + ")");
  AddCommonOptions(*cmd, args->common, "specht-out/replay");
  cmd->add_option("--ground-truth", args->ground_truth,
                  "reference trajectory (TUM or 't x y theta'); default <dataset>.GT.txt when present");
  cmd->add_option("--rate", args->rate, "pace at R x real time (same as --set replay.rate=R)");
  cmd->add_option("--from", args->from_s, "start S seconds into the data (replay.from_s)");
  cmd->add_option("--to", args->to_s, "stop S seconds into the data (replay.to_s)");
  cmd->callback([args, &exit_code] { exit_code = RunReplay(*args); });
}

}  // namespace specht::app
