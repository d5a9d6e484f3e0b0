// slam_bench <dataset> [name]: the mapping pipeline of `specht replay` / `specht slam`
// (read, graph SLAM with loop closure, grid) on one dataset, default parameters.
// Prints one JSON object: ms per scan p50/p95/mean (each scan's whole SLAM step,
// loop search and optimisation included), real-time factor (data seconds per wall
// second, whole pipeline), peak memory, and, where the dataset carries a reference
// (CARMEN corrected poses, MRPT <rawlog>.GT.txt), relation error and ATE; where a
// published relations file lies beside it (the Freiburg benchmark's <log>.relations),
// the Kümmerle metric on it.
#include <mrpt/obs/CObservation2DRangeScan.h>

#include <chrono>
#include <iostream>

#include "bench_support.h"
#include "specht/core/statistics.h"
#include "specht/eval/relation_error.h"
#include "specht/eval/trajectory_error.h"
#include "specht/io/dataset.h"
#include "specht/io/reference.h"
#include "specht/io/trajectory_io.h"
#include "specht/slam/graph_slam.h"

using Clock = std::chrono::steady_clock;
using namespace specht;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: slam_bench <dataset> [name]\n";
    return 2;
  }
  const std::string dataset = argv[1];
  const std::string name = argc > 2 ? argv[2] : dataset;
  const auto t0 = Clock::now();
  auto source = io::OpenDataset(dataset);
  slam::GraphSlam slam(slam::SlamOptions{}, slam::ScanMatchingOptions{}, slam::LoopClosureOptions{},
                       slam::PoseGraphOptions{}, nullptr, "base_link");
  std::vector<double> scan_ms;
  std::optional<Stamp> first, last;
  while (auto obs = source->Next()) {
    const bool is_scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs->data) != nullptr;
    const auto s = Clock::now();
    slam.Add(obs->stamp, obs->data);
    if (is_scan) scan_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - s).count());
    if (!first) first = obs->stamp;
    last = obs->stamp;
  }
  const auto f = Clock::now();
  slam.Finish();
  const double finish_ms = std::chrono::duration<double, std::milli>(Clock::now() - f).count();
  const auto grid = slam::BuildGrid(slam.keyframes(), slam::GridOptions{});
  const double wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const double data_s = first ? SecondsBetween(*first, *last) : 0.0;
  double sum = finish_ms;
  for (double v : scan_ms) sum += v;
  nlohmann::json result = {{"name", "slam/" + name},
                           {"format", source->Format()},
                           {"scans", scan_ms.size()},
                           {"keyframes", slam.keyframes().size()},
                           {"loop_closures", slam.stats().loops_accepted},
                           {"ms_per_scan_p50", Percentile(scan_ms, 0.5)},
                           {"ms_per_scan_p95", Percentile(scan_ms, 0.95)},
                           {"ms_per_scan_mean", scan_ms.empty() ? 0.0 : sum / scan_ms.size()},
                           {"data_s", data_s},
                           {"wall_s", wall_s},
                           {"real_time_factor", wall_s > 0 ? data_s / wall_s : 0.0},
                           {"peak_rss_mib", bench::PeakRssMib()},
                           {"map_cells", grid.getSizeX() * grid.getSizeY()},
                           {"machine", bench::MachineNotes()}};
  const std::string reference_path = io::DefaultReferencePath(dataset, source->Format());
  const Trajectory reference = reference_path.empty() ? Trajectory{} : io::ReadReference(reference_path);
  if (!reference.empty()) {
    eval::RelationOptions options;
    options.max_dt_s = 0.05;
    const auto rel = eval::ComputeRelationError(slam.trajectory(), reference, options);
    const auto ate = eval::AbsoluteTrajectoryError2D(slam.trajectory(), reference, 0.05);
    result["relation_error"] = eval::ToJson(rel.all);
    result["ate_rmse_m"] = ate.rmse_m;
  }
  const std::string relations_path = io::DefaultRelationsPath(dataset);
  if (!relations_path.empty()) {
    const auto rel = eval::ComputePublishedRelationError(slam.trajectory(), io::ReadRelations(relations_path));
    result["published_relations"] = {{"relations", rel.relations}, {"absolute", eval::ToJson(rel.absolute)}};
  }
  bench::Emit(result);
  return 0;
}
