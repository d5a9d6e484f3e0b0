// specht/slam/pose_graph_optimizer.h: the 2D pose-graph back end on Ceres.
//
// For each edge (i, j) with measurement z_ij = (t_ij, θ_ij) and information Ω_ij,
// the error is g2o's, expressed in the frame of the measurement (where Ω_ij lives):
//   e_ij = [ R(θ_ij)ᵀ (R(θ_i)ᵀ (p_j − p_i) − t_ij) ;  wrap(θ_j − θ_i − θ_ij) ]
//   r_ij = S_ij M_ij ẽ_ij,  S_ijᵀ S_ij = Ω_ij (Cholesky), M_ij = diag(R(θ_ij)ᵀ, 1),
//   cost ½ Σ ρ(|r_ij|²)
// where ẽ_ij is the error before the rotation into the measurement frame (the
// rotation is constant, so it folds into the square-root information).
// with ρ the identity for odometry edges and a robust loss (Cauchy or Huber) for
// loop closures. Positions (x, y) and headings θ are separate parameter blocks; θ
// lives on an angle manifold (Plus = wrap(θ + δ)). Jacobians of ẽ are analytic:
//   ∂ẽ_p/∂p_i = −R_iᵀ,  ∂ẽ_p/∂θ_i = dR_iᵀ/dθ (p_j − p_i),  ∂ẽ_p/∂p_j = R_iᵀ,
//   ∂ẽ_θ/∂θ_i = −1,     ∂ẽ_θ/∂θ_j = 1.
// The first node (lowest id) is held fixed. Solved with Levenberg-Marquardt and a
// sparse normal Cholesky factorisation.
#pragma once

#include <string>
#include <vector>

#include "specht/core/error.h"
#include "specht/core/params.h"
#include "specht/core/pose_graph.h"

namespace specht::slam {

// Section "pose_graph".
struct PoseGraphOptions {
  int max_iterations = 100;
  std::string loop_loss = "cauchy";
  double loop_loss_scale = 1.0;  // in whitened units (√χ²)
  double function_tolerance = 1e-6;
  // One thread: the sparse Cholesky factorisation is single-threaded, and only the
  // residuals (cheap, analytic) would run in parallel; a second thread cost more
  // than it saved (bench/pose_graph_bench: manhattan 0.22 s with two, 0.18 s with
  // one, against 0.20 s for a plain autodiff solve; χ² the same to 1e-12).
  int threads = 1;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("max_iterations", max_iterations, "Levenberg-Marquardt iterations per optimisation", Range::Of(1, 1000));
    v.Choice("loop_loss", loop_loss, {"cauchy", "huber", "none"}, "robust loss on loop-closure edges");
    v.Param("loop_loss_scale", loop_loss_scale, "scale of the robust loss, in standard deviations",
            Range::Of(0.1, 100.0).Log());
    v.Param("function_tolerance", function_tolerance, "stop when the cost changes less than this (relative)",
            Range::Of(1e-12, 1e-2).Log());
    v.Param("threads", threads, "solver threads (residual evaluation only; 1 is fastest on these graphs)",
            Range::Of(1, 64).Fixed());
  }
};

struct OptimizeSummary {
  double initial_chi2 = 0;
  double final_chi2 = 0;
  int iterations = 0;
  double seconds = 0;
  bool usable = false;  // Ceres reports a usable solution
  std::string report;   // Ceres' one-line summary
};

// Optimises the node poses in place. Throws InputError when an edge names a missing
// node or an information matrix is not symmetric positive definite.
OptimizeSummary Optimize(PoseGraph2D& graph, const PoseGraphOptions& options);

// How a loop-closure (robust) edge sits in a graph, usually the optimised one: its
// error e_ij (pose_graph.h's EdgeError) as a distance and an angle, s = e_ijᵀ Ω_ij e_ij,
// and the weight the robust loss leaves it in the normal equations, ρ'(s):
//   Cauchy (scale c): 1 / (1 + s / c²)    Huber: min(1, c / √s)    none: 1.
// A loop that disagrees with the rest of the graph ends with a weight near 0: the
// robust loss has set it aside (an alias, or a match off by more than its noise).
struct LoopResidual {
  int from = 0, to = 0;
  double error_m = 0, error_deg = 0;
  double chi2 = 0;
  double weight = 1;
};

// One entry per robust edge of `graph`, in edge order.
std::vector<LoopResidual> LoopResiduals(const PoseGraph2D& graph, const PoseGraphOptions& options);

}  // namespace specht::slam
