#include "specht/pipeline/replay.h"

#include <chrono>
#include <functional>
#include <map>
#include <optional>
#include <tuple>

#include "internal/dataset_drive.h"
#include "internal/map_outputs.h"
#include "internal/perception_video.h"
#include "internal/ros_recorder.h"
#include "specht/core/error.h"
#include "specht/core/interrupt.h"
#include "specht/core/log.h"
#include "specht/core/progress.h"
#include "specht/core/transform_tree.h"
#include "specht/eval/map_quality.h"
#include "specht/io/atomic_file.h"
#include "specht/io/data_dir.h"
#include "specht/io/dataset.h"
#include "specht/io/map_io.h"
#include "specht/io/reference.h"
#include "specht/io/replay.h"
#include "specht/io/report.h"
#include "specht/io/ros_bag.h"
#include "specht/io/trajectory_io.h"
#include "specht/pipeline/perception.h"
#include "specht/slam/graph_slam.h"
#include "specht/slam/localizer.h"

namespace specht::pipeline {
namespace {

using internal::Drive;
using internal::DriveResult;

// A run that placed no scan has no result to write: an error naming the reason (the
// record it broke off at, or what the replay window held), not an empty map. An
// interrupt before the first scan still ends as an interrupt.
void RequireScans(long scans, const DriveResult& run, io::RunReport& report, const std::string& dataset) {
  if (scans > 0 || InterruptRequested()) return;
  if (report.json().contains("error")) throw InputError(report.json()["error"].get<std::string>());
  std::string held;
  for (const auto& [type, n] : run.observations) held += (held.empty() ? "" : ", ") + std::to_string(n) + " " + type;
  throw InputError(dataset + ": no laser scan to map with" +
                   (held.empty() ? std::string(" (no record in the replay window)") : " (it holds " + held + ")"));
}

// What SLAM (or the localizer) ends with.
struct Estimate {
  Trajectory trajectory;
  std::vector<slam::Keyframe> keyframes;  // mapping only
  mrpt::maps::COccupancyGridMap2D grid;
  slam::MappingStats front_end;
};

}  // namespace

std::unique_ptr<io::DatasetSource> OpenDatasetSource(const std::string& path, const io::ReplayOptions& replay) {
  const auto on_bad = replay.on_bad_record == "skip" ? io::OnBadRecord::kSkip : io::OnBadRecord::kStop;
  const io::BagTopicChoice topics{replay.scan_topic, replay.odometry_topic};
  return io::IsRos2Bag(path)   ? io::OpenRos2Bag(path, topics, on_bad)
         : io::IsMcap(path)    ? io::OpenMcap(path, topics, on_bad)
         : io::IsRos1Bag(path) ? io::OpenRos1Bag(path, topics, on_bad)
                               : io::OpenDataset(path, on_bad);
}

struct Replay::State {
  const params::Params& params;
  ReplayInputs in;
  std::string command;
  std::unique_ptr<io::DatasetSource> source;
  std::string reference_path;
  Trajectory reference;
  std::optional<io::RelationsFile> relations;
  std::string reference_map;  // map_server YAML, or ""
  MapArtefact saved;
  std::unique_ptr<PerceptionPipeline> perception;
  std::unique_ptr<internal::RosRecorder> mcap;  // --mcap, and a node's published estimates

  // The parts of one run.
  Estimate Localize(io::ReplayClock& clock, PerceptionPipeline& perception, io::StageTimer& timer,
                    io::RunReport& report, TransformTree& frames, DriveResult& run, bool quiet, int& exit_code);
  Estimate Map(io::ReplayClock& clock, PerceptionPipeline& perception, io::StageTimer& timer, io::RunReport& report,
               TransformTree& frames, DriveResult& run, const std::string& out, bool quiet, int& exit_code);
  std::unique_ptr<slam::Localizer> LocalizerOnSaved(TransformTree& frames) const;
};

Replay::Replay(const params::Params& params, ReplayInputs in, std::string command)
    : state_(std::make_unique<State>(
          State{params, std::move(in), std::move(command), nullptr, "", {}, {}, "", {}, nullptr, nullptr})) {
  State& s = *state_;
  if (s.in.node) {
    s.source = net::SubscribeTopics(s.in.node->participant, s.in.node->topics);
    s.in.dataset = s.source->Path();
  } else {
    if (s.in.dataset.empty()) s.in.dataset = io::DefaultRawlog();
    s.source = OpenDatasetSource(s.in.dataset, params.Get<io::ReplayOptions>("replay"));
  }
  const bool file = !s.in.node;
  s.reference_path = s.in.ground_truth.empty() && file ? io::DefaultReferencePath(s.in.dataset, s.source->Format())
                                                       : s.in.ground_truth;
  if (!s.reference_path.empty()) s.reference = io::ReadReference(s.reference_path);
  const std::string relations =
      s.in.relations.empty() && file ? io::DefaultRelationsPath(s.in.dataset) : s.in.relations;
  if (!relations.empty()) s.relations = io::ReadRelations(relations);
  s.reference_map = s.in.reference_map;
  if (s.reference_map.empty() && io::IsRos2Bag(s.in.dataset) && std::filesystem::is_directory(s.in.dataset) &&
      std::filesystem::is_regular_file(s.in.dataset + "/map.yaml"))
    s.reference_map = s.in.dataset + "/map.yaml";
  if (!s.reference_map.empty() && !std::filesystem::is_regular_file(s.reference_map))
    throw InputError(s.reference_map + ": no such reference map");
  if (!s.in.map_dir.empty()) s.saved = ReadMapArtefact(s.in.map_dir);
  if (!s.in.continue_dir.empty()) s.saved = ReadMapArtefact(s.in.continue_dir);
  s.perception = std::make_unique<PerceptionPipeline>(params, s.in.data_dir);
}

Replay::~Replay() = default;

std::unique_ptr<slam::Localizer> Replay::State::LocalizerOnSaved(TransformTree& frames) const {
  return std::make_unique<slam::Localizer>(saved.keyframes, params.Get<slam::LocalizationOptions>("localization"),
                                           params.Get<slam::ScanMatchingOptions>("scan_matching"), &frames,
                                           params.Get<FramesOptions>("frames").base_frame);
}

// Localization on the saved map: every scan placed on it; the world model's static
// layer is the saved grid.
Estimate Replay::State::Localize(io::ReplayClock& clock, PerceptionPipeline& perception, io::StageTimer& timer,
                                 io::RunReport& report, TransformTree& frames, DriveResult& run, bool quiet,
                                 int& exit_code) {
  const auto located = LocalizerOnSaved(frames);
  slam::Localizer& localizer = *located;
  size_t placed = 0;
  run = Drive(
      *source, clock,
      [&](Stamp t, const mrpt::obs::CObservation::Ptr& o) {
        {
          auto timing = timer.Time("slam");
          localizer.Add(t, o);
        }
        if (mcap) {
          auto timing = timer.Time("mcap");
          mcap->Observation(t, o);
          const auto& p = localizer.trajectory();
          if (p.size() > placed) mcap->Pose(p.back().stamp, p.back().pose);
        }
        auto timing = timer.Time("perception");
        perception.Add(t, o);
        // The saved grid is the static layer, once perception has started.
        if (perception.active() && !perception.world().snapshot()->static_map) perception.SetStaticMap(saved.grid, t);
        for (const auto& p = localizer.trajectory(); placed < p.size(); ++placed)
          perception.AddPose(p[placed].stamp, p[placed].pose);
        return std::make_pair(localizer.stats().scans, std::string());
      },
      timer, report, quiet, exit_code);
  RequireScans(localizer.stats().scans, run, report, in.dataset);
  if (localizer.global_score()) report.json()["metrics"]["global_search_score"] = *localizer.global_score();
  return {localizer.trajectory(), {}, saved.grid, localizer.stats()};
}

// Mapping (or continuing the saved map): graph SLAM, the map artefact and the loop report.
Estimate Replay::State::Map(io::ReplayClock& clock, PerceptionPipeline& perception, io::StageTimer& timer,
                            io::RunReport& report, TransformTree& frames, DriveResult& run, const std::string& out,
                            bool quiet, int& exit_code) {
  auto& j = report.json();
  const auto& grid_options = params.Get<slam::GridOptions>("grid");
  slam::GraphSlam slam(params.Get<slam::SlamOptions>("slam"), params.Get<slam::ScanMatchingOptions>("scan_matching"),
                       params.Get<slam::LoopClosureOptions>("loop_closure"),
                       params.Get<slam::PoseGraphOptions>("pose_graph"), &frames,
                       params.Get<FramesOptions>("frames").base_frame);
  // Continuing: observations go to a localizer on the saved map until it has placed
  // the first scan; that scan then starts the new keyframes at its pose.
  std::unique_ptr<slam::Localizer> locate;
  if (!in.continue_dir.empty()) locate = LocalizerOnSaved(frames);
  long scans_placed = 0, optimizations = 0;
  run = Drive(
      *source, clock,
      [&](Stamp t, const mrpt::obs::CObservation::Ptr& o) {
        if (locate) {
          locate->Add(t, o);
          if (locate->trajectory().empty()) return std::make_pair(0L, std::string("locating"));
          const mrpt::poses::CPose3D& p = locate->trajectory().front().pose;
          slam.Continue(saved.keyframes, saved.graph, mrpt::poses::CPose2D(p.x(), p.y(), p.yaw()));
          if (locate->global_score()) j["metrics"]["continue_global_search_score"] = *locate->global_score();
          locate.reset();
        }
        {
          auto timing = timer.Time("slam");
          slam.Add(t, o);
        }
        if (mcap) {
          auto timing = timer.Time("mcap");
          mcap->Observation(t, o);
        }
        auto timing = timer.Time("perception");
        perception.Add(t, o);
        if (slam.front_end_stats().scans > scans_placed) {
          scans_placed = slam.front_end_stats().scans;
          const auto latest = slam.LatestPose();
          perception.AddPose(latest->stamp, latest->pose);
          // The static layer as the map grows, and at once after a loop closure moved it.
          const bool moved = slam.stats().optimizations > optimizations;
          optimizations = slam.stats().optimizations;
          if (mcap) {
            auto timing = timer.Time("mcap");
            mcap->Pose(latest->stamp, latest->pose);
            mcap->Keyframes(slam.keyframes(), moved, latest->stamp);
          }
          if (perception.active() && (moved || perception.StaticMapDue(t)))
            perception.SetStaticMap(slam::BuildGrid(slam.keyframes(), grid_options), latest->stamp);
        }
        return std::make_pair(slam.front_end_stats().scans, "loops " + std::to_string(slam.stats().loops_accepted));
      },
      timer, report, quiet, exit_code);
  RequireScans(slam.front_end_stats().scans, run, report, in.dataset);
  {
    auto t = timer.Time("slam");
    slam.Finish();
  }
  Estimate e{slam.trajectory(), slam.keyframes(), {}, slam.front_end_stats()};
  {
    auto t = timer.Time("grid");
    e.grid = slam::BuildGrid(slam.keyframes(), grid_options);
  }
  const auto& be = slam.stats();
  j["counts"] = {{"keyframes", e.front_end.keyframes},
                 {"loop_searches", be.loop_searches},
                 {"loops_found", be.loops_found},
                 {"loops_accepted", be.loops_accepted},
                 {"loops_free_along_axis", be.loops_free_along_axis},
                 {"optimizations", be.optimizations}};
  j["metrics"]["graph_chi2"] = be.final_chi2;
  j["timing"]["loop_search_ms"] = be.loop_search_ms;
  j["timing"]["optimize_ms"] = be.optimize_ms;
  auto t = timer.Time("write");
  internal::WriteMapArtefact(slam, e.grid, out);
  internal::ReportLoops(slam, params.Get<slam::PoseGraphOptions>("pose_graph"), e.grid, e.trajectory, out,
                        j["metrics"]);
  for (const char* f : {"map.yaml", "map.pgm", "map.gridmap", "graph.g2o", "keyframes.rawlog", "loops.png"})
    report.AddOutput(f);
  return e;
}

namespace {

void AddCounts(const slam::MappingStats& fe, const io::DatasetSource& source, const DriveResult& run,
               nlohmann::json& counts) {
  counts["observations"] = run.observations;
  counts["scans"] = fe.scans;
  counts["rejected_matches"] = fe.rejected_matches;
  counts["degenerate_matches"] = fe.degenerate_matches;
  counts["recovered_matches"] = fe.recovered_matches;
  counts["rechecked_steps"] = fe.rechecked_steps;
  counts["odometry"] = fe.odometry;
  counts["imu"] = fe.imu;
  counts["ignored"] = fe.ignored;
  counts["skipped_records"] = source.SkippedRecords().size();
}

// The world model's outputs: tracks.csv, snapshots.jsonl, world.json (the last
// snapshot, with the final static map).
void WritePerception(PerceptionPipeline& perception, const mrpt::maps::COccupancyGridMap2D& grid, Stamp end,
                     const std::string& out, io::RunReport& report) {
  if (!perception.active()) return;
  perception.SetStaticMap(grid, end);
  io::WriteObjectTracks(perception.track_samples(), out + "/tracks.csv");
  std::string lines;
  for (const auto& s : perception.snapshots()) lines += s.dump() + "\n";
  io::WriteTextAtomically(out + "/snapshots.jsonl", lines);
  io::WriteTextAtomically(out + "/world.json", perception.world().snapshot()->ToJson().dump(1) + "\n");
  for (const char* f : {"tracks.csv", "snapshots.jsonl", "world.json"}) report.AddOutput(f);
  for (const auto& f : perception.CloseVideos()) report.AddOutput(f);
  report.json()["perception"] = perception.summary().ToJson();
  report.json()["perception"]["snapshots"] = perception.snapshots().size();
}

void WriteMapPicture(const mrpt::maps::COccupancyGridMap2D& grid, const Trajectory& trajectory,
                     const Trajectory& reference_in_map, const PerceptionPipeline& perception,
                     const std::string& path) {
  std::vector<io::PathOverlay> paths;
  if (!reference_in_map.empty()) paths.push_back({&reference_in_map, {40, 170, 60}, "reference"});
  paths.push_back({&trajectory, {30, 90, 220}, "estimate"});
  for (const auto& [cls, where] : perception.seen())
    paths.push_back({&where, internal::ClassColour(cls), cls + " (" + std::to_string(where.size()) + ")", true});
  io::WriteMapPng(grid, paths, path);
}

}  // namespace

int Replay::Run(const std::string& out, bool quiet) {
  State& s = *state_;
  spdlog::info("{}: {} -> {}{}{}", s.command, s.in.dataset, out,
               s.in.map_dir.empty() ? "" : " (localization on " + s.in.map_dir + ")",
               s.in.continue_dir.empty() ? "" : " (continuing " + s.in.continue_dir + ")");
  TransformTree frames(s.params.Get<FramesOptions>("frames"));
  io::ReplayClock clock(s.params.Get<io::ReplayOptions>("replay"));
  io::StageTimer timer;
  io::RunReport report(s.command);
  auto& j = report.json();
  j["inputs"] = {{"dataset", s.in.dataset},          {"format", s.source->Format()},
                 {"ground_truth", s.reference_path}, {"relations", s.relations ? s.relations->path : ""},
                 {"reference_map", s.reference_map}, {"map", s.in.map_dir},
                 {"continue", s.in.continue_dir},    {"params_files", s.in.param_files},
                 {"overrides", s.in.overrides}};
  int exit_code = 0;
  PerceptionPipeline& perception = *s.perception;
  perception.WriteVideosTo(out);
  std::vector<std::unique_ptr<internal::MessageSink>> sinks;
  if (!s.in.mcap.empty()) sinks.push_back(internal::McapSink(internal::RecordingPath(out, s.in.mcap)));
  std::shared_ptr<net::TopicPublisher> published;
  if (s.in.node) {
    published = std::make_shared<net::TopicPublisher>(s.in.node->participant, net::Qos::kDefault);
    sinks.push_back(internal::DdsSink(published, internal::Origin::kEstimate));
  }
  if (!sinks.empty())
    s.mcap = std::make_unique<internal::RosRecorder>(
        std::move(sinks),
        s.in.node ? s.in.node->map_every_s : s.params.Get<io::ReplayOptions>("replay").mcap_map_every_s,
        s.params.Get<slam::GridOptions>("grid"));
  DriveResult run;
  const Estimate e = s.in.map_dir.empty() ? s.Map(clock, perception, timer, report, frames, run, out, quiet, exit_code)
                                          : s.Localize(clock, perception, timer, report, frames, run, quiet, exit_code);
  try {
    auto t = timer.Time("perception");
    perception.Finish();
  } catch (const InputError& e) {  // a frame still queued at the end that the stack cannot use
    spdlog::error("{}: {}", s.in.dataset, e.what());
    report.SetIncomplete(e.what());
    exit_code = 2;
  }
  for (const auto& skipped : s.source->SkippedRecords()) spdlog::warn("skipped {}", skipped);
  j["input_notes"] = s.source->Notes();
  if (const auto figures = s.source->Figures(); !figures.empty()) j["input_figures"] = figures;
  for (const auto& note : s.source->Notes()) spdlog::info("{}: {}", s.in.dataset, note);

  AddCounts(e.front_end, *s.source, run, j["counts"]);
  const double data_s = run.first ? SecondsBetween(*run.first, *run.last) : 0.0;
  const double slam_ms = timer.TotalMs("slam");
  j["metrics"]["path_length_m"] = PathLength(e.trajectory);
  const auto walls = eval::MeasureWallThickness(e.grid);
  j["metrics"]["wall_thickness_p50_m"] = walls.p50_m;
  j["metrics"]["wall_thickness_p95_m"] = walls.p95_m;
  j["metrics"]["map_size_m"] = {e.grid.getXMax() - e.grid.getXMin(), e.grid.getYMax() - e.grid.getYMin()};
  const Trajectory reference_in_map = internal::AddReferenceMetrics(e.trajectory, s.reference, j["metrics"]);
  if (s.relations) {
    auto t = timer.Time("write");
    internal::AddPublishedRelationMetrics(e.trajectory, *s.relations, e.grid, out, j["metrics"]);
    if (j["metrics"]["published_relations"].contains("worst")) report.AddOutput("relations.png");
  }
  if (!s.reference_map.empty()) {
    auto t = timer.Time("reference_map");
    internal::AddReferenceMapMetrics(e.grid, s.reference_map, out, j["metrics"]);
    report.AddOutput("map_vs_reference.png");
  }
  if (!e.keyframes.empty()) {
    auto t = timer.Time("map_entropy");
    internal::AddMapEntropy(e.keyframes, s.reference, j["metrics"]);
  }
  {
    auto t = timer.Time("write");
    io::WriteTum(e.trajectory, out + "/trajectory.tum");
    WriteMapPicture(e.grid, e.trajectory, reference_in_map, perception, out + "/map.png");
    WritePerception(perception, e.grid, run.last ? *run.last : Stamp{}, out, report);
  }
  for (const char* f : {"map.png", "trajectory.tum", "params.yaml"}) report.AddOutput(f);
  if (s.mcap) {
    auto t = timer.Time("mcap");
    s.mcap->Finish(e.grid, e.trajectory, run.last ? *run.last : Stamp{});
    if (!s.in.mcap.empty()) {
      report.AddOutput(s.in.mcap);
      j["mcap"] = {{"file", s.in.mcap}, {"messages", s.mcap->Counts()}};
    }
    if (published)
      j["published"] = {{"domain", s.in.node->participant->options().domain}, {"messages", published->Counts()}};
  }
  j["timing"]["stages"] = timer.ToJson();
  j["timing"]["wall_s"] = run.wall_s;
  j["timing"]["data_s"] = data_s;
  j["timing"]["real_time_factor"] = run.wall_s > 0 ? data_s / run.wall_s : 0.0;
  j["timing"]["ms_per_scan"] = e.front_end.scans > 0 ? slam_ms / e.front_end.scans : 0.0;
  j["timing"]["peak_rss_mib"] = PeakRssMib();
  report.Write(out);
  spdlog::info("{}: {} scans, {:.1f} m, {:.2f} ms/scan, {:.0f}x real time{}", s.command, e.front_end.scans,
               PathLength(e.trajectory), e.front_end.scans ? slam_ms / e.front_end.scans : 0.0,
               run.wall_s > 0 ? data_s / run.wall_s : 0.0,
               exit_code == 0         ? ""
               : InterruptRequested() ? " (INTERRUPTED)"
                                      : " (INCOMPLETE)");
  return exit_code;
}

}  // namespace specht::pipeline
