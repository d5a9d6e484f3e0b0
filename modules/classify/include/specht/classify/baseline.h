// specht/classify/baseline.h: the baseline to beat — a random forest (OpenCV ml
// RTrees) on hand-crafted motion and map features of a window:
//   speed mean, std, 10/50/90th percentile, max; |acceleration| mean and std;
//   |turn rate| mean, std, max; fraction of steps below 10 % of the window's max speed
//   (stops); straightness (net displacement / path length); duration; distance to the
//   static layer (mean, min) and to the nearest point of interest (mean); the mean
//   region (map position, when the map gives one; else 0).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "specht/classify/preprocess.h"

#include <opencv2/core.hpp>

namespace cv::ml {
class RTrees;
}

namespace specht::classify {

std::vector<float> HandcraftedFeatures(const Window& w, const MapFeatures& map);
int HandcraftedFeatureCount();

class ForestBaseline {
 public:
  explicit ForestBaseline(int trees = 200, int max_depth = 12, int seed = 1);
  // x: size × HandcraftedFeatureCount(), row-major.
  void Train(const std::vector<float>& x, const std::vector<int>& y);
  std::vector<int> Predict(const std::vector<float>& x) const;
  // OpenCV's own YAML model file.
  void Save(const std::string& path) const;
  static ForestBaseline Load(const std::string& path);  // InputError when unreadable

 private:
  int trees_, max_depth_, seed_;
  cv::Ptr<cv::ml::RTrees> forest_;
};

}  // namespace specht::classify
