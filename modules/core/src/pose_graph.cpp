#include "specht/core/pose_graph.h"

#include <mrpt/math/wrap2pi.h>

#include <cmath>

namespace specht {

Eigen::Vector3d EdgeError(const PoseGraph2D& graph, const PoseGraphEdge& e) {
  const auto& a = graph.nodes.at(e.from);
  const auto& b = graph.nodes.at(e.to);
  const double c = std::cos(a.phi()), s = std::sin(a.phi());
  const double dx = b.x() - a.x(), dy = b.y() - a.y();
  // Position error in the measurement's frame (g2o's convention).
  const double ex = c * dx + s * dy - e.measurement.x(), ey = -s * dx + c * dy - e.measurement.y();
  const double cz = std::cos(e.measurement.phi()), sz = std::sin(e.measurement.phi());
  return {cz * ex + sz * ey, -sz * ex + cz * ey, mrpt::math::wrapToPi(b.phi() - a.phi() - e.measurement.phi())};
}

double Chi2(const PoseGraph2D& graph) {
  double chi2 = 0;
  for (const auto& e : graph.edges) {
    const Eigen::Vector3d r = EdgeError(graph, e);
    chi2 += r.dot(e.information * r);
  }
  return chi2;
}

}  // namespace specht
