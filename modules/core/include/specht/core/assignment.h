// specht/core/assignment.h: optimal assignment (the Hungarian method) for rectangular
// cost matrices, used by the tracker (detections to tracks) and by CLEAR MOT
// evaluation (hypotheses to ground truth).
//
// Minimises Σ cost(i, a(i)) over one-to-one assignments of rows to columns. Pairs
// whose cost is +inf (or above `max_cost`) are forbidden: they are never returned,
// and a row with no allowed column stays unassigned. The solver is the shortest
// augmenting path form (Kuhn–Munkres with potentials u, v; reduced costs
// c(i,j) − u(i) − v(j) ≥ 0), O(n² m) for n ≤ m.
#pragma once

#include <limits>
#include <vector>

namespace specht {

struct Assignment {
  std::vector<int> column_of_row;  // −1: row unassigned
  double total_cost = 0;           // over the assigned pairs
};

// cost[i][j]; every row must have the same length.
Assignment SolveAssignment(const std::vector<std::vector<double>>& cost,
                           double max_cost = std::numeric_limits<double>::infinity());

}  // namespace specht
