// specht/pipeline/online_classifier.h: the trajectory classifier on live tracks.
//
// After every tracker update, each confirmed track's latest window (the last
// `classify.length` filtered positions of its history, classify/trajectory_classifier.h)
// is classified with the map features of the scene, all tracks of the frame in one
// batch. A track's class probabilities are then either that window's answer
// (Averaging::kLatest, what `specht track --model` scores per track-frame) or the
// mean over every window of the track classified so far (Averaging::kTrack, what the
// perception pipeline publishes: a track's class should not flicker with each frame).
// A track too short for a window keeps the probabilities it had, none at first.
#pragma once

#include <map>
#include <memory>
#include <vector>

#include "specht/classify/trajectory_classifier.h"
#include "specht/types/track.h"

namespace specht::pipeline {

class OnlineClassifier {
 public:
  enum class Averaging { kLatest, kTrack };

  OnlineClassifier(std::shared_ptr<const classify::TrajectoryClassifier> classifier, Averaging averaging);

  // Sets class_probabilities of `tracks` (one tracker cycle) as described above.
  void Update(std::vector<types::Track>& tracks, const classify::MapFeatures& map);

  const classify::TrajectoryClassifier& classifier() const { return *classifier_; }
  long windows() const { return windows_; }    // classified so far
  double seconds() const { return seconds_; }  // spent classifying

 private:
  struct Sum {
    std::vector<double> p;
    long n = 0;
  };
  std::shared_ptr<const classify::TrajectoryClassifier> classifier_;
  Averaging averaging_;
  std::map<long, Sum> sums_;  // by track id (kTrack)
  long windows_ = 0;
  double seconds_ = 0;
};

}  // namespace specht::pipeline
