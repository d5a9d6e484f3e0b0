// `specht eval slam --estimate traj.tum --reference REF`: relation error (Kümmerle et
// al. 2009) and ATE of an estimated trajectory against a reference, with a plot.
// REF is a CARMEN log (its corrected laser poses), a TUM file or a "t x y theta" file.
#include <cstdio>
#include <iostream>

#include "commands.h"
#include "specht/io/reference.h"
#include "run_setup.h"
#include "specht/eval/relation_error.h"
#include "specht/eval/trajectory_error.h"
#include "specht/io/atomic_file.h"
#include "specht/io/map_io.h"
#include "specht/io/report.h"
#include "specht/io/trajectory_io.h"

namespace specht::app {
namespace {

struct EvalSlamArgs {
  std::string estimate;
  std::string reference;
  std::string out_dir = "specht-out/eval-slam";
  eval::RelationOptions relations;
};

int RunEvalSlam(const EvalSlamArgs& a) {
  const Trajectory estimate = io::ReadTum(a.estimate);
  const Trajectory reference = io::ReadReference(a.reference);
  const eval::RelationError rel = eval::ComputeRelationError(estimate, reference, a.relations);
  const eval::AteResult ate = eval::AbsoluteTrajectoryError2D(estimate, reference, a.relations.max_dt_s);
  io::MakeOutputDir(a.out_dir);

  io::RunReport report("eval slam");
  auto& j = report.json();
  j["inputs"] = {{"estimate", a.estimate}, {"reference", a.reference}};
  j["metrics"]["relation"] = eval::ToJson(rel);
  j["metrics"]["ate"] = eval::ToJson(ate);
  const Trajectory aligned = eval::Transform(estimate, ate.alignment);
  io::WriteTrajectoryPng({{&reference, {40, 170, 60}, "reference"}, {&aligned, {30, 90, 220}, "estimate (aligned)"}},
                         a.out_dir + "/trajectories.png");
  report.AddOutput("trajectories.png");
  report.Write(a.out_dir);

  std::printf("relations       count   mean±std m          max m    mean±std deg      max deg\n");
  for (const auto& [name, s] : {std::pair{"consecutive", rel.consecutive}, {"loop", rel.loop}, {"all", rel.all}}) {
    std::printf("%-12s %8zu   %.4f ± %.4f   %8.4f   %6.3f ± %6.3f   %7.3f\n", name, s.count, s.mean_m, s.std_m,
                s.max_m, s.mean_deg, s.std_deg, s.max_deg);
  }
  std::printf("ATE (SE(2)-aligned, %zu poses): RMSE %.4f m, max %.4f m, %.3f deg RMSE\n", ate.pairs, ate.rmse_m,
              ate.max_m, ate.rmse_deg);
  return 0;
}

}  // namespace

void AddEvalCommand(CLI::App& app, int& exit_code) {
  CLI::App* eval = app.add_subcommand("eval", "evaluate outputs against ground truth");
  eval->require_subcommand(1);
  auto args = std::make_shared<EvalSlamArgs>();
  CLI::App* slam = eval->add_subcommand("slam", "relation error (Kuemmerle et al. 2009) and ATE of a trajectory");
  slam->add_option("--estimate", args->estimate, "estimated trajectory (TUM)")->required();
  slam->add_option("--reference", args->reference, "CARMEN log, TUM or 't x y theta' reference")->required();
  slam->add_option("-o,--out", args->out_dir, "output directory")->capture_default_str();
  slam->add_option("--loop-distance", args->relations.loop_max_distance_m,
                   "loop relations: reference poses closer than this (m)")->capture_default_str();
  slam->add_option("--loop-separation", args->relations.loop_min_separation,
                   "loop relations: more than this many scans apart")->capture_default_str();
  slam->add_option("--max-dt", args->relations.max_dt_s, "pair poses whose stamps differ by at most this (s)")
      ->capture_default_str();
  slam->callback([args, &exit_code] { exit_code = RunEvalSlam(*args); });
}

}  // namespace specht::app
