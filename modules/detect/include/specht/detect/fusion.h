// specht/detect/fusion.h: a detection box + the stereo disparity → an obstacle in 3D.
//
// Two ways to take the box's disparity d:
//   centre        the paper's: the disparity at the box's centre of gravity, bilinear
//                 between the four valid neighbours (the nearest valid pixel of the
//                 inner box when the centre has none);
//   nearest_mode  robust: a histogram (bin_px) of the valid disparities of the inner
//                 box (inner_fraction of its width and height); the nearest mode
//                 holding at least mode_min_share of them is the object (background
//                 and ground fall into farther modes); d = median of that mode.
// Then Z = f B / d, X = (u_c − c_x) Z / f, Y = (v_c − c_y) Z / f, width and height =
// box size · Z / f, and by first-order propagation of σ_d:
//   σ_Z = Z² σ_d / (f B),   Σ = J diag(σ_u², σ_v², σ_d²) Jᵀ with J = ∂(X,Y,Z)/∂(u,v,d).
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "specht/core/params.h"
#include "specht/detect/detector.h"
#include "specht/stereo/calibration.h"

namespace specht::detect {

// Section "fusion".
struct FusionOptions {
  std::string method = "nearest_mode";
  double inner_fraction = 0.6;
  double bin_px = 1.0;
  double mode_min_share = 0.15;
  double disparity_sigma_px = 0.3;
  double centre_sigma_px = 2.0;
  double max_distance_m = 60;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Choice("method", method, {"nearest_mode", "centre"}, "how a box's disparity is taken (see fusion.h)");
    v.Param("inner_fraction", inner_fraction, "use the central part of the box (fraction of width and height)",
            Range::Of(0.2, 1.0));
    v.Param("bin_px", bin_px, "nearest_mode: histogram bin width (px)", Range::Of(0.25, 4.0));
    v.Param("mode_min_share", mode_min_share, "nearest_mode: least share of the box's valid pixels in the mode",
            Range::Of(0.02, 0.9));
    v.Param("disparity_sigma_px", disparity_sigma_px, "disparity noise for the covariance", Range::Of(0.05, 5.0));
    v.Param("centre_sigma_px", centre_sigma_px, "box centre noise for the covariance", Range::Of(0.1, 20.0));
    v.Param("max_distance_m", max_distance_m, "no 3D position beyond this", Range::Of(5.0, 500.0));
  }
};

struct Obstacle3D {
  Detection detection;
  double disparity_px = 0;
  double distance_m = 0;        // Z, along the optical axis
  cv::Point3d position_camera;  // box centre, camera frame (x right, y down, z forward)
  cv::Size2d size_m;            // width, height
  cv::Matx33d covariance;       // of position_camera
};

// The box's disparity by `method` (0 when the box has no usable disparity).
double BoxDisparity(const cv::Rect2d& box, const cv::Mat& disparity, const FusionOptions& options);

std::optional<Obstacle3D> Fuse(const Detection& detection, const cv::Mat& disparity,
                               const stereo::RectifiedCamera& camera, const FusionOptions& options);

}  // namespace specht::detect
