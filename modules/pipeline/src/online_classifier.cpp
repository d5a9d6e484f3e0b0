#include "specht/pipeline/online_classifier.h"

#include <chrono>

namespace specht::pipeline {

OnlineClassifier::OnlineClassifier(std::shared_ptr<const classify::TrajectoryClassifier> classifier,
                                   Averaging averaging)
    : classifier_(std::move(classifier)), averaging_(averaging) {}

void OnlineClassifier::Update(std::vector<types::Track>& tracks, const classify::MapFeatures& map) {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<classify::Window> windows;
  std::vector<types::Track*> owners;
  for (auto& t : tracks) {
    if (t.state != "confirmed") continue;
    classify::Trajectory trajectory{std::to_string(t.id), "", {}};
    for (const auto& p : t.history) trajectory.points.push_back({p.stamp.Seconds(), p.x_m, p.y_m});
    if (auto w = classifier_->LatestWindow(trajectory)) windows.push_back(std::move(*w)), owners.push_back(&t);
  }
  const auto& classes = classifier_->classes();
  const std::vector<float> p = windows.empty() ? std::vector<float>() : classifier_->Classify(windows, map);
  for (size_t i = 0; i < owners.size(); ++i) {
    const float* row = p.data() + i * classes.size();
    if (averaging_ == Averaging::kLatest) {
      for (size_t c = 0; c < classes.size(); ++c) owners[i]->class_probabilities[classes[c]] = row[c];
      continue;
    }
    Sum& sum = sums_[owners[i]->id];
    sum.p.resize(classes.size(), 0.0);
    for (size_t c = 0; c < classes.size(); ++c) sum.p[c] += row[c];
    ++sum.n;
  }
  if (averaging_ == Averaging::kTrack)
    for (auto& t : tracks) {
      const auto it = sums_.find(t.id);
      if (it == sums_.end()) continue;
      for (size_t c = 0; c < classes.size(); ++c) t.class_probabilities[classes[c]] = it->second.p[c] / it->second.n;
    }
  windows_ += static_cast<long>(owners.size());
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace specht::pipeline
