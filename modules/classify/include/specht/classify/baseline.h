// specht/classify/baseline.h: the baseline to beat — a random forest (OpenCV ml
// RTrees) on hand-crafted motion and map features of a window:
//   speed mean, std, 10/50/90th percentile, max; |acceleration| mean and std;
//   |turn rate| mean, std, max; fraction of steps below 10 % of the window's max speed
//   (stops); straightness (net displacement / path length); duration; the time between
//   samples, 10/50/90th percentile (AIS: class A transponders report every 2–10 s
//   under way, class B ones, on most pleasure craft, every 30 s, so the intervals
//   differ by class); distance to the static layer (mean, min) and to the nearest
//   point of interest (mean); the mean region (map position, when the map gives
//   one; else 0); the object's category code (AIS: the flag's MID; the trees split
//   its ranges, e.g. 2xx Europe).
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "specht/classify/preprocess.h"

namespace cv::ml {
class RTrees;
}

namespace specht::classify {

// The baseline's features of one window. Its geography and category are only what
// the network's `features` name (dist_static, dist_poi, region_x / region_y,
// category; 0 where not named), so that both models compare on the same
// information, an ablation takes it from both, and training and prediction cannot
// disagree.
std::vector<float> HandcraftedFeatures(const Window& w, const MapFeatures& map,
                                       const std::vector<std::string>& features);
int HandcraftedFeatureCount();

// The network and the forest combined: the mean of their class probabilities, row
// by row (the forest's are its trees' vote fractions). On the robot classes it
// matched or beat both; on AIS it is level with the forest on one window and ahead
// from a vessel's windows so far (README); both sizes must agree.
std::vector<float> CombinedProbabilities(const std::vector<float>& network, const std::vector<float>& forest);

class ForestBaseline {
 public:
  explicit ForestBaseline(int trees = 200, int max_depth = 12, int seed = 1);
  // x: size × HandcraftedFeatureCount(), row-major.
  void Train(const std::vector<float>& x, const std::vector<int>& y);
  std::vector<int> Predict(const std::vector<float>& x) const;
  // The fraction of trees voting for each class, size × classes, row-major.
  std::vector<float> Probabilities(const std::vector<float>& x, int classes) const;
  // OpenCV's own YAML model file.
  void Save(const std::string& path) const;
  static ForestBaseline Load(const std::string& path);  // InputError when unreadable

 private:
  int trees_, max_depth_, seed_;
  cv::Ptr<cv::ml::RTrees> forest_;
};

}  // namespace specht::classify
