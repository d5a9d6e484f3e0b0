#include "mapping_run.h"

#include <algorithm>
#include <chrono>
#include <functional>
#include <tuple>
#include <filesystem>
#include <map>

#include "specht/core/error.h"
#include "specht/core/log.h"
#include "specht/core/progress.h"
#include "specht/core/transform_tree.h"
#include "specht/eval/map_quality.h"
#include "specht/eval/relation_error.h"
#include "specht/eval/trajectory_error.h"
#include "specht/io/carmen.h"
#include "specht/io/atomic_file.h"
#include "specht/io/data_dir.h"
#include "specht/io/dataset.h"
#include "specht/io/g2o.h"
#include "specht/io/map_io.h"
#include "specht/io/replay.h"
#include "specht/io/rawlog_writer.h"
#include "specht/io/reference.h"
#include "specht/io/report.h"
#include "specht/io/trajectory_io.h"
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationStereoImages.h>
#include "specht/slam/graph_slam.h"
#include "specht/slam/localizer.h"
#include "specht/pipeline/stereo_perception.h"
#include "specht/world/world_model.h"

namespace specht::app {
namespace {

std::string Real(double v) {
  std::ostringstream s;
  s.precision(15);
  s << v;
  return s.str();
}

struct DriveResult {
  std::map<std::string, long> observations;  // by MRPT class name
  std::optional<Stamp> first, last;
  double wall_s = 0;
};

// Feeds every observation inside the replay window to `add` (which returns the scans
// processed so far and a note for the progress line).
using Consumer = std::function<std::pair<long, std::string>(Stamp, const mrpt::obs::CObservation::Ptr&)>;

DriveResult Drive(io::DatasetSource& source, io::ReplayClock& clock, const Consumer& add, io::StageTimer& timer,
                  io::RunReport& report, bool quiet, int& exit_code) {
  DriveResult r;
  ProgressLine progress(report.json().value("command", "run"), "scans", !quiet);
  const auto wall0 = std::chrono::steady_clock::now();
  long scans = 0;
  while (true) {
    std::optional<io::Observation> obs;
    try {
      auto t = timer.Time("read");
      obs = source.Next();
    } catch (const io::DatasetError& e) {
      // Stop here and keep everything computed so far.
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
    std::string note;
    {
      auto t = timer.Time("slam");
      std::tie(scans, note) = add(obs->stamp, obs->data);
    }
    if (!r.first) r.first = obs->stamp;
    r.last = obs->stamp;
    progress.Update(static_cast<double>(scans), source.FractionRead(), note);
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  progress.Finish();
  return r;
}

// Metrics against the reference, when there is one; returns the reference moved into
// the map frame for the picture.
Trajectory AddReferenceMetrics(const Trajectory& trajectory, const Trajectory& reference, nlohmann::json& metrics) {
  if (reference.empty() || trajectory.size() < 2) return {};
  try {
    const auto ate = eval::AbsoluteTrajectoryError2D(trajectory, reference, 0.05);
    metrics["ate"] = eval::ToJson(ate);
    eval::RelationOptions rel_options;
    rel_options.max_dt_s = 0.05;
    const auto rel = eval::ComputeRelationError(trajectory, reference, rel_options);
    metrics["relation"] = eval::ToJson(rel);
    spdlog::info("against the reference: ATE RMSE {:.3f} m; relation error {:.4f} ± {:.4f} m (max {:.3f}), "
                 "{:.3f} ± {:.3f} deg over {} relations",
                 ate.rmse_m, rel.all.mean_m, rel.all.std_m, rel.all.max_m, rel.all.mean_deg, rel.all.std_deg,
                 rel.all.count);
    return eval::Transform(reference, -ate.alignment);
  } catch (const InputError& e) {
    spdlog::warn("reference not used: {}", e.what());
    return {};
  }
}

// Mean map entropy of the keyframe scans at the estimated poses and, with a
// reference, of the same scans at the estimate's and at the reference's poses
// (eval/map_quality.h): whether the reference's map is sharper than ours.
void AddMapEntropy(const std::vector<slam::Keyframe>& keyframes, const Trajectory& reference,
                   nlohmann::json& metrics) {
  const eval::MapEntropy ours = eval::MeanMapEntropy(keyframes);
  metrics["map_entropy"] = {{"mean_nats", ours.mean_nats}, {"points", ours.points}};
  if (reference.empty()) return;
  const auto [at_estimate, at_reference] = eval::KeyframesAtReference(keyframes, reference, 0.05);
  if (at_estimate.size() < 2) return;
  const eval::MapEntropy a = at_estimate.size() == keyframes.size() ? ours : eval::MeanMapEntropy(at_estimate);
  const eval::MapEntropy b = eval::MeanMapEntropy(at_reference);
  metrics["map_entropy_vs_reference"] = {
      {"keyframes", at_estimate.size()}, {"estimate_nats", a.mean_nats}, {"reference_nats", b.mean_nats}};
  spdlog::info("map entropy: {:.3f} nats at the estimated poses, {:.3f} at the reference's ({} keyframes; lower is "
               "sharper)",
               a.mean_nats, b.mean_nats, at_estimate.size());
}

// The map artefact: grid (ROS + MRPT), pose graph (g2o; node i = keyframe i) and the
// keyframe scans (rawlog, in node order): what localization and continuing need.
void WriteMapArtefact(const slam::GraphSlam& slam, const mrpt::maps::COccupancyGridMap2D& grid,
                      const std::string& out) {
  io::WriteRosMap(grid, out + "/map.yaml");
  io::WriteMrptGridmap(grid, out + "/map.gridmap");
  io::WriteG2o(slam.graph(), out + "/graph.g2o");
  io::RawlogWriter keyframes(out + "/keyframes.rawlog");
  for (const auto& kf : slam.keyframes()) keyframes.Write(*kf.scan);
  keyframes.Close();
}

// The loop closures as the final graph holds them (slam/pose_graph_optimizer.h's
// LoopResiduals): how many the robust loss keeps (weight ≥ 0.5), weakens, or sets
// aside (< 0.1: aliases, or matches off by far more than their noise); their errors;
// the worst by χ², named by their keyframes' scans; and loops.png, every loop drawn on
// the map in the colour of its weight.
void ReportLoops(const slam::GraphSlam& slam, const slam::PoseGraphOptions& options,
                 const mrpt::maps::COccupancyGridMap2D& grid, const Trajectory& trajectory, const std::string& out,
                 nlohmann::json& metrics) {
  std::vector<slam::LoopResidual> loops = slam::LoopResiduals(slam.graph(), options);
  const auto& keyframes = slam.keyframes();
  const auto& nodes = slam.graph().nodes;
  constexpr double kKeptWeight = 0.5, kSetAsideWeight = 0.1;
  Trajectory kept, weakened, set_aside;  // the loops' end poses in pairs, as PathOverlay segments
  std::vector<double> kept_m;
  for (const auto& l : loops) {
    Trajectory& group = l.weight >= kKeptWeight ? kept : l.weight >= kSetAsideWeight ? weakened : set_aside;
    for (int id : {l.from, l.to}) {
      const mrpt::poses::CPose2D& p = nodes.at(id);
      group.push_back({Stamp{}, mrpt::poses::CPose3D(p.x(), p.y(), 0, p.phi(), 0, 0)});
    }
    if (&group == &kept) kept_m.push_back(l.error_m);
  }
  std::sort(kept_m.begin(), kept_m.end());
  auto quantile = [&](double q) { return kept_m.empty() ? 0.0 : kept_m[static_cast<size_t>(q * (kept_m.size() - 1))]; };
  nlohmann::json j = {{"edges", loops.size()},
                      {"kept", kept.size() / 2},
                      {"weakened", weakened.size() / 2},
                      {"set_aside", set_aside.size() / 2},
                      {"kept_error_m", {{"p50", quantile(0.5)}, {"p95", quantile(0.95)}, {"max", quantile(1.0)}}}};
  std::sort(loops.begin(), loops.end(), [](const auto& a, const auto& b) { return a.chi2 > b.chi2; });
  nlohmann::json worst = nlohmann::json::array();
  for (size_t i = 0; i < std::min<size_t>(5, loops.size()); ++i) {
    const auto& l = loops[i];
    const auto scan = [&](int id) { return keyframes.at(static_cast<size_t>(id)).scan_index; };
    const auto t = [&](int id) { return keyframes.at(static_cast<size_t>(id)).stamp.Seconds(); };
    worst.push_back({{"from_scan", scan(l.from)}, {"to_scan", scan(l.to)}, {"t_from", t(l.from)}, {"t_to", t(l.to)},
                     {"error_m", l.error_m}, {"error_deg", l.error_deg}, {"weight", l.weight}});
  }
  j["worst"] = worst;
  metrics["loops"] = j;
  spdlog::info("loops in the final graph: {} kept, {} weakened, {} set aside by the robust loss (kept: error p50 "
               "{:.3f} m, p95 {:.3f} m)",
               kept.size() / 2, weakened.size() / 2, set_aside.size() / 2, quantile(0.5), quantile(0.95));
  const std::vector<io::PathOverlay> paths = {
      {&trajectory, {30, 90, 220}, "estimate"},
      {&kept, {40, 170, 60}, "loop kept (" + std::to_string(kept.size() / 2) + ")", false, true},
      {&weakened, {240, 150, 0}, "loop weakened (" + std::to_string(weakened.size() / 2) + ")", false, true},
      {&set_aside, {220, 30, 30}, "loop set aside (" + std::to_string(set_aside.size() / 2) + ")", false, true}};
  io::WriteMapPng(grid, paths, out + "/loops.png");
}

struct SavedMap {
  std::vector<slam::Keyframe> keyframes;  // poses from the graph
  PoseGraph2D graph;
  mrpt::maps::COccupancyGridMap2D grid;
};

SavedMap ReadMapArtefact(const std::string& dir) {
  for (const char* f : {"graph.g2o", "keyframes.rawlog", "map.gridmap"}) {
    if (!std::filesystem::is_regular_file(dir + "/" + f)) {
      throw InputError(dir + ": not a specht map (missing " + f + "; write one with `specht slam -o DIR`)");
    }
  }
  const io::G2oReadResult graph = io::ReadG2o(dir + "/graph.g2o");
  std::vector<mrpt::obs::CObservation2DRangeScan::Ptr> scans;
  auto rawlog = io::OpenRawlog(dir + "/keyframes.rawlog");
  while (auto obs = rawlog->Next()) {
    if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs->data)) scans.push_back(scan);
  }
  std::vector<mrpt::poses::CPose2D> poses;
  for (const auto& [id, pose] : graph.graph.nodes) poses.push_back(pose);
  if (scans.size() != poses.size() || scans.empty()) {
    throw InputError(dir + ": map artefact is inconsistent: " + std::to_string(scans.size()) +
                     " keyframe scans in keyframes.rawlog but " + std::to_string(poses.size()) +
                     " nodes in graph.g2o");
  }
  return {slam::KeyframesFromGraph(scans, poses), graph.graph, io::ReadMrptGridmap(dir + "/map.gridmap")};
}

}  // namespace

void AddMappingOptions(CLI::App& cmd, MappingArgs& args, const std::string& default_out) {
  cmd.add_option("dataset", args.dataset,
                 "MRPT rawlog or CARMEN log (default: the rawlog shipped by Debian's mrpt-common, " +
                     io::DefaultRawlog() + ")");
  AddCommonOptions(cmd, args.common, default_out);
  cmd.add_option("--ground-truth", args.ground_truth,
                 "reference trajectory (TUM, 't x y theta' or CARMEN log); default <dataset>.GT.txt when present, "
                 "or the corrected poses of a CARMEN log");
  cmd.add_option("--map", args.map_dir,
                 "localize on the map artefact in this directory (written by `specht slam`) instead of mapping");
  cmd.add_option("--continue", args.continue_dir,
                 "continue the map artefact in this directory: localize the first scan on it, then map on, "
                 "closing loops against it (writes the extended map)")
      ->excludes("--map");
  cmd.add_option("--rate", args.rate, "pace at R x real time (same as --set replay.rate=R)");
  cmd.add_option("--from", args.from_s, "start S seconds into the data (replay.from_s)");
  cmd.add_option("--to", args.to_s, "stop S seconds into the data (replay.to_s)");
}

// The perception stage: stereo observations → obstacles in the world model, placed
// at the current pose estimate. Built at the first stereo observation; under
// perception "auto" a detector that cannot load (no models) turns the stage off with
// a warning, under "on" it is an error.
class PerceptionStage {
 public:
  PerceptionStage(const params::Params& params, const std::string& data_dir)
      : params_(params), data_dir_(data_dir), mode_(params.Get<io::ReplayOptions>("replay").perception),
        world_(params.Get<world::WorldModelOptions>("world")) {}

  void Add(Stamp t, const mrpt::obs::CObservation::Ptr& o, const std::function<mrpt::poses::CPose3D()>& pose) {
    auto stereo = std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(o);
    if (!stereo || mode_ == "off") return;
    if (!perception_ && !Start()) return;
    const auto obstacles = perception_->Process(*stereo, pose(), t);
    world_.AddObstacles(obstacles, t);
    for (const auto& ob : obstacles) seen_[ob.cls].push_back({ob.stamp, mrpt::poses::CPose3D(ob.x_m, ob.y_m, 0, 0, 0, 0)});
  }

  void Report(nlohmann::json& j) const {
    if (!perception_) return;
    const auto& s = perception_->stats();
    j["perception"] = {{"frames", s.frames},
                       {"detections", s.detections},
                       {"obstacles", s.obstacles},
                       {"ms_per_frame",
                        {{"stereo", s.stereo_ms / s.frames}, {"detect", s.detect_ms / s.frames},
                         {"fusion", s.fusion_ms / s.frames}}}};
  }
  // Obstacles seen, per class, as map markers.
  const std::map<std::string, Trajectory>& seen() const { return seen_; }
  const world::WorldModel& world() const { return world_; }
  void SetStaticMap(const mrpt::maps::COccupancyGridMap2D& grid, Stamp t) {
    if (perception_) world_.SetStaticMap(grid, t);
  }
  bool active() const { return perception_ != nullptr; }

 private:
  bool Start() {
    try {
      perception_ = std::make_unique<pipeline::StereoPerception>(
          params_.Get<stereo::SgmOptions>("stereo"), params_.Get<detect::DetectorOptions>("detect"),
          params_.Get<detect::FusionOptions>("fusion"), data_dir_);
    } catch (const InputError& e) {
      if (mode_ == "on") throw;
      spdlog::warn("perception off: {}", e.what());
      mode_ = "off";
      return false;
    }
    return true;
  }

  const params::Params& params_;
  std::string data_dir_;
  std::string mode_;
  world::WorldModel world_;
  std::unique_ptr<pipeline::StereoPerception> perception_;
  std::map<std::string, Trajectory> seen_;
};

mrpt::poses::CPose3D LatestPose(const Trajectory& t) { return t.empty() ? mrpt::poses::CPose3D() : t.back().pose; }

int RunMapping(MappingArgs a, const std::string& command) {
  CommonArgs& common = a.common;
  if (a.rate) common.overrides.push_back("replay.rate=" + Real(*a.rate));
  if (a.from_s) common.overrides.push_back("replay.from_s=" + Real(*a.from_s));
  if (a.to_s) common.overrides.push_back("replay.to_s=" + Real(*a.to_s));

  // Everything that can be wrong with the input is checked before anything is written.
  const params::Params params = LoadParams(common);
  const auto& frames_options = params.Get<FramesOptions>("frames");
  const auto& replay_options = params.Get<io::ReplayOptions>("replay");
  const std::string data_dir = io::ResolveDataDir(common.data_dir).value_or("");
  const std::string dataset = a.dataset.empty() ? io::DefaultRawlog() : a.dataset;
  auto source = io::OpenDataset(dataset, replay_options.on_bad_record == "skip" ? io::OnBadRecord::kSkip
                                                                                : io::OnBadRecord::kStop);
  const std::string gt_path =
      a.ground_truth.empty() ? io::DefaultReferencePath(dataset, source->Format()) : a.ground_truth;
  const Trajectory reference = gt_path.empty() ? Trajectory{} : io::ReadReference(gt_path);
  SavedMap saved;
  if (!a.map_dir.empty()) saved = ReadMapArtefact(a.map_dir);
  if (!a.continue_dir.empty()) saved = ReadMapArtefact(a.continue_dir);
  PrepareOutputDir(common, params);

  spdlog::info("{}: {} -> {}{}{}", command, dataset, common.out_dir,
               a.map_dir.empty() ? "" : " (localization on " + a.map_dir + ")",
               a.continue_dir.empty() ? "" : " (continuing " + a.continue_dir + ")");
  TransformTree frames(frames_options);
  io::ReplayClock clock(replay_options);
  io::StageTimer timer;
  io::RunReport report(command);
  auto& j = report.json();
  j["inputs"] = {{"dataset", dataset}, {"format", source->Format()}, {"ground_truth", gt_path},
                 {"map", a.map_dir}, {"continue", a.continue_dir}, {"params_files", common.param_files},
                 {"overrides", common.overrides}};
  int exit_code = 0;
  const std::string out = common.out_dir;
  PerceptionStage perception(params, data_dir);

  Trajectory trajectory;
  std::vector<slam::Keyframe> keyframes;  // mapping only
  mrpt::maps::COccupancyGridMap2D grid;
  DriveResult run;
  slam::MappingStats fe;
  // Localization on the saved map: the whole run with --map, the first scan with --continue.
  const auto localizer_on_saved = [&] {
    return std::make_unique<slam::Localizer>(saved.keyframes, params.Get<slam::LocalizationOptions>("localization"),
                                             params.Get<slam::ScanMatchingOptions>("scan_matching"), &frames,
                                             frames_options.base_frame);
  };
  if (!a.map_dir.empty()) {
    const auto located = localizer_on_saved();
    slam::Localizer& localizer = *located;
    run = Drive(*source, clock,
                [&](Stamp t, const mrpt::obs::CObservation::Ptr& o) {
                  localizer.Add(t, o);
                  perception.Add(t, o, [&] { return LatestPose(localizer.trajectory()); });
                  return std::make_pair(localizer.stats().scans, std::string());
                },
                timer, report, common.quiet, exit_code);
    trajectory = localizer.trajectory();
    fe = localizer.stats();
    if (localizer.global_score()) j["metrics"]["global_search_score"] = *localizer.global_score();
    grid = saved.grid;
  } else {
    slam::GraphSlam slam(params.Get<slam::SlamOptions>("slam"), params.Get<slam::ScanMatchingOptions>("scan_matching"),
                         params.Get<slam::LoopClosureOptions>("loop_closure"),
                         params.Get<slam::PoseGraphOptions>("pose_graph"), &frames, frames_options.base_frame);
    // Continuing: observations go to a localizer on the saved map until it has placed
    // the first scan; that scan then starts the new keyframes at its pose.
    std::unique_ptr<slam::Localizer> locate;
    if (!a.continue_dir.empty()) locate = localizer_on_saved();
    run = Drive(*source, clock,
                [&](Stamp t, const mrpt::obs::CObservation::Ptr& o) {
                  if (locate) {
                    locate->Add(t, o);
                    if (locate->trajectory().empty()) return std::make_pair(0L, std::string("locating"));
                    const mrpt::poses::CPose3D& p = locate->trajectory().front().pose;
                    slam.Continue(saved.keyframes, saved.graph, mrpt::poses::CPose2D(p.x(), p.y(), p.yaw()));
                    if (locate->global_score()) j["metrics"]["continue_global_search_score"] = *locate->global_score();
                    locate.reset();
                  }
                  slam.Add(t, o);
                  perception.Add(t, o, [&] { return LatestPose(slam.trajectory()); });
                  return std::make_pair(slam.front_end_stats().scans,
                                        "loops " + std::to_string(slam.stats().loops_accepted));
                },
                timer, report, common.quiet, exit_code);
    {
      auto t = timer.Time("slam");
      slam.Finish();
    }
    trajectory = slam.trajectory();
    keyframes = slam.keyframes();
    fe = slam.front_end_stats();
    {
      auto t = timer.Time("grid");
      grid = slam::BuildGrid(slam.keyframes(), params.Get<slam::GridOptions>("grid"));
    }
    const auto& be = slam.stats();
    j["counts"] = {{"keyframes", fe.keyframes},         {"loop_searches", be.loop_searches},
                   {"loops_found", be.loops_found},     {"loops_accepted", be.loops_accepted},
                   {"optimizations", be.optimizations}};
    j["metrics"]["graph_chi2"] = be.final_chi2;
    j["timing"]["loop_search_ms"] = be.loop_search_ms;
    j["timing"]["optimize_ms"] = be.optimize_ms;
    auto t = timer.Time("write");
    WriteMapArtefact(slam, grid, out);
    ReportLoops(slam, params.Get<slam::PoseGraphOptions>("pose_graph"), grid, trajectory, out, j["metrics"]);
    for (const char* f : {"map.yaml", "map.pgm", "map.gridmap", "graph.g2o", "keyframes.rawlog", "loops.png"})
      report.AddOutput(f);
  }
  for (const auto& skipped : source->SkippedRecords()) spdlog::warn("skipped {}", skipped);

  j["counts"]["observations"] = run.observations;
  j["counts"]["scans"] = fe.scans;
  j["counts"]["rejected_matches"] = fe.rejected_matches;
  j["counts"]["recovered_matches"] = fe.recovered_matches;
  j["counts"]["rechecked_steps"] = fe.rechecked_steps;
  j["counts"]["odometry"] = fe.odometry;
  j["counts"]["imu"] = fe.imu;
  j["counts"]["ignored"] = fe.ignored;
  j["counts"]["skipped_records"] = source->SkippedRecords().size();
  const double data_s = run.first ? SecondsBetween(*run.first, *run.last) : 0.0;
  const double slam_ms = timer.TotalMs("slam");
  j["metrics"]["path_length_m"] = PathLength(trajectory);
  const auto walls = eval::MeasureWallThickness(grid);
  j["metrics"]["wall_thickness_p50_m"] = walls.p50_m;
  j["metrics"]["wall_thickness_p95_m"] = walls.p95_m;
  j["metrics"]["map_size_m"] = {grid.getXMax() - grid.getXMin(), grid.getYMax() - grid.getYMin()};
  const Trajectory reference_in_map = AddReferenceMetrics(trajectory, reference, j["metrics"]);
  if (!keyframes.empty()) {
    auto t = timer.Time("map_entropy");
    AddMapEntropy(keyframes, reference, j["metrics"]);
  }
  {
    auto t = timer.Time("write");
    io::WriteTum(trajectory, out + "/trajectory.tum");
    std::vector<io::PathOverlay> paths;
    if (!reference_in_map.empty()) paths.push_back({&reference_in_map, {40, 170, 60}, "reference"});
    paths.push_back({&trajectory, {30, 90, 220}, "estimate"});
    static const std::map<std::string, std::array<unsigned char, 3>> kClassColours = {
        {"pedestrian", {220, 30, 30}}, {"cyclist", {230, 180, 0}}, {"car", {240, 120, 0}}};
    for (const auto& [cls, where] : perception.seen()) {
      const auto colour = kClassColours.count(cls) ? kClassColours.at(cls) : std::array<unsigned char, 3>{120, 0, 160};
      paths.push_back({&where, colour, cls + " (" + std::to_string(where.size()) + ")", true});
    }
    io::WriteMapPng(grid, paths, out + "/map.png");
    if (perception.active()) {
      perception.SetStaticMap(grid, run.last ? *run.last : Stamp{});
      io::WriteTextAtomically(out + "/world.json", perception.world().snapshot()->ToJson().dump(1) + "\n");
      report.AddOutput("world.json");
    }
  }
  perception.Report(j);
  for (const char* f : {"map.png", "trajectory.tum", "params.yaml"}) report.AddOutput(f);
  j["timing"]["stages"] = timer.ToJson();
  j["timing"]["wall_s"] = run.wall_s;
  j["timing"]["data_s"] = data_s;
  j["timing"]["real_time_factor"] = run.wall_s > 0 ? data_s / run.wall_s : 0.0;
  j["timing"]["ms_per_scan"] = fe.scans > 0 ? slam_ms / fe.scans : 0.0;
  report.Write(out);
  spdlog::info("{}: {} scans, {:.1f} m, {:.2f} ms/scan, {:.0f}x real time{}", command, fe.scans,
               PathLength(trajectory), fe.scans ? slam_ms / fe.scans : 0.0, run.wall_s > 0 ? data_s / run.wall_s : 0.0,
               exit_code ? " (INCOMPLETE)" : "");
  return exit_code;
}

}  // namespace specht::app
