// point_index_bench: the scan matcher's nearest-neighbour search, specht's k-d tree
// (slam::IndexedPoints) beside MRPT's own (nanoflann inside CPointsMap), on clouds
// shaped like a SLAM submap (walls seen by many overlapping scans, a little clutter).
// Per cloud size, one JSON object: build ms, µs per nearest query within the ICP
// gate, µs per 5-nearest query within the point-to-line gate (median of 9 runs).
#include <mrpt/maps/CSimplePointsMap.h>

#include <algorithm>
#include <chrono>
#include <random>
#include <vector>

#include "bench_support.h"
#include "specht/slam/indexed_points.h"

using Clock = std::chrono::steady_clock;
using mrpt::maps::CSimplePointsMap;

namespace {

// 60 scans' worth of a 20 × 12 m room with a partition, 1 cm range noise, 5 % clutter.
CSimplePointsMap SubmapLike(size_t n, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::normal_distribution<float> noise(0.0f, 0.01f);
  CSimplePointsMap points;
  for (size_t i = 0; i < n; ++i) {
    const float t = u(rng);
    switch (i % 20) {
      case 0:
        points.insertPoint(20 * u(rng), 12 * u(rng), 0);
        break;  // clutter
      case 1:
      case 2:
      case 3:
      case 4:
        points.insertPoint(20 * t, noise(rng), 0);
        break;
      case 5:
      case 6:
      case 7:
      case 8:
        points.insertPoint(20 * t, 12 + noise(rng), 0);
        break;
      case 9:
      case 10:
      case 11:
        points.insertPoint(noise(rng), 12 * t, 0);
        break;
      case 12:
      case 13:
      case 14:
        points.insertPoint(20 + noise(rng), 12 * t, 0);
        break;
      default:
        points.insertPoint(8 + noise(rng), 8 * t, 0);
        break;  // the partition
    }
  }
  return points;
}

template <class F>
double MedianMs(F&& f) {
  std::vector<double> ms;
  for (int run = 0; run < 9; ++run) {
    const auto t0 = Clock::now();
    f();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
  }
  std::nth_element(ms.begin(), ms.begin() + 4, ms.end());
  return ms[4];
}

}  // namespace

int main() {
  std::mt19937 rng(1);
  for (const size_t n : {5000u, 20000u, 60000u}) {
    const CSimplePointsMap cloud = SubmapLike(n, rng);
    // Queries where a scan's points fall: near the walls, a few centimetres off.
    std::vector<float> qx, qy;
    const CSimplePointsMap queries = SubmapLike(2000, rng);
    qx.assign(queries.getPointsBufferRef_x().begin(), queries.getPointsBufferRef_x().end());
    qy.assign(queries.getPointsBufferRef_y().begin(), queries.getPointsBufferRef_y().end());
    float sink = 0;

    const double ours_build = MedianMs([&] { sink += specht::slam::IndexedPoints(cloud).size(); });
    const double mrpt_build = MedianMs([&] {
      CSimplePointsMap copy(cloud);  // a fresh tree: MRPT builds it on the first query
      float d2;
      copy.kdTreeClosestPoint2D(0.f, 0.f, d2);
      sink += d2;
    });
    const double copy_only = MedianMs([&] { sink += CSimplePointsMap(cloud).size(); });

    const specht::slam::IndexedPoints ours(cloud);
    std::vector<specht::slam::IndexedPoints::Neighbour> near;
    const double ours_nearest = MedianMs([&] {
      for (size_t i = 0; i < qx.size(); ++i)
        if (const auto m = ours.Nearest(qx[i], qy[i], 0.36f)) sink += m->distance2;
    });
    const double ours_k5 = MedianMs([&] {
      for (size_t i = 0; i < qx.size(); ++i) ours.Nearest(qx[i], qy[i], 5, 0.04f, near), sink += near.size();
    });
    std::vector<size_t> idx;
    std::vector<float> d2s;
    const double mrpt_nearest = MedianMs([&] {
      for (size_t i = 0; i < qx.size(); ++i) {
        float d2;
        cloud.kdTreeClosestPoint2D(qx[i], qy[i], d2);
        sink += d2;
      }
    });
    const double mrpt_k5 = MedianMs([&] {
      for (size_t i = 0; i < qx.size(); ++i) cloud.kdTreeNClosestPoint2DIdx(qx[i], qy[i], 5, idx, d2s), sink += d2s[0];
    });
    const double per_query_us = 1000.0 / static_cast<double>(qx.size());
    specht::bench::Emit(
        {{"name", "point_index/" + std::to_string(n)},
         {"points", n},
         {"build_ms", {{"specht", ours_build}, {"mrpt_nanoflann", mrpt_build - copy_only}}},
         {"nearest_us", {{"specht", ours_nearest * per_query_us}, {"mrpt_nanoflann", mrpt_nearest * per_query_us}}},
         {"k5_us", {{"specht", ours_k5 * per_query_us}, {"mrpt_nanoflann", mrpt_k5 * per_query_us}}},
         {"checksum", sink},
         {"peak_rss_mib", specht::bench::PeakRssMib()},
         {"machine", specht::bench::MachineNotes()}});
  }
  return 0;
}
