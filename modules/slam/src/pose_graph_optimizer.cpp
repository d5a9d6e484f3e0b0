#include "specht/slam/pose_graph_optimizer.h"

#include <ceres/ceres.h>
#include <mrpt/math/wrap2pi.h>

#include <Eigen/Cholesky>
#include <chrono>
#include <cmath>

namespace specht::slam {
namespace {

double WrapAngle(double a) { return mrpt::math::wrapToPi(a); }

class AngleManifold final : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 1; }
  int TangentSize() const override { return 1; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    *x_plus_delta = WrapAngle(*x + *delta);
    return true;
  }
  bool PlusJacobian(const double*, double* jacobian) const override {
    *jacobian = 1.0;
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    *y_minus_x = WrapAngle(*y - *x);
    return true;
  }
  bool MinusJacobian(const double*, double* jacobian) const override {
    *jacobian = 1.0;
    return true;
  }
};

// Residual blocks: p_i (2), θ_i (1), p_j (2), θ_j (1).
class RelativePoseError final : public ceres::SizedCostFunction<3, 2, 1, 2, 1> {
 public:
  RelativePoseError(const mrpt::poses::CPose2D& z, const Eigen::Matrix3d& sqrt_information)
      : tx_(z.x()), ty_(z.y()), tth_(z.phi()), s_(sqrt_information) {}

  bool Evaluate(double const* const* p, double* residuals, double** jacobians) const override {
    const double xi = p[0][0], yi = p[0][1], thi = p[1][0], xj = p[2][0], yj = p[2][1], thj = p[3][0];
    const double c = std::cos(thi), s = std::sin(thi), dx = xj - xi, dy = yj - yi;
    const Eigen::Vector3d e(c * dx + s * dy - tx_, -s * dx + c * dy - ty_, WrapAngle(thj - thi - tth_));
    Eigen::Map<Eigen::Vector3d> r(residuals);
    r = s_ * e;
    if (jacobians == nullptr) return true;
    // de/dp_i, de/dθ_i, de/dp_j, de/dθ_j, each mapped through S.
    if (jacobians[0] != nullptr) {
      Eigen::Matrix<double, 3, 2> j;
      j << -c, -s, s, -c, 0, 0;
      Eigen::Map<Eigen::Matrix<double, 3, 2, Eigen::RowMajor>> out(jacobians[0]);
      out = s_ * j;
    }
    if (jacobians[1] != nullptr) {
      const Eigen::Vector3d j(-s * dx + c * dy, -c * dx - s * dy, -1.0);
      Eigen::Map<Eigen::Vector3d> out(jacobians[1]);
      out = s_ * j;
    }
    if (jacobians[2] != nullptr) {
      Eigen::Matrix<double, 3, 2> j;
      j << c, s, -s, c, 0, 0;
      Eigen::Map<Eigen::Matrix<double, 3, 2, Eigen::RowMajor>> out(jacobians[2]);
      out = s_ * j;
    }
    if (jacobians[3] != nullptr) {
      Eigen::Map<Eigen::Vector3d> out(jacobians[3]);
      out = s_ * Eigen::Vector3d(0, 0, 1);
    }
    return true;
  }

 private:
  double tx_, ty_, tth_;
  Eigen::Matrix3d s_;
};

// S with SᵀS = Ω (upper triangular), or throws when Ω is not SPD.
Eigen::Matrix3d SqrtInformation(const PoseGraphEdge& e) {
  const Eigen::Matrix3d& omega = e.information;
  if (!omega.isApprox(omega.transpose(), 1e-9)) {
    throw InputError("pose graph: edge " + std::to_string(e.from) + " -> " + std::to_string(e.to) +
                     ": information matrix is not symmetric");
  }
  Eigen::LLT<Eigen::Matrix3d> llt(omega);
  if (llt.info() != Eigen::Success) {
    throw InputError("pose graph: edge " + std::to_string(e.from) + " -> " + std::to_string(e.to) +
                     ": information matrix is not positive definite");
  }
  return llt.matrixU();
}

// g2o expresses an edge's error in the frame of its measurement,
//   e = t2v(Z_ij⁻¹ (X_i⁻¹ X_j)) = (R(θ_ij)ᵀ [R_iᵀ(p_j − p_i) − t_ij], wrap(θ_j − θ_i − θ_ij)),
// and its information matrix with it: fold R(θ_ij)ᵀ into the square root.
Eigen::Matrix3d MeasurementFrame(const PoseGraphEdge& e) {
  const double c = std::cos(e.measurement.phi()), s = std::sin(e.measurement.phi());
  Eigen::Matrix3d m;
  m << c, s, 0, -s, c, 0, 0, 0, 1;
  return m;
}

// The robust loss on loop edges (none: nullptr, the plain square).
std::unique_ptr<ceres::LossFunction> LoopLoss(const PoseGraphOptions& options) {
  if (options.loop_loss == "cauchy") return std::make_unique<ceres::CauchyLoss>(options.loop_loss_scale);
  if (options.loop_loss == "huber") return std::make_unique<ceres::HuberLoss>(options.loop_loss_scale);
  return nullptr;
}

}  // namespace

OptimizeSummary Optimize(PoseGraph2D& graph, const PoseGraphOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  OptimizeSummary out;
  if (graph.nodes.empty()) return out;
  for (const auto& e : graph.edges) {
    if (graph.nodes.count(e.from) == 0 || graph.nodes.count(e.to) == 0) {
      throw InputError("pose graph: edge " + std::to_string(e.from) + " -> " + std::to_string(e.to) +
                       " names a missing node");
    }
  }
  out.initial_chi2 = Chi2(graph);

  // Parameter storage: [x, y] and [θ] per node, in node order.
  std::map<int, std::array<double, 3>> state;
  for (const auto& [id, pose] : graph.nodes) state[id] = {pose.x(), pose.y(), pose.phi()};

  ceres::Problem::Options problem_options;
  problem_options.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  AngleManifold angle_manifold;
  ceres::LossFunctionWrapper shared_loss(LoopLoss(options).release(), ceres::TAKE_OWNERSHIP);

  for (const auto& e : graph.edges) {
    auto a = state.find(e.from), b = state.find(e.to);
    const bool robust = e.robust && options.loop_loss != "none";
    problem.AddResidualBlock(new RelativePoseError(e.measurement, SqrtInformation(e) * MeasurementFrame(e)),
                             robust ? &shared_loss : nullptr, a->second.data(), a->second.data() + 2, b->second.data(),
                             b->second.data() + 2);
  }
  for (auto& [id, s] : state) {
    if (problem.HasParameterBlock(s.data() + 2)) problem.SetManifold(s.data() + 2, &angle_manifold);
  }
  auto& first = state.begin()->second;
  if (problem.HasParameterBlock(first.data())) {
    problem.SetParameterBlockConstant(first.data());
    problem.SetParameterBlockConstant(first.data() + 2);
  }

  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.max_num_iterations = options.max_iterations;
  solver.function_tolerance = options.function_tolerance;
  solver.num_threads = options.threads;
  solver.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);

  for (auto& [id, s] : state) graph.nodes[id] = mrpt::poses::CPose2D(s[0], s[1], s[2]);
  out.final_chi2 = Chi2(graph);
  out.iterations = static_cast<int>(summary.iterations.size());
  out.usable = summary.IsSolutionUsable();
  out.report = summary.BriefReport();
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

std::vector<LoopResidual> LoopResiduals(const PoseGraph2D& graph, const PoseGraphOptions& options) {
  const std::unique_ptr<ceres::LossFunction> loss = LoopLoss(options);
  std::vector<LoopResidual> out;
  for (const auto& e : graph.edges) {
    if (!e.robust) continue;
    const Eigen::Vector3d r = EdgeError(graph, e);
    LoopResidual l;
    l.from = e.from, l.to = e.to;
    l.error_m = r.head<2>().norm();
    l.error_deg = std::abs(r.z()) * 180.0 / M_PI;
    l.chi2 = r.dot(e.information * r);
    if (loss) {
      double rho[3];
      loss->Evaluate(l.chi2, rho);
      l.weight = rho[1];
    }
    out.push_back(l);
  }
  return out;
}

}  // namespace specht::slam
