// specht/core/pose_graph.h: a 2D pose graph, as in g2o's VERTEX_SE2 / EDGE_SE2.
// Nodes are poses x_i = (x, y, θ) in a fixed frame; an edge (i, j) measures the pose
// of j seen from i, z_ij, with information matrix Ω_ij (inverse covariance, order
// x, y, θ). The SLAM back end optimises it (slam/pose_graph_optimizer.h); io reads
// and writes it as g2o.
#pragma once

#include <mrpt/poses/CPose2D.h>

#include <Eigen/Core>
#include <map>
#include <vector>

namespace specht {

struct PoseGraphEdge {
  int from = 0;
  int to = 0;
  mrpt::poses::CPose2D measurement;                           // z_ij
  Eigen::Matrix3d information = Eigen::Matrix3d::Identity();  // Ω_ij
  bool robust = false;                                        // loop closures: under a robust loss during optimisation
};

struct PoseGraph2D {
  std::map<int, mrpt::poses::CPose2D> nodes;
  std::vector<PoseGraphEdge> edges;
};

// An edge's error with g2o's convention, in the measurement's frame:
//   e_ij = t2v(Z_ij⁻¹ (X_i⁻¹ X_j)) = (R(θ_ij)ᵀ [R_iᵀ(p_j − p_i) − t_ij], wrap(θ_j − θ_i − θ_ij)).
// Both nodes must exist (std::out_of_range otherwise).
Eigen::Vector3d EdgeError(const PoseGraph2D& graph, const PoseGraphEdge& edge);

// χ² = Σ e_ijᵀ Ω_ij e_ij over all edges.
double Chi2(const PoseGraph2D& graph);

}  // namespace specht
