#include "specht/tune/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "specht/core/error.h"
#include "specht/core/text.h"

namespace specht::tune {

void WriteConvergencePng(const RunResult& r, bool maximise, const std::string& metric, const std::string& path) {
  const int w = 900, h = 500, left = 80, right = 20, top = 40, bottom = 50;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& e : r.evaluations)
    if (e.ok) lo = std::min(lo, e.value), hi = std::max(hi, e.value);
  if (!std::isfinite(lo)) lo = 0, hi = 1;
  if (hi - lo < 1e-12) hi = lo + 1;
  const double pad = 0.05 * (hi - lo);
  lo -= pad, hi += pad;
  const int n = std::max<int>(2, static_cast<int>(r.evaluations.size()));
  const auto X = [&](int i) { return left + static_cast<int>((w - left - right) * static_cast<double>(i) / (n - 1)); };
  const auto Y = [&](double v) { return top + static_cast<int>((h - top - bottom) * (hi - v) / (hi - lo)); };
  cv::rectangle(img, {left, top}, {w - right, h - bottom}, cv::Scalar(0, 0, 0));
  char buf[96];
  for (int k = 0; k <= 4; ++k) {
    const double v = lo + (hi - lo) * k / 4;
    std::snprintf(buf, sizeof(buf), "%.4g", v);
    cv::putText(img, buf, {5, Y(v) + 4}, cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 0, 0));
  }
  std::snprintf(buf, sizeof(buf), "evaluation (0 = defaults, %zu in all)", r.evaluations.size());
  cv::putText(img, buf, {left, h - 15}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0));
  cv::putText(img, AsciiForImage(metric) + (maximise ? " (higher is better)" : " (lower is better)"), {left, 25},
              cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(0, 0, 0));
  if (!r.evaluations.empty() && r.evaluations[0].ok) {
    const int y = Y(r.evaluations[0].value);
    for (int x = left; x < w - right; x += 12) cv::line(img, {x, y}, {std::min(x + 6, w - right), y}, {0, 140, 0});
    cv::putText(img, "defaults", {w - right - 70, y - 5}, cv::FONT_HERSHEY_SIMPLEX, 0.45, {0, 140, 0});
  }
  cv::Point previous(-1, -1);
  double best = maximise ? -INFINITY : INFINITY;
  for (size_t i = 0; i < r.evaluations.size(); ++i) {
    const Evaluation& e = r.evaluations[i];
    if (!e.ok) {
      cv::line(img, {X(static_cast<int>(i)), h - bottom}, {X(static_cast<int>(i)), h - bottom - 8}, {0, 0, 220});
      continue;
    }
    cv::circle(img, {X(static_cast<int>(i)), Y(e.value)}, 2, cv::Scalar(150, 150, 150), cv::FILLED);
    best = maximise ? std::max(best, e.value) : std::min(best, e.value);
    const cv::Point p(X(static_cast<int>(i)), Y(best));
    if (previous.x >= 0) {
      cv::line(img, previous, {p.x, previous.y}, cv::Scalar(200, 80, 0), 2);
      cv::line(img, {p.x, previous.y}, p, cv::Scalar(200, 80, 0), 2);
    }
    previous = p;
  }
  if (!cv::imwrite(path, img)) throw RuntimeError(path + ": cannot write PNG");
}

}  // namespace specht::tune
