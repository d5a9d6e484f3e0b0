// `specht slam <dataset>`: graph SLAM alone, writing the map artefact (grid, graph,
// trajectory) and a report.
// `specht slam optimize <graph.g2o>`: the pose-graph back end alone. Writes the
// optimised graph (g2o) and reports χ² before and after.
#include <cstdio>

#include "commands.h"
#include "mapping_run.h"
#include "run_setup.h"
#include "specht/core/log.h"
#include "specht/io/atomic_file.h"
#include "specht/io/g2o.h"
#include "specht/io/replay.h"
#include "specht/io/report.h"
#include "specht/slam/pose_graph_optimizer.h"

namespace specht::app {
namespace {

struct OptimizeArgs {
  CommonArgs common;
  std::string graph;
};

int RunOptimize(const OptimizeArgs& a) {
  const params::Params params = LoadParams(a.common);
  const auto& options = params.Get<slam::PoseGraphOptions>("pose_graph");
  const auto on_bad =
      params.Get<io::ReplayOptions>("replay").on_bad_record == "skip" ? io::OnBadRecord::kSkip : io::OnBadRecord::kStop;
  io::G2oReadResult read = io::ReadG2o(a.graph, on_bad);
  for (const auto& s : read.skipped) spdlog::warn("skipped {}", s);
  PrepareOutputDir(a.common, params);
  const slam::OptimizeSummary summary = slam::Optimize(read.graph, options);
  io::WriteG2o(read.graph, a.common.out_dir + "/optimized.g2o");
  io::RunReport report("slam optimize");
  report.json()["inputs"] = {{"graph", a.graph}, {"initial_guess", read.had_vertices ? "vertices" : "odometry chain"}};
  report.json()["counts"] = {{"nodes", read.graph.nodes.size()},
                             {"edges", read.graph.edges.size()},
                             {"skipped_records", read.skipped.size()},
                             {"iterations", summary.iterations}};
  report.json()["metrics"] = {{"initial_chi2", summary.initial_chi2}, {"final_chi2", summary.final_chi2}};
  report.json()["timing"] = {{"solve_s", summary.seconds}};
  report.AddOutput("optimized.g2o");
  report.Write(a.common.out_dir);
  std::printf("%s: %zu nodes, %zu edges: chi2 %.6g -> %.6g in %d iterations, %.3f s\n", a.graph.c_str(),
              read.graph.nodes.size(), read.graph.edges.size(), summary.initial_chi2, summary.final_chi2,
              summary.iterations, summary.seconds);
  return summary.usable ? 0 : 1;
}

}  // namespace

void AddSlamCommand(CLI::App& app, int& exit_code) {
  CLI::App* slam = app.add_subcommand("slam", "graph SLAM on a dataset, or `slam optimize` a pose graph");
  auto run_args = std::make_shared<MappingArgs>();
  AddMappingOptions(*slam, *run_args, "specht-out/slam");
  slam->require_subcommand(0, 1);
  slam->callback([slam, run_args, &exit_code] {
    if (slam->get_subcommands().empty()) exit_code = RunMapping(*run_args, "slam");
  });
  auto args = std::make_shared<OptimizeArgs>();
  CLI::App* optimize = slam->add_subcommand("optimize", "optimise a 2D pose graph (g2o VERTEX_SE2/EDGE_SE2)");
  optimize->add_option("graph", args->graph, "g2o file")->required();
  AddCommonOptions(*optimize, args->common, "specht-out/optimize");
  optimize->callback([args, &exit_code] { exit_code = RunOptimize(*args); });
}

}  // namespace specht::app
