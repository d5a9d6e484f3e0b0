#include "specht/core/assignment.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace specht {
namespace {

// Rows ≤ columns, finite costs. Returns column_of_row (1-based internals as in the
// classic formulation: p[j] is the row matched to column j, row 0 is the virtual one).
std::vector<int> Hungarian(const std::vector<std::vector<double>>& a, int n, int m) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0), v(m + 1, 0);
  std::vector<int> p(m + 1, 0), way(m + 1, 0);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(m + 1, inf);
    std::vector<char> used(m + 1, 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double cur = a[i0 - 1][j - 1] - u[i0] - v[j];
        if (cur < minv[j]) minv[j] = cur, way[j] = j0;
        if (minv[j] < delta) delta = minv[j], j1 = j;
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j])
          u[p[j]] += delta, v[j] -= delta;
        else
          minv[j] -= delta;
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0);
  }
  std::vector<int> column_of_row(n, -1);
  for (int j = 1; j <= m; ++j)
    if (p[j] > 0) column_of_row[p[j] - 1] = j - 1;
  return column_of_row;
}

}  // namespace

Assignment SolveAssignment(const std::vector<std::vector<double>>& cost, double max_cost) {
  Assignment out;
  const int rows = static_cast<int>(cost.size());
  out.column_of_row.assign(rows, -1);
  if (rows == 0) return out;
  const int cols = static_cast<int>(cost[0].size());
  for (const auto& r : cost)
    if (static_cast<int>(r.size()) != cols) throw std::invalid_argument("SolveAssignment: ragged cost matrix");
  if (cols == 0) return out;

  // Forbidden pairs get a cost larger than any allowed assignment can sum to, so
  // the optimum uses one only when a row has nothing else; those are dropped after.
  double largest = 0;
  for (const auto& r : cost)
    for (double c : r)
      if (std::isfinite(c) && c <= max_cost) largest = std::max(largest, std::abs(c));
  const double forbidden = (largest + 1) * (std::max(rows, cols) + 1);
  const bool transpose = rows > cols;
  const int n = transpose ? cols : rows, m = transpose ? rows : cols;
  std::vector<std::vector<double>> a(n, std::vector<double>(m));
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const double c = cost[i][j];
      const double finite = std::isfinite(c) && c <= max_cost ? c : forbidden;
      (transpose ? a[j][i] : a[i][j]) = finite;
    }
  const std::vector<int> match = Hungarian(a, n, m);
  for (int k = 0; k < n; ++k) {
    if (match[k] < 0) continue;
    const int row = transpose ? match[k] : k, col = transpose ? k : match[k];
    const double c = cost[row][col];
    if (!std::isfinite(c) || c > max_cost) continue;
    out.column_of_row[row] = col;
    out.total_cost += c;
  }
  return out;
}

}  // namespace specht
