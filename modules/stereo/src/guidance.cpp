#include "specht/stereo/guidance.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace specht::stereo {

cv::Mat SampleHints(const cv::Mat& truth, double fraction, uint64_t seed) {
  CV_Assert(truth.type() == CV_32FC1);
  std::vector<int> candidates;
  for (int i = 0; i < static_cast<int>(truth.total()); ++i)
    if (truth.at<float>(i / truth.cols, i % truth.cols) > 0) candidates.push_back(i);
  const size_t wanted = std::min(candidates.size(), static_cast<size_t>(std::lround(fraction * truth.total())));
  std::mt19937_64 rng(seed);
  // Partial Fisher–Yates: the first `wanted` entries become a uniform sample.
  for (size_t i = 0; i < wanted; ++i) {
    std::uniform_int_distribution<size_t> pick(i, candidates.size() - 1);
    std::swap(candidates[i], candidates[pick(rng)]);
  }
  cv::Mat hints(truth.size(), CV_32FC1, cv::Scalar(0));
  for (size_t i = 0; i < wanted; ++i) {
    const int y = candidates[i] / truth.cols, x = candidates[i] % truth.cols;
    hints.at<float>(y, x) = truth.at<float>(y, x);
  }
  return hints;
}

Guidance HintsGuidance(const cv::Mat& sparse_disparity) {
  return Guidance{Guidance::Kind::kHints, sparse_disparity, cv::Mat()};
}

cv::Mat GroundPlaneDisparity(const GroundPlane& p, cv::Size size, double max_disparity) {
  cv::Mat disparity(size, CV_32FC1, cv::Scalar(0));
  for (int v = 0; v < size.height; ++v) {
    const double d =
        p.baseline_m / p.height_m * (std::cos(p.pitch_rad) * (v - p.cy_px) + p.focal_px * std::sin(p.pitch_rad));
    if (d > 0 && d < max_disparity) disparity.row(v).setTo(d);
  }
  return disparity;
}

Guidance PriorGuidance(const cv::Mat& prior_disparity, double confidence) {
  cv::Mat weight(prior_disparity.size(), CV_32FC1, cv::Scalar(0));
  weight.setTo(confidence, prior_disparity > 0);
  return Guidance{Guidance::Kind::kPrior, prior_disparity, weight};
}

}  // namespace specht::stereo
