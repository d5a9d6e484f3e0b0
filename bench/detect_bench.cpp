// detect_bench [data_dir]: each shipped detector on the KITTI frames (ms per frame,
// median of 10, detections per frame), and the whole perception step at 1242×375:
// our SGM (2 threads) + detection + fusion, run one after the other (latency) and
// with the stages of consecutive frames overlapped on two threads (throughput).
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <future>
#include <iostream>
#include <opencv2/imgcodecs.hpp>

#include "bench_support.h"
#include "specht/detect/detector.h"
#include "specht/detect/fusion.h"
#include "specht/stereo/images.h"
#include "specht/stereo/sgm.h"

namespace {

using Clock = std::chrono::steady_clock;
double Ms(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::milli>(b - a).count(); }
double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  const std::string data = argc > 1 ? argv[1] : SPECHT_DATA_DIR;
  if (!std::filesystem::is_directory(data + "/models")) {
    std::cerr << "detect_bench: no models under " << data << "\n";
    return 2;
  }
  const std::string k = data + "/stereo/kitti2015/";
  std::vector<cv::Mat> colour, left, right;
  for (const char* f : {"000000_10", "000001_10"}) {
    colour.push_back(cv::imread(k + "image_2/" + f + ".png"));
    left.push_back(specht::stereo::ReadGray8(k + "image_2/" + f + ".png"));
    right.push_back(specht::stereo::ReadGray8(k + "image_3/" + f + ".png"));
  }
  const specht::stereo::RectifiedCamera camera{left[0].size(), 721.5377, 609.5593, 172.854, 0.5327};
  for (const char* model : {"yolo-fastest", "fastestdet"}) {
    specht::detect::Detector detector(specht::detect::ShippedModel(model), data);
    std::vector<double> detect_ms;
    long detections = 0;
    for (int run = 0; run < 10; ++run)
      for (const auto& image : colour) {
        const auto t0 = Clock::now();
        const auto found = detector.Detect(image);
        detect_ms.push_back(Ms(t0, Clock::now()));
        if (run == 0) detections += static_cast<long>(found.size());
      }
    // The perception step: SGM → detection → fusion.
    specht::stereo::SemiGlobalMatcher matcher{specht::stereo::SgmOptions()};
    std::vector<double> sgm_ms, step_ms;
    for (int run = 0; run < 10; ++run) {
      const size_t i = static_cast<size_t>(run) % left.size();
      const auto t0 = Clock::now();
      const cv::Mat disparity = matcher.Compute(left[i], right[i]);
      const auto t1 = Clock::now();
      for (const auto& d : detector.Detect(colour[i])) specht::detect::Fuse(d, disparity, camera, {});
      sgm_ms.push_back(Ms(t0, t1));
      step_ms.push_back(Ms(t0, Clock::now()));
    }
    // Overlapped: frame n's detection runs beside frame n+1's matching.
    const int frames = 20;
    const auto p0 = Clock::now();
    std::future<void> detecting;
    for (int n = 0; n < frames; ++n) {
      const size_t i = static_cast<size_t>(n) % left.size();
      const cv::Mat disparity = matcher.Compute(left[i], right[i]);
      if (detecting.valid()) detecting.get();
      detecting = std::async(std::launch::async, [&, i, disparity] {
        for (const auto& d : detector.Detect(colour[i])) specht::detect::Fuse(d, disparity, camera, {});
      });
    }
    detecting.get();
    const double pipelined_fps = frames / (Ms(p0, Clock::now()) / 1000.0);
    specht::bench::Emit({{"name", std::string("detect/") + model},
                         {"input", std::to_string(detector.options().input_width) + "x" +
                                       std::to_string(detector.options().input_height)},
                         {"detect_ms_p50", Median(detect_ms)},
                         {"detections_on_2_kitti_frames", detections},
                         {"sgm_ms_p50", Median(sgm_ms)},
                         {"perception_step_latency_ms_p50", Median(step_ms)},
                         {"perception_fps_sequential", 1000.0 / Median(step_ms)},
                         {"perception_fps_pipelined", pipelined_fps},
                         {"peak_rss_mib", specht::bench::PeakRssMib()},
                         {"machine", specht::bench::MachineNotes()}});
  }
  return 0;
}
