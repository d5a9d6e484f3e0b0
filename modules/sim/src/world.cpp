#include "specht/sim/world.h"

#include <cmath>
#include <limits>

#include "internal/geometry.h"

namespace specht::sim {
namespace {

double Cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

using internal::InsidePolygon;

}  // namespace

std::vector<Segment> BoxOutline(const Pose2& pose, double length_m, double width_m) {
  const double c = std::cos(pose.yaw_rad), s = std::sin(pose.yaw_rad), hl = length_m / 2, hw = width_m / 2;
  Vec2 corners[4];
  const double lx[4] = {hl, -hl, -hl, hl}, ly[4] = {hw, hw, -hw, -hw};
  for (int i = 0; i < 4; ++i) corners[i] = {pose.x + c * lx[i] - s * ly[i], pose.y + s * lx[i] + c * ly[i]};
  return {{corners[0], corners[1]}, {corners[1], corners[2]}, {corners[2], corners[3]}, {corners[3], corners[0]}};
}

World::World(const Scenario& scenario) : scenario_(scenario) {
  for (const auto& o : scenario.objects) {
    const size_t n = o.polygon.size(), edges = o.closed ? n : n - 1;
    for (size_t i = 0; i < edges; ++i) segments_.push_back({o.polygon[i], o.polygon[(i + 1) % n]});
  }
}

double World::RayCast(Vec2 p, double angle, double max_range_m, const std::vector<Segment>& moving,
                      bool* hit_moving) const {
  const Vec2 d{std::cos(angle), std::sin(angle)};
  double best = std::numeric_limits<double>::infinity();
  bool best_moving = false;
  auto test = [&](const Segment& seg, bool is_moving) {
    const Vec2 e{seg.b.x - seg.a.x, seg.b.y - seg.a.y}, ap{seg.a.x - p.x, seg.a.y - p.y};
    const double den = Cross(d, e);
    if (std::abs(den) < 1e-12) return;
    const double t = Cross(ap, e) / den, u = Cross(ap, d) / den;
    if (t >= 0 && u >= 0 && u <= 1 && t < best) best = t, best_moving = is_moving;
  };
  for (const auto& s : segments_) test(s, false);
  for (const auto& s : moving) test(s, true);
  if (hit_moving != nullptr) *hit_moving = best_moving;
  return best <= max_range_m ? best : std::numeric_limits<double>::infinity();
}

bool World::Blocked(Vec2 p) const {
  const auto& b = scenario_.bounds;
  if (p.x < b[0] || p.x > b[2] || p.y < b[1] || p.y > b[3]) return true;
  for (const auto& o : scenario_.objects) {
    if (o.closed && InsidePolygon(o.polygon, p)) return true;
  }
  return false;
}

mrpt::maps::COccupancyGridMap2D World::TrueGrid(double res) const {
  const auto& b = scenario_.bounds;
  mrpt::maps::COccupancyGridMap2D grid(static_cast<float>(b[0] - 1), static_cast<float>(b[2] + 1),
                                       static_cast<float>(b[1] - 1), static_cast<float>(b[3] + 1),
                                       static_cast<float>(res));
  for (unsigned y = 0; y < grid.getSizeY(); ++y) {
    for (unsigned x = 0; x < grid.getSizeX(); ++x) {
      const Vec2 c{grid.idx2x(x), grid.idx2y(y)};
      const bool inside_bounds = c.x >= b[0] && c.x <= b[2] && c.y >= b[1] && c.y <= b[3];
      bool filled = false;
      for (const auto& o : scenario_.objects) filled = filled || (o.closed && InsidePolygon(o.polygon, c));
      grid.setCell(x, y, filled ? 0.0f : inside_bounds ? 1.0f : 0.5f);
    }
  }
  // Outlines, sampled at a quarter cell.
  for (const auto& s : segments_) {
    const double len = std::hypot(s.b.x - s.a.x, s.b.y - s.a.y);
    const int steps = std::max(1, static_cast<int>(std::ceil(len / (res / 4))));
    for (int k = 0; k <= steps; ++k) {
      const double u = static_cast<double>(k) / steps;
      const int cx = grid.x2idx(s.a.x + u * (s.b.x - s.a.x)), cy = grid.y2idx(s.a.y + u * (s.b.y - s.a.y));
      if (cx >= 0 && cy >= 0 && cx < static_cast<int>(grid.getSizeX()) && cy < static_cast<int>(grid.getSizeY())) {
        grid.setCell(cx, cy, 0.0f);
      }
    }
  }
  return grid;
}

}  // namespace specht::sim
