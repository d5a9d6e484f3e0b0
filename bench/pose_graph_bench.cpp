// pose_graph_bench <graph.g2o>...: specht's back end beside a plain Ceres solve of the
// same graphs (autodiff, x/y/θ blocks, angle manifold, SPARSE_NORMAL_CHOLESKY,
// default tolerances — the setup of Ceres' own pose_graph_2d example, with g2o's
// error convention so both minimise the same χ²). Both start from the same initial
// guess. One JSON object per graph and solver: χ², iterations, seconds.
#include <ceres/ceres.h>

#include <chrono>
#include <cmath>
#include <iostream>

#include "bench_support.h"
#include "specht/io/g2o.h"
#include "specht/slam/pose_graph_optimizer.h"

namespace {

template <typename T>
T Wrap(T a) {
  const T two_pi(2.0 * M_PI);
  return a - two_pi * ceres::floor((a + T(M_PI)) / two_pi);
}

struct AutodiffError {
  AutodiffError(const specht::PoseGraphEdge& e, const Eigen::Matrix3d& sqrt_info)
      : x(e.measurement.x()), y(e.measurement.y()), th(e.measurement.phi()), s(sqrt_info) {}
  template <typename T>
  bool operator()(const T* xa, const T* ya, const T* tha, const T* xb, const T* yb, const T* thb, T* r) const {
    const T c = ceres::cos(*tha), sn = ceres::sin(*tha), dx = *xb - *xa, dy = *yb - *ya;
    const T ex = c * dx + sn * dy - T(x), ey = -sn * dx + c * dy - T(y);
    const T cz(std::cos(th)), sz(std::sin(th));
    const Eigen::Matrix<T, 3, 1> e(cz * ex + sz * ey, -sz * ex + cz * ey, Wrap(*thb - *tha - T(th)));
    Eigen::Map<Eigen::Matrix<T, 3, 1>> out(r);
    out = s.cast<T>() * e;
    return true;
  }
  double x, y, th;
  Eigen::Matrix3d s;
};

struct AngleManifoldFunctor {
  template <typename T>
  bool Plus(const T* x, const T* d, T* out) const {
    *out = Wrap(*x + *d);
    return true;
  }
  template <typename T>
  bool Minus(const T* y, const T* x, T* out) const {
    *out = Wrap(*y - *x);
    return true;
  }
};

double PlainCeres(specht::PoseGraph2D graph, int* iterations) {
  std::map<int, std::array<double, 3>> s;
  for (const auto& [id, p] : graph.nodes) s[id] = {p.x(), p.y(), p.phi()};
  ceres::Problem problem;
  ceres::Manifold* angle = new ceres::AutoDiffManifold<AngleManifoldFunctor, 1, 1>;
  for (const auto& e : graph.edges) {
    const Eigen::Matrix3d sqrt_info = Eigen::LLT<Eigen::Matrix3d>(e.information).matrixU();
    auto& a = s[e.from];
    auto& b = s[e.to];
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<AutodiffError, 3, 1, 1, 1, 1, 1, 1>(new AutodiffError(e, sqrt_info)), nullptr,
        &a[0], &a[1], &a[2], &b[0], &b[1], &b[2]);
  }
  for (auto& [id, v] : s) problem.SetManifold(&v[2], angle);
  auto& first = s.begin()->second;
  for (double* p : {&first[0], &first[1], &first[2]}) problem.SetParameterBlockConstant(p);
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  options.max_num_iterations = 100;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  *iterations = static_cast<int>(summary.iterations.size());
  return 2.0 * summary.final_cost;
}

}  // namespace

int main(int argc, char** argv) {
  using Clock = std::chrono::steady_clock;
  for (int i = 1; i < argc; ++i) {
    const std::string path = argv[i];
    const std::string name = path.substr(path.find_last_of('/') + 1);
    const specht::io::G2oReadResult read = specht::io::ReadG2o(path);
    // Best of 3 runs for each solver.
    double ours_s = 1e9, plain_s = 1e9, ours_chi2 = 0, plain_chi2 = 0;
    int ours_it = 0, plain_it = 0;
    for (int run = 0; run < 3; ++run) {
      specht::PoseGraph2D g = read.graph;
      const auto t0 = Clock::now();
      const auto summary = specht::slam::Optimize(g, specht::slam::PoseGraphOptions{});
      ours_s = std::min(ours_s, std::chrono::duration<double>(Clock::now() - t0).count());
      ours_chi2 = summary.final_chi2, ours_it = summary.iterations;
      const auto t1 = Clock::now();
      plain_chi2 = PlainCeres(read.graph, &plain_it);
      plain_s = std::min(plain_s, std::chrono::duration<double>(Clock::now() - t1).count());
    }
    specht::bench::Emit(
        {{"name", "pose_graph/" + name},
         {"nodes", read.graph.nodes.size()},
         {"edges", read.graph.edges.size()},
         {"specht", {{"chi2", ours_chi2}, {"iterations", ours_it}, {"seconds", ours_s}}},
         {"plain_ceres_autodiff", {{"chi2", plain_chi2}, {"iterations", plain_it}, {"seconds", plain_s}}},
         {"speedup", plain_s / ours_s},
         {"peak_rss_mib", specht::bench::PeakRssMib()},
         {"machine", specht::bench::MachineNotes()}});
  }
  return 0;
}
