#include "specht/detect/fusion.h"

#include <algorithm>
#include <cmath>

namespace specht::detect {
namespace {

cv::Rect InnerBox(const cv::Rect2d& box, double fraction, cv::Size size) {
  const double w = box.width * fraction, h = box.height * fraction;
  const cv::Rect inner(static_cast<int>(std::lround(box.x + (box.width - w) / 2)),
                       static_cast<int>(std::lround(box.y + (box.height - h) / 2)), std::max(1, static_cast<int>(w)),
                       std::max(1, static_cast<int>(h)));
  return inner & cv::Rect(cv::Point(0, 0), size);
}

double CentreDisparity(const cv::Rect2d& box, const cv::Mat& disparity, const cv::Rect& inner) {
  const double u = box.x + box.width / 2 - 0.5, v = box.y + box.height / 2 - 0.5;
  const int u0 = static_cast<int>(std::floor(u)), v0 = static_cast<int>(std::floor(v));
  double sum = 0, weights = 0;
  for (int dv = 0; dv <= 1; ++dv)
    for (int du = 0; du <= 1; ++du) {
      const int x = u0 + du, y = v0 + dv;
      if (x < 0 || y < 0 || x >= disparity.cols || y >= disparity.rows) continue;
      const float d = disparity.at<float>(y, x);
      if (!(d > 0)) continue;
      const double w = (du ? u - u0 : 1 - (u - u0)) * (dv ? v - v0 : 1 - (v - v0));
      sum += w * d;
      weights += w;
    }
  if (weights > 1e-6) return sum / weights;
  // No valid neighbour: the nearest valid pixel of the inner box.
  double best = 0, best_distance = 1e18;
  for (int y = inner.y; y < inner.y + inner.height; ++y)
    for (int x = inner.x; x < inner.x + inner.width; ++x) {
      const float d = disparity.at<float>(y, x);
      const double r = (x - u) * (x - u) + (y - v) * (y - v);
      if (d > 0 && r < best_distance) best = d, best_distance = r;
    }
  return best;
}

double NearestModeDisparity(const cv::Mat& disparity, const cv::Rect& inner, const FusionOptions& o) {
  std::vector<float> values;
  for (int y = inner.y; y < inner.y + inner.height; ++y)
    for (int x = inner.x; x < inner.x + inner.width; ++x)
      if (disparity.at<float>(y, x) > 0) values.push_back(disparity.at<float>(y, x));
  if (values.empty()) return 0;
  const float top = *std::max_element(values.begin(), values.end());
  const int bins = static_cast<int>(top / o.bin_px) + 2;
  std::vector<int> histogram(static_cast<size_t>(bins), 0);
  for (float d : values) ++histogram[static_cast<size_t>(d / o.bin_px)];
  const double needed = o.mode_min_share * values.size();
  // From the nearest (largest disparity) down: the first window of 3 bins holding enough.
  for (int b = bins - 1; b >= 0; --b) {
    const int lo = std::max(0, b - 1), hi = std::min(bins - 1, b + 1);
    int count = 0;
    for (int i = lo; i <= hi; ++i) count += histogram[static_cast<size_t>(i)];
    if (count < needed) continue;
    std::vector<float> mode;
    for (float d : values)
      if (d >= lo * o.bin_px && d < (hi + 1) * o.bin_px) mode.push_back(d);
    std::nth_element(mode.begin(), mode.begin() + static_cast<long>(mode.size() / 2), mode.end());
    return mode[mode.size() / 2];
  }
  return 0;
}

}  // namespace

double BoxDisparity(const cv::Rect2d& box, const cv::Mat& disparity, const FusionOptions& options) {
  CV_Assert(disparity.type() == CV_32FC1);
  const cv::Rect inner = InnerBox(box, options.inner_fraction, disparity.size());
  if (inner.area() == 0) return 0;
  return options.method == "centre" ? CentreDisparity(box, disparity, inner)
                                    : NearestModeDisparity(disparity, inner, options);
}

std::optional<Obstacle3D> Fuse(const Detection& detection, const cv::Mat& disparity,
                               const stereo::RectifiedCamera& camera, const FusionOptions& options) {
  const double d = BoxDisparity(detection.box, disparity, options);
  if (!(d > 0)) return std::nullopt;
  const double f = camera.focal_px, fb = f * camera.baseline_m, z = fb / d;
  if (z > options.max_distance_m) return std::nullopt;
  const double u = detection.box.x + detection.box.width / 2, v = detection.box.y + detection.box.height / 2;
  Obstacle3D o;
  o.detection = detection;
  o.disparity_px = d;
  o.distance_m = z;
  o.position_camera = cv::Point3d((u - camera.cx_px) * z / f, (v - camera.cy_px) * z / f, z);
  o.size_m = cv::Size2d(detection.box.width * z / f, detection.box.height * z / f);
  // X = (u − c_x) B / d, Y = (v − c_y) B / d, Z = f B / d.
  const double b = camera.baseline_m;
  const cv::Matx33d j(b / d, 0, -(u - camera.cx_px) * b / (d * d),  //
                      0, b / d, -(v - camera.cy_px) * b / (d * d),  //
                      0, 0, -fb / (d * d));
  const double su = options.centre_sigma_px, sd = options.disparity_sigma_px;
  o.covariance = j * cv::Matx33d(su * su, 0, 0, 0, su * su, 0, 0, 0, sd * sd) * j.t();
  return o;
}

}  // namespace specht::detect
