// specht/stereo/guidance.h: where guidance for the matcher comes from (sgm.h says
// how it is used).
//   Sparse hints: a sparse disparity map (LiDAR projected into the left image, or
//   any file), or a random sample of ground truth (for evaluation).
//   Dense priors: the ground plane seen from a camera at known height and pitch, or
//   any rendered model of the static scene, each with a confidence.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>

#include "specht/stereo/sgm.h"

namespace specht::stereo {

// Hints at `fraction` of all image pixels, drawn uniformly (seeded) from the pixels
// where `truth` (CV_32F) has a value. Returns CV_32F, 0 = no hint.
cv::Mat SampleHints(const cv::Mat& truth, double fraction, uint64_t seed);

Guidance HintsGuidance(const cv::Mat& sparse_disparity);

// The disparity of a flat ground seen by a rectified camera (x right, y down, z
// forward) at height h above it, pitched down by θ:
//   ground normal in the camera frame n = (0, cos θ, sin θ), points X with n·X = h;
//   along the ray r = ((u − c_x)/f, (v − c_y)/f, 1): Z = h / (n·r), so
//   d(v) = f B / Z = (B / h) · (cos θ · (v − c_y) + f sin θ)     (rows where d > 0).
struct GroundPlane {
  double focal_px = 0, cy_px = 0, baseline_m = 0;
  double height_m = 0, pitch_rad = 0;
};
cv::Mat GroundPlaneDisparity(const GroundPlane& plane, cv::Size size, double max_disparity);

// A dense prior with one confidence for every pixel that has a prior disparity.
Guidance PriorGuidance(const cv::Mat& prior_disparity, double confidence);

}  // namespace specht::stereo
