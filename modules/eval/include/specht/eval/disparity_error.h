// specht/eval/disparity_error.h: disparity against ground truth, as KITTI 2015 scores it.
//
// A pixel with ground truth g and estimate e is bad at threshold τ when
//   |e − g| > τ px  and  |e − g| > 5 % of g        (D1: τ = 3; bad-2: |e − g| > 2 px)
// Over "all" pixels with ground truth, a missing estimate counts as bad (fill holes
// first to score as the KITTI benchmark does); over "estimated" pixels only the
// pixels with an estimate count. End-point error is the mean |e − g| of estimated pixels.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

namespace specht::eval {

struct DisparityErrors {
  double d1_all = 0, bad2_all = 0;  // fractions of ground-truth pixels
  double d1_est = 0, bad2_est = 0;  // fractions of estimated ground-truth pixels
  double epe_est = 0;               // px
  double density_gt = 0;            // estimated / ground-truth pixels
  double density = 0;               // estimated / all pixels
  size_t gt_pixels = 0, est_pixels = 0;
};

// estimate, truth: CV_32F, 0 = none. mask (optional CV_8U): pixels to score.
DisparityErrors CompareDisparity(const cv::Mat& estimate, const cv::Mat& truth, const cv::Mat& mask = cv::Mat());

// KITTI-style error picture (BGR): blue (small) to red (large error), dark where
// there is no ground truth, white where ground truth has no estimate.
cv::Mat DisparityErrorImage(const cv::Mat& estimate, const cv::Mat& truth);

nlohmann::json ToJson(const DisparityErrors& e);

}  // namespace specht::eval
