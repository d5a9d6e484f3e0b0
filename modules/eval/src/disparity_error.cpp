#include "specht/eval/disparity_error.h"

#include <cmath>

namespace specht::eval {
namespace {

bool Bad(double error, double truth, double threshold) { return error > threshold && error > 0.05 * truth; }

}  // namespace

DisparityErrors CompareDisparity(const cv::Mat& estimate, const cv::Mat& truth, const cv::Mat& mask) {
  CV_Assert(estimate.type() == CV_32FC1 && truth.type() == CV_32FC1 && estimate.size() == truth.size());
  CV_Assert(mask.empty() || (mask.type() == CV_8UC1 && mask.size() == truth.size()));
  DisparityErrors e;
  size_t d1 = 0, bad2 = 0, d1_est = 0, bad2_est = 0, estimated_anywhere = 0;
  double epe = 0;
  for (int y = 0; y < truth.rows; ++y) {
    const float* est = estimate.ptr<float>(y);
    const float* gt = truth.ptr<float>(y);
    const uint8_t* m = mask.empty() ? nullptr : mask.ptr<uint8_t>(y);
    for (int x = 0; x < truth.cols; ++x) {
      if (m != nullptr && m[x] == 0) continue;
      if (est[x] > 0) ++estimated_anywhere;
      if (!(gt[x] > 0)) continue;
      ++e.gt_pixels;
      if (!(est[x] > 0)) {
        ++d1;
        ++bad2;
        continue;
      }
      ++e.est_pixels;
      const double error = std::abs(static_cast<double>(est[x]) - gt[x]);
      epe += error;
      const bool is_d1 = Bad(error, gt[x], 3.0), is_bad2 = error > 2.0;
      d1 += is_d1;
      d1_est += is_d1;
      bad2 += is_bad2;
      bad2_est += is_bad2;
    }
  }
  const size_t scored = mask.empty() ? truth.total() : static_cast<size_t>(cv::countNonZero(mask));
  auto ratio = [](double a, size_t b) { return b == 0 ? 0.0 : a / static_cast<double>(b); };
  e.d1_all = ratio(static_cast<double>(d1), e.gt_pixels);
  e.bad2_all = ratio(static_cast<double>(bad2), e.gt_pixels);
  e.d1_est = ratio(static_cast<double>(d1_est), e.est_pixels);
  e.bad2_est = ratio(static_cast<double>(bad2_est), e.est_pixels);
  e.epe_est = ratio(epe, e.est_pixels);
  e.density_gt = ratio(static_cast<double>(e.est_pixels), e.gt_pixels);
  e.density = ratio(static_cast<double>(estimated_anywhere), scored);
  return e;
}

cv::Mat DisparityErrorImage(const cv::Mat& estimate, const cv::Mat& truth) {
  // KITTI's error colour scale: error / 3 px steps from blue to red.
  static const double kBounds[] = {0.1875, 0.375, 0.75, 1.5, 3, 6, 12, 24, 48, 1e9};
  static const cv::Vec3b kColours[] = {{149, 54, 49},   {180, 117, 69},  {209, 173, 116}, {233, 217, 171},
                                       {248, 243, 224}, {144, 224, 254}, {97, 174, 253},  {67, 109, 244},
                                       {39, 48, 215},   {38, 0, 165}};
  cv::Mat picture(truth.size(), CV_8UC3, cv::Scalar::all(0));
  for (int y = 0; y < truth.rows; ++y) {
    for (int x = 0; x < truth.cols; ++x) {
      const float gt = truth.at<float>(y, x), est = estimate.at<float>(y, x);
      if (!(gt > 0)) continue;
      if (!(est > 0)) {
        picture.at<cv::Vec3b>(y, x) = cv::Vec3b(255, 255, 255);
        continue;
      }
      const double scaled = std::min(std::abs(est - gt) / 3.0, 20.0 * std::abs(est - gt) / gt);
      int i = 0;
      while (scaled > kBounds[i]) ++i;
      picture.at<cv::Vec3b>(y, x) = kColours[i];
    }
  }
  return picture;
}

nlohmann::json ToJson(const DisparityErrors& e) {
  return {{"d1_all", e.d1_all},     {"bad2_all", e.bad2_all},   {"d1_est", e.d1_est},
          {"bad2_est", e.bad2_est}, {"epe_est_px", e.epe_est},  {"density_gt", e.density_gt},
          {"density", e.density},   {"gt_pixels", e.gt_pixels}, {"est_pixels", e.est_pixels}};
}

}  // namespace specht::eval
