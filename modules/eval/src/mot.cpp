#include "specht/eval/mot.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "specht/core/assignment.h"
#include "specht/core/error.h"

namespace specht::eval {
namespace {

using FrameMap = std::map<int64_t, std::vector<const io::ObjectSample*>>;

int64_t FrameKey(double t_s) { return std::llround(t_s * 1000.0); }

FrameMap ByFrame(const std::vector<io::ObjectSample>& samples, bool ignored) {
  FrameMap frames;
  for (const auto& s : samples)
    if (s.ignore == ignored) frames[FrameKey(s.t_s)].push_back(&s);
  return frames;
}

double Distance(const io::ObjectSample& a, const io::ObjectSample& b) {
  return std::hypot(a.x_m - b.x_m, a.y_m - b.y_m);
}

}  // namespace

namespace {
void UpdateRates(MotResult& r) {
  r.mota = r.truth_objects
               ? 1.0 - static_cast<double>(r.false_negatives + r.false_positives + r.id_switches) / r.truth_objects
               : 0.0;
  r.motp_m = r.matches ? r.distance_sum_m / r.matches : 0.0;
  r.id_switches_per_100s = r.track_seconds > 0 ? 100.0 * r.id_switches / r.track_seconds : 0.0;
}
}  // namespace

void MotResult::Add(const MotResult& o) {
  frames += o.frames, truth_objects += o.truth_objects, matches += o.matches;
  false_negatives += o.false_negatives, false_positives += o.false_positives, id_switches += o.id_switches;
  fragmentations += o.fragmentations, truth_ids += o.truth_ids, hypothesis_ids += o.hypothesis_ids;
  mostly_tracked += o.mostly_tracked, mostly_lost += o.mostly_lost;
  distance_sum_m += o.distance_sum_m, track_seconds += o.track_seconds;
  truth_of_hypothesis.insert(o.truth_of_hypothesis.begin(), o.truth_of_hypothesis.end());
  UpdateRates(*this);
}

nlohmann::json MotResult::ToJson() const {
  return {{"mota", mota},
          {"motp_m", motp_m},
          {"id_switches", id_switches},
          {"id_switches_per_100s", id_switches_per_100s},
          {"false_negatives", false_negatives},
          {"false_positives", false_positives},
          {"matches", matches},
          {"truth_objects", truth_objects},
          {"frames", frames},
          {"fragmentations", fragmentations},
          {"truth_ids", truth_ids},
          {"hypothesis_ids", hypothesis_ids},
          {"mostly_tracked", mostly_tracked},
          {"mostly_lost", mostly_lost},
          {"track_seconds", track_seconds}};
}

MotResult EvaluateMot(const std::vector<io::ObjectSample>& truth, const std::vector<io::ObjectSample>& hypotheses,
                      double match_threshold_m) {
  if (!(match_threshold_m > 0)) throw InputError("eval track: the match threshold must be positive");
  const FrameMap truth_frames = ByFrame(truth, false), hyp_frames = ByFrame(hypotheses, false);
  const FrameMap dont_care = ByFrame(truth, true);
  std::set<int64_t> keys;
  for (const auto& [k, v] : truth_frames) keys.insert(k);
  for (const auto& [k, v] : hyp_frames) keys.insert(k);

  MotResult r;
  std::map<std::string, std::string> last_match;          // truth id → hypothesis id at its last match
  std::map<std::string, bool> tracked_last_frame;         // truth id → matched in its previous frame
  std::map<std::string, std::pair<long, long>> coverage;  // truth id → (frames, matched frames)
  std::map<std::string, std::map<std::string, long>> votes;
  std::set<std::string> hyp_ids;
  const std::vector<const io::ObjectSample*> none;
  for (const int64_t key : keys) {
    const auto ti = truth_frames.find(key), hi = hyp_frames.find(key);
    const auto& gt = ti == truth_frames.end() ? none : ti->second;
    const auto& hy = hi == hyp_frames.end() ? none : hi->second;
    ++r.frames;
    r.truth_objects += static_cast<long>(gt.size());
    for (const auto* h : hy) hyp_ids.insert(h->id);

    std::vector<int> hyp_of(gt.size(), -1);
    std::vector<char> hyp_used(hy.size(), 0);
    // Keep last frame's correspondences that still hold.
    for (size_t g = 0; g < gt.size(); ++g) {
      const auto it = last_match.find(gt[g]->id);
      if (it == last_match.end() || !tracked_last_frame[gt[g]->id]) continue;
      for (size_t h = 0; h < hy.size(); ++h)
        if (!hyp_used[h] && hy[h]->id == it->second && Distance(*gt[g], *hy[h]) <= match_threshold_m) {
          hyp_of[g] = static_cast<int>(h);
          hyp_used[h] = 1;
        }
    }
    // The rest by optimal assignment.
    std::vector<size_t> free_gt, free_hy;
    for (size_t g = 0; g < gt.size(); ++g)
      if (hyp_of[g] < 0) free_gt.push_back(g);
    for (size_t h = 0; h < hy.size(); ++h)
      if (!hyp_used[h]) free_hy.push_back(h);
    std::vector<std::vector<double>> cost(free_gt.size(), std::vector<double>(free_hy.size()));
    for (size_t a = 0; a < free_gt.size(); ++a)
      for (size_t b = 0; b < free_hy.size(); ++b) cost[a][b] = Distance(*gt[free_gt[a]], *hy[free_hy[b]]);
    const Assignment assignment = SolveAssignment(cost, match_threshold_m);
    for (size_t a = 0; a < free_gt.size(); ++a) {
      const int b = assignment.column_of_row[a];
      if (b < 0) continue;
      hyp_of[free_gt[a]] = static_cast<int>(free_hy[b]);
      hyp_used[free_hy[b]] = 1;
    }

    for (size_t g = 0; g < gt.size(); ++g) {
      const std::string& id = gt[g]->id;
      auto& cov = coverage[id];
      ++cov.first;
      if (hyp_of[g] < 0) {
        ++r.false_negatives;
        tracked_last_frame[id] = false;
        continue;
      }
      const auto& h = *hy[hyp_of[g]];
      ++r.matches;
      ++cov.second;
      r.distance_sum_m += Distance(*gt[g], h);
      const auto last = last_match.find(id);
      if (last != last_match.end() && last->second != h.id) ++r.id_switches;
      const auto seen = tracked_last_frame.find(id);
      if (seen != tracked_last_frame.end() && !seen->second && last != last_match.end()) ++r.fragmentations;
      last_match[id] = h.id;
      tracked_last_frame[id] = true;
      ++votes[h.id][id];
    }
    // Unmatched hypotheses on a don't-care object are not false positives.
    const auto di = dont_care.find(key);
    for (size_t h = 0; h < hy.size(); ++h) {
      if (hyp_used[h]) continue;
      bool on_ignored = false;
      if (di != dont_care.end())
        for (const auto* d : di->second) on_ignored |= Distance(*d, *hy[h]) <= match_threshold_m;
      r.false_positives += on_ignored ? 0 : 1;
    }
  }

  r.truth_ids = static_cast<int>(coverage.size());
  r.hypothesis_ids = static_cast<int>(hyp_ids.size());
  for (const auto& [id, cov] : coverage) {
    const double fraction = static_cast<double>(cov.second) / cov.first;
    r.mostly_tracked += fraction >= 0.8;
    r.mostly_lost += fraction < 0.2;
  }
  for (const auto& [h, by_truth] : votes)
    r.truth_of_hypothesis[h] =
        std::max_element(by_truth.begin(), by_truth.end(), [](auto& a, auto& b) { return a.second < b.second; })->first;
  std::vector<double> gaps;
  for (auto it = truth_frames.begin(); it != truth_frames.end() && std::next(it) != truth_frames.end(); ++it)
    gaps.push_back((std::next(it)->first - it->first) / 1000.0);
  if (!gaps.empty()) {
    std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
    r.track_seconds = r.truth_objects * gaps[gaps.size() / 2];
  }
  UpdateRates(r);
  return r;
}

}  // namespace specht::eval
