// specht/slam/icp.h: 2D point-to-point ICP (MRPT CICP) with specht's options, and
// the conversion of a laser scan to points in the car's frame.
//
// ICP minimises Σ |R(θ) s_i + t − m_j(i)|² over (t, θ), pairing each scan point s_i
// with its nearest map point m_j(i) closer than a threshold that starts at
// max_pair_distance_m and shrinks by threshold_decay each time the estimate settles,
// down to min_pair_distance_m.
#pragma once

#include <memory>

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose2D.h>

#include "specht/core/params.h"

namespace specht::slam {

// MRPT CICP settings (section "scan_matching.icp").
struct IcpOptions {
  int max_iterations = 80;
  double max_pair_distance_m = 0.6;      // initial matching distance (CICP thresholdDist)
  double max_pair_angle_deg = 5.0;       // angular part of the matching distance (thresholdAng)
  double threshold_decay = 0.6;          // ALFA: thresholds shrink by this on convergence
  double min_pair_distance_m = 0.05;     // smallest threshold before stopping
  int point_decimation = 3;              // use every n-th point of the scan as a query

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("max_iterations", max_iterations, "ICP iterations per alignment", Range::Of(5, 500));
    v.Param("max_pair_distance_m", max_pair_distance_m, "initial point pairing distance",
            Range::Of(0.05, 3.0).Log());
    v.Param("max_pair_angle_deg", max_pair_angle_deg, "angular term of the pairing distance",
            Range::Of(0.0, 20.0));
    v.Param("threshold_decay", threshold_decay, "pairing distance factor on convergence", Range::Of(0.1, 0.95));
    v.Param("min_pair_distance_m", min_pair_distance_m, "smallest pairing distance", Range::Of(0.005, 0.5).Log());
    v.Param("point_decimation", point_decimation, "pair every n-th scan point", Range::Of(1, 20));
  }
};

struct IcpResult {
  mrpt::poses::CPose2D pose;  // of the scan's frame in the reference's frame
  double goodness = 0;        // fraction of scan points that found a partner
  int iterations = 0;
};

class IcpAligner {
 public:
  explicit IcpAligner(const IcpOptions& options);
  ~IcpAligner();
  IcpAligner(const IcpAligner&) = delete;
  IcpAligner& operator=(const IcpAligner&) = delete;

  IcpResult Align(const mrpt::maps::CSimplePointsMap& reference, const mrpt::maps::CSimplePointsMap& scan,
                  const mrpt::poses::CPose2D& guess);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The valid returns of a scan as points in the car's frame (sensor mount applied).
mrpt::maps::CSimplePointsMap ScanToPoints(const mrpt::obs::CObservation2DRangeScan& scan);

// The points within max_range_m of the frame's origin.
mrpt::maps::CSimplePointsMap WithinRange(const mrpt::maps::CSimplePointsMap& points, double max_range_m);

}  // namespace specht::slam
