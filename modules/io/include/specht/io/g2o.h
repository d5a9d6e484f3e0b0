// specht/io/g2o.h: 2D pose graphs in g2o's text format.
//   VERTEX_SE2 id x y θ
//   EDGE_SE2 i j dx dy dθ I11 I12 I13 I22 I23 I33   (upper triangle of Ω, order x y θ)
// Files with edges only (e.g. M3500) get their initial guess by composing the
// odometry edges (i, i+1) from node 0 at the origin. Other tags (FIX, ...) are ignored.
#pragma once

#include <string>
#include <vector>

#include "specht/core/pose_graph.h"
#include "specht/io/dataset.h"

namespace specht::io {

struct G2oReadResult {
  PoseGraph2D graph;
  bool had_vertices = false;
  std::vector<std::string> skipped;  // "file:line: reason" for records skipped
};

// Throws DatasetError (file and line) on a malformed record, an edge to a missing
// vertex or an information matrix that is not symmetric positive definite, unless
// on_bad says skip.
G2oReadResult ReadG2o(const std::string& path, OnBadRecord on_bad = OnBadRecord::kStop);

void WriteG2o(const PoseGraph2D& graph, const std::string& path);

}  // namespace specht::io
