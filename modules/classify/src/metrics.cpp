#include "specht/classify/metrics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

#include "specht/core/text.h"
#include "specht/io/map_io.h"

namespace specht::classify {
namespace {

// Colours of classes or models in the pictures (BGR; matplotlib's tab10).
const cv::Scalar kPalette[] = {{180, 119, 31},  {14, 127, 255}, {44, 160, 44},   {40, 39, 214},
                               {189, 103, 148}, {75, 86, 140},  {194, 119, 227}, {127, 127, 127}};
constexpr int kPaletteSize = sizeof(kPalette) / sizeof(kPalette[0]);

void PutLabel(cv::Mat& img, const std::string& text, cv::Point at, double scale = 0.45,
              cv::Scalar colour = cv::Scalar(0, 0, 0)) {
  cv::putText(img, AsciiForImage(text), at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, 1, cv::LINE_AA);
}

}  // namespace

std::vector<int> MostProbable(const std::vector<float>& p, int k) {
  std::vector<int> out(k > 0 ? p.size() / k : 0);
  for (size_t i = 0; i < out.size(); ++i) {
    const auto row = p.begin() + static_cast<long>(i) * k;
    out[i] = static_cast<int>(std::max_element(row, row + k) - row);
  }
  return out;
}

Scores Score(const std::vector<int>& truth, const std::vector<int>& predicted, int k) {
  Scores s;
  s.confusion.assign(k, std::vector<long>(k, 0));
  long n = 0, correct = 0;
  for (size_t i = 0; i < truth.size() && i < predicted.size(); ++i) {
    if (truth[i] < 0 || truth[i] >= k || predicted[i] < 0 || predicted[i] >= k) continue;
    ++s.confusion[truth[i]][predicted[i]];
    ++n;
    correct += truth[i] == predicted[i];
  }
  s.f1.assign(k, 0), s.precision.assign(k, 0), s.recall.assign(k, 0), s.support.assign(k, 0);
  int present = 0;
  for (int c = 0; c < k; ++c) {
    long tp = s.confusion[c][c], fp = 0, fn = 0;
    for (int o = 0; o < k; ++o)
      if (o != c) fp += s.confusion[o][c], fn += s.confusion[c][o];
    s.support[c] = tp + fn;
    s.precision[c] = tp + fp ? static_cast<double>(tp) / (tp + fp) : 0.0;
    s.recall[c] = tp + fn ? static_cast<double>(tp) / (tp + fn) : 0.0;
    const double pr = s.precision[c] + s.recall[c];
    s.f1[c] = pr > 0 ? 2 * s.precision[c] * s.recall[c] / pr : 0.0;
    if (s.support[c] > 0) {
      ++present;
      s.macro_f1 += s.f1[c];
      s.weighted_f1 += s.f1[c] * s.support[c];
    }
  }
  s.macro_f1 = present ? s.macro_f1 / present : 0.0;
  s.weighted_f1 = n ? s.weighted_f1 / n : 0.0;
  s.accuracy = n ? static_cast<double>(correct) / n : 0.0;
  return s;
}

nlohmann::json Scores::ToJson(const std::vector<std::string>& classes) const {
  nlohmann::json j = {{"macro_f1", macro_f1},
                      {"weighted_f1", weighted_f1},
                      {"accuracy", accuracy},
                      {"confusion", confusion},
                      {"classes", classes}};
  for (size_t c = 0; c < classes.size() && c < f1.size(); ++c)
    j["per_class"][classes[c]] = {
        {"f1", f1[c]}, {"precision", precision[c]}, {"recall", recall[c]}, {"support", support[c]}};
  return j;
}

namespace {

// A column heading within `width` pixels, bottom line at `baseline`: split into two
// lines at the last space or hyphen when too wide ("Pleasure Craft", "Cargo-Tanker"),
// then shrunk until the wider line fits.
void PutColumnHeading(cv::Mat& img, const std::string& utf8, int x, int baseline, int width) {
  const std::string text = AsciiForImage(utf8);
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  double scale = 0.45;
  auto wide = [&](const std::string& t) { return cv::getTextSize(t, font, scale, 1, nullptr).width; };
  std::vector<std::string> lines = {text};
  const size_t cut = text.find_last_of(" -");
  if (wide(text) > width && cut != std::string::npos && cut > 0) {
    lines = {text.substr(0, text[cut] == '-' ? cut + 1 : cut), text.substr(cut + 1)};
  }
  const int widest = std::max(wide(lines.front()), wide(lines.back()));
  if (widest > width) scale *= static_cast<double>(width) / widest;
  for (size_t i = 0; i < lines.size(); ++i) {
    const int y = baseline - static_cast<int>(lines.size() - 1 - i) * 17;
    cv::putText(img, lines[i], {x, y}, font, scale, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
}

}  // namespace

void WriteConfusionPng(const Scores& s, const std::vector<std::string>& classes, const std::string& title,
                       const std::string& path) {
  const int k = static_cast<int>(classes.size()), cell = 90, left = 150, top = 70;
  cv::Mat img(top + k * cell + 60, left + k * cell + 20, CV_8UC3, cv::Scalar(255, 255, 255));
  PutLabel(img, title, {10, 25}, 0.6);
  for (int r = 0; r < k; ++r) {
    const double support = std::max<long>(1, s.support[r]);
    for (int c = 0; c < k; ++c) {
      const double f = s.confusion[r][c] / support;
      const int shade = static_cast<int>(255 - 200 * f);
      const cv::Rect box(left + c * cell, top + r * cell, cell, cell);
      cv::rectangle(img, box, cv::Scalar(255, shade, shade), cv::FILLED);
      cv::rectangle(img, box, cv::Scalar(120, 120, 120), 1);
      char text[48];
      std::snprintf(text, sizeof(text), "%.2f", f);
      const cv::Scalar ink = f > 0.6 ? cv::Scalar(255, 255, 255) : cv::Scalar(0, 0, 0);
      PutLabel(img, text, {box.x + 18, box.y + 40}, 0.6, ink);
      std::snprintf(text, sizeof(text), "(%ld)", s.confusion[r][c]);
      PutLabel(img, text, {box.x + 18, box.y + 62}, 0.42, ink);
    }
    PutLabel(img, classes[r], {8, top + r * cell + cell / 2 + 5}, 0.5);
  }
  for (int c = 0; c < k; ++c) PutColumnHeading(img, classes[c], left + c * cell + 4, top - 8, cell - 8);
  PutLabel(img, "rows: truth, columns: predicted (fraction of the row, count)", {10, top + k * cell + 35}, 0.45,
           cv::Scalar(60, 60, 60));
  io::WritePng(img, path);
}

void WriteStepCountsPng(const std::map<std::string, std::map<std::string, long>>& counts,
                        const std::vector<std::string>& steps, const std::vector<std::string>& classes,
                        const std::string& title, const std::string& path) {
  const int k = static_cast<int>(classes.size()), n = static_cast<int>(steps.size());
  const int bar = 16, group = k * bar + 30, left = 70, top = 50, height = 300;
  cv::Mat img(top + height + 90, left + n * group + 180, CV_8UC3, cv::Scalar(255, 255, 255));
  PutLabel(img, title, {10, 25}, 0.6);
  long max_count = 1;
  for (const auto& [step, per_class] : counts)
    for (const auto& [cls, c] : per_class) max_count = std::max(max_count, c);
  const double decades = std::max(1.0, std::ceil(std::log10(static_cast<double>(max_count) + 1)));
  auto y_of = [&](double v) { return top + height - static_cast<int>(height * std::log10(v + 1) / decades); };
  for (int d = 0; d <= decades; ++d) {
    const int y = y_of(std::pow(10.0, d) - 1);
    cv::line(img, {left - 5, y}, {left + n * group, y}, cv::Scalar(220, 220, 220), 1);
    PutLabel(img, "1e" + std::to_string(d), {15, y + 5}, 0.4, cv::Scalar(60, 60, 60));
  }
  for (int s = 0; s < n; ++s) {
    const auto it = counts.find(steps[s]);
    for (int c = 0; c < k; ++c) {
      long v = 0;
      if (it != counts.end() && it->second.count(classes[c])) v = it->second.at(classes[c]);
      const int x = left + s * group + c * bar;
      cv::rectangle(img, cv::Point(x, y_of(static_cast<double>(v))), cv::Point(x + bar - 2, top + height),
                    kPalette[c % kPaletteSize], cv::FILLED);
    }
    PutLabel(img, steps[s], {left + s * group, top + height + 20});
  }
  for (int c = 0; c < k; ++c) {
    const int y = top + 10 + c * 22, x = left + n * group + 15;
    cv::rectangle(img, cv::Point(x, y), cv::Point(x + 14, y + 14), kPalette[c % kPaletteSize], cv::FILLED);
    PutLabel(img, classes[c], {x + 20, y + 12});
  }
  PutLabel(img, "count per class after each step (log scale)", {left, top + height + 50}, 0.45, cv::Scalar(60, 60, 60));
  io::WritePng(img, path);
}

// Shares on a log₂ axis from the smallest to 1; scores on a linear axis over the
// bars' range, padded and rounded to 0.05.
void WriteLearningCurvePng(const std::map<std::string, std::vector<CurvePoint>>& curves, const std::string& title,
                           const std::string& y_label, const std::string& path) {
  const int w = 900, h = 520, left = 70, right = 170, top = 50, bottom = 60;
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(255, 255, 255));
  PutLabel(img, title, {10, 25}, 0.55);
  double smallest = 1, lo = 1, hi = 0;
  std::vector<double> shares;
  for (const auto& [model, points] : curves)
    for (const auto& p : points) {
      smallest = std::min(smallest, p.share);
      lo = std::min(lo, p.mean - p.std), hi = std::max(hi, p.mean + p.std);
      if (std::find(shares.begin(), shares.end(), p.share) == shares.end()) shares.push_back(p.share);
    }
  lo = std::max(0.0, std::floor(lo * 20 - 0.5) / 20), hi = std::min(1.0, std::ceil(hi * 20 + 0.5) / 20);
  if (hi <= lo) lo = 0, hi = 1;
  const double span = std::max(1e-9, -std::log2(smallest));
  const auto X = [&](double share) {
    return left + 20 + static_cast<int>((w - left - right - 40) * (span + std::log2(share)) / span);
  };
  const auto Y = [&](double v) { return top + static_cast<int>((h - top - bottom) * (hi - v) / (hi - lo)); };
  cv::rectangle(img, {left, top}, {w - right, h - bottom}, cv::Scalar(0, 0, 0));
  char buf[32];
  for (double v = lo; v <= hi + 1e-9; v += 0.05) {
    cv::line(img, {left, Y(v)}, {w - right, Y(v)}, cv::Scalar(230, 230, 230));
    std::snprintf(buf, sizeof(buf), "%.2f", v);
    PutLabel(img, buf, {left - 45, Y(v) + 4}, 0.4);
  }
  for (double s : shares) {
    std::snprintf(buf, sizeof(buf), "%g", s);
    PutLabel(img, buf, {X(s) - 12, h - bottom + 20}, 0.4);
  }
  PutLabel(img, "share of each class's training objects (log scale)", {left, h - 15});
  PutLabel(img, y_label, {left, top - 8}, 0.45, cv::Scalar(60, 60, 60));
  int index = 0;
  for (const auto& [model, points] : curves) {
    const cv::Scalar colour = kPalette[index % kPaletteSize];
    const int dx = 4 * (index - static_cast<int>(curves.size()) / 2);  // bars side by side, not on top of each other
    for (size_t i = 0; i < points.size(); ++i) {
      const cv::Point at(X(points[i].share) + dx, Y(points[i].mean));
      cv::line(img, {at.x, Y(points[i].mean - points[i].std)}, {at.x, Y(points[i].mean + points[i].std)}, colour);
      cv::circle(img, at, 4, colour, cv::FILLED, cv::LINE_AA);
      if (i > 0) cv::line(img, {X(points[i - 1].share) + dx, Y(points[i - 1].mean)}, at, colour, 2, cv::LINE_AA);
    }
    const int y = top + 10 + index * 22, x = w - right + 15;
    cv::rectangle(img, cv::Point(x, y), cv::Point(x + 14, y + 14), colour, cv::FILLED);
    PutLabel(img, model, {x + 20, y + 12});
    ++index;
  }
  io::WritePng(img, path);
}

}  // namespace specht::classify
