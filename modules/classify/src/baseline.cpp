#include "specht/classify/baseline.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/core.hpp>
#include <opencv2/ml.hpp>

#include "specht/core/error.h"

namespace specht::classify {
namespace {

double Mean(const std::vector<double>& v) {
  return v.empty() ? 0 : std::accumulate(v.begin(), v.end(), 0.0) / v.size();
}
double Std(const std::vector<double>& v) {
  if (v.size() < 2) return 0;
  const double m = Mean(v);
  double s = 0;
  for (double x : v) s += (x - m) * (x - m);
  return std::sqrt(s / v.size());
}
double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + i, v.end());
  return v[i];
}

}  // namespace

int HandcraftedFeatureCount() { return 23; }

std::vector<float> HandcraftedFeatures(const Window& w, const MapFeatures& map,
                                       const std::vector<std::string>& features) {
  auto named = [&](const char* f) { return std::find(features.begin(), features.end(), f) != features.end(); };
  const bool use_static = map.distance_to_static && named("dist_static");
  const bool use_poi = map.distance_to_poi && named("dist_poi");
  const bool use_region = map.region && (named("region_x") || named("region_y"));
  const bool use_category = named("category");
  const auto& p = w.points;
  std::vector<double> speed, accel, turn, intervals, ds, dp, rx, ry;
  double path = 0, prev_course = 0;
  for (size_t i = 1; i < p.size(); ++i) {
    const double dt = p[i].t_s - p[i - 1].t_s, step = std::hypot(p[i].x - p[i - 1].x, p[i].y - p[i - 1].y);
    path += step;
    intervals.push_back(dt);
    if (dt <= 0) continue;
    speed.push_back(step / dt);
    const double course = std::atan2(p[i].y - p[i - 1].y, p[i].x - p[i - 1].x);
    if (speed.size() > 1) {
      accel.push_back(std::abs(speed.back() - speed[speed.size() - 2]) / dt);
      turn.push_back(std::abs(std::remainder(course - prev_course, 2 * M_PI)) / dt);
    }
    prev_course = course;
  }
  for (const auto& q : p) {
    if (use_static) ds.push_back(map.distance_to_static(q.x, q.y));
    if (use_poi) dp.push_back(map.distance_to_poi(q.x, q.y));
    if (use_region) {
      const auto r = map.region(q.x, q.y);
      rx.push_back(r[0]), ry.push_back(r[1]);
    }
  }
  const double vmax = speed.empty() ? 0 : *std::max_element(speed.begin(), speed.end());
  const double stops = speed.empty() ? 0 : std::count_if(speed.begin(), speed.end(), [&](double v) {
                                             return v < 0.1 * vmax;
                                           }) / static_cast<double>(speed.size());
  const double net = p.empty() ? 0 : std::hypot(p.back().x - p.front().x, p.back().y - p.front().y);
  const double tmax = turn.empty() ? 0 : *std::max_element(turn.begin(), turn.end());
  return {static_cast<float>(Mean(speed)),
          static_cast<float>(Std(speed)),
          static_cast<float>(Quantile(speed, 0.1)),
          static_cast<float>(Quantile(speed, 0.5)),
          static_cast<float>(Quantile(speed, 0.9)),
          static_cast<float>(vmax),
          static_cast<float>(Mean(accel)),
          static_cast<float>(Std(accel)),
          static_cast<float>(Mean(turn)),
          static_cast<float>(Std(turn)),
          static_cast<float>(tmax),
          static_cast<float>(stops),
          static_cast<float>(path > 0 ? net / path : 0),
          static_cast<float>(p.empty() ? 0 : p.back().t_s - p.front().t_s),
          static_cast<float>(Quantile(intervals, 0.1)),
          static_cast<float>(Quantile(intervals, 0.5)),
          static_cast<float>(Quantile(intervals, 0.9)),
          static_cast<float>(Mean(ds)),
          static_cast<float>(ds.empty() ? 0 : *std::min_element(ds.begin(), ds.end())),
          static_cast<float>(Mean(dp)),
          static_cast<float>(Mean(rx)),
          static_cast<float>(Mean(ry)),
          static_cast<float>(use_category ? w.category : 0)};
}

std::vector<float> CombinedProbabilities(const std::vector<float>& network, const std::vector<float>& forest) {
  if (network.size() != forest.size())
    throw InputError("combining network and forest: " + std::to_string(network.size()) + " against " +
                     std::to_string(forest.size()) + " probabilities");
  std::vector<float> out(network.size());
  for (size_t i = 0; i < out.size(); ++i) out[i] = 0.5f * (network[i] + forest[i]);
  return out;
}

ForestBaseline::ForestBaseline(int trees, int max_depth, int seed)
    : trees_(trees), max_depth_(max_depth), seed_(seed) {}

void ForestBaseline::Train(const std::vector<float>& x, const std::vector<int>& y) {
  const int n = static_cast<int>(y.size()), f = HandcraftedFeatureCount();
  if (n == 0 || x.size() != static_cast<size_t>(n) * f) throw InputError("forest baseline: empty or mis-sized data");
  cv::theRNG().state = static_cast<uint64>(seed_);
  forest_ = cv::ml::RTrees::create();
  forest_->setMaxDepth(max_depth_);
  forest_->setMinSampleCount(2);
  forest_->setTermCriteria(cv::TermCriteria(cv::TermCriteria::MAX_ITER, trees_, 0));
  const cv::Mat samples(n, f, CV_32F, const_cast<float*>(x.data()));
  const cv::Mat labels(n, 1, CV_32S, const_cast<int*>(y.data()));
  forest_->train(cv::ml::TrainData::create(samples, cv::ml::ROW_SAMPLE, labels));
}

std::vector<int> ForestBaseline::Predict(const std::vector<float>& x) const {
  const int f = HandcraftedFeatureCount(), n = static_cast<int>(x.size() / f);
  std::vector<int> out(n);
  if (n == 0) return out;
  cv::Mat result;
  forest_->predict(cv::Mat(n, f, CV_32F, const_cast<float*>(x.data())), result);
  for (int i = 0; i < n; ++i) out[i] = static_cast<int>(std::lround(result.at<float>(i)));
  return out;
}

std::vector<float> ForestBaseline::Probabilities(const std::vector<float>& x, int classes) const {
  const int f = HandcraftedFeatureCount(), n = static_cast<int>(x.size() / f);
  std::vector<float> out(static_cast<size_t>(n) * classes, 0.0f);
  if (n == 0) return out;
  // getVotes: row 0 holds the class labels, row 1 + i the trees' votes for sample i.
  cv::Mat votes;
  forest_->getVotes(cv::Mat(n, f, CV_32F, const_cast<float*>(x.data())), votes, 0);
  for (int i = 0; i < n; ++i) {
    double total = 0;
    for (int c = 0; c < votes.cols; ++c) total += votes.at<int>(i + 1, c);
    for (int c = 0; c < votes.cols; ++c) {
      const int label = votes.at<int>(0, c);
      if (label >= 0 && label < classes && total > 0)
        out[static_cast<size_t>(i) * classes + label] = static_cast<float>(votes.at<int>(i + 1, c) / total);
    }
  }
  return out;
}

void ForestBaseline::Save(const std::string& path) const { forest_->save(path); }

ForestBaseline ForestBaseline::Load(const std::string& path) {
  ForestBaseline f;
  try {
    f.forest_ = cv::ml::RTrees::load(path);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": not an OpenCV RTrees model (" + e.msg + ")");
  }
  if (!f.forest_ || !f.forest_->isTrained()) throw InputError(path + ": not a trained OpenCV RTrees model");
  if (f.forest_->getVarCount() != HandcraftedFeatureCount())
    throw InputError(path + ": a forest on " + std::to_string(f.forest_->getVarCount()) +
                     " features, this version uses " + std::to_string(HandcraftedFeatureCount()) + " (train it again)");
  return f;
}

}  // namespace specht::classify
