// 2D geometry shared by the simulator's sources: angles, polygons, segments.
#pragma once

#include <cmath>
#include <vector>

#include "specht/sim/scenario.h"

namespace specht::sim::internal {

constexpr double kDeg = M_PI / 180.0;

// An angle in (-π, π].
inline double WrapAngle(double a) { return std::atan2(std::sin(a), std::cos(a)); }

// Even-odd rule: whether p lies inside the closed polygon.
inline bool InsidePolygon(const std::vector<Vec2>& poly, Vec2 p) {
  bool inside = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    if (((poly[i].y > p.y) != (poly[j].y > p.y)) &&
        (p.x < (poly[j].x - poly[i].x) * (p.y - poly[i].y) / (poly[j].y - poly[i].y) + poly[i].x)) {
      inside = !inside;
    }
  }
  return inside;
}

// (a − o) × (b − o)
inline double Cross(Vec2 o, Vec2 a, Vec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

// Whether segments ab and cd cross at a point interior to both (touching does not count).
inline bool SegmentsCross(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const double d1 = Cross(c, d, a), d2 = Cross(c, d, b), d3 = Cross(a, b, c), d4 = Cross(a, b, d);
  return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)) && d1 != 0 && d2 != 0 && d3 != 0 && d4 != 0;
}

}  // namespace specht::sim::internal
