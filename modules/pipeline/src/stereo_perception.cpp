#include "specht/pipeline/stereo_perception.h"

#include <mrpt/core/Clock.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "specht/core/error.h"

namespace specht::pipeline {
namespace {

using Clock = std::chrono::steady_clock;
double MsSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

cv::Mat Gray(const mrpt::img::CImage& image, const char* which) {
  const cv::Mat m = image.asCvMatRef();
  if (m.empty()) throw InputError(std::string("stereo observation: the ") + which + " image cannot be loaded");
  if (m.channels() == 1) return m;
  cv::Mat gray;
  cv::cvtColor(m, gray, cv::COLOR_BGR2GRAY);
  return gray;
}

// num_disparities for images shrunk k times: a multiple of 32, at least 32.
stereo::SgmOptions ShrunkBy(stereo::SgmOptions o, int k) {
  if (k > 1) o.num_disparities = std::max(32, (o.num_disparities / k + 31) / 32 * 32);
  return o;
}

}  // namespace

types::Obstacle ToMapObstacle(const detect::Obstacle3D& o, const mrpt::poses::CPose3D& map_from_camera, Stamp stamp,
                              long id) {
  types::Obstacle out;
  out.id = id;
  out.cls = o.detection.cls;
  out.stamp = stamp;
  out.score = o.detection.score;
  out.range_m = o.distance_m;
  map_from_camera.composePoint(o.position_camera.x, o.position_camera.y, o.position_camera.z, out.x_m, out.y_m,
                               out.z_m);
  out.radius_m = std::max(0.2, o.size_m.width / 2);
  const auto r = map_from_camera.getRotationMatrix();
  cv::Matx33d rot;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) rot(i, k) = r(i, k);
  const cv::Matx33d map_cov = rot * o.covariance * rot.t();
  out.covariance_xy = cv::Matx22d(map_cov(0, 0), map_cov(0, 1), map_cov(1, 0), map_cov(1, 1));
  return out;
}

stereo::RectifiedCamera CameraOf(const mrpt::obs::CObservationStereoImages& obs, const cv::Size& size) {
  const std::string what = "stereo observation '" + obs.sensorLabel + "' at " +
                           std::to_string(mrpt::Clock::toDouble(obs.timestamp)) + " s: ";
  const mrpt::img::TCamera& left = obs.leftCamera;
  stereo::RectifiedCamera camera;
  camera.size = size;
  camera.focal_px = left.fx();
  camera.cx_px = left.cx();
  camera.cy_px = left.cy();
  camera.baseline_m = mrpt::poses::CPose3D(obs.rightCameraPose).x();
  if (!(camera.focal_px > 0))
    throw InputError(what + "leftCamera: no focal length (fx = " + std::to_string(camera.focal_px) +
                     "): the stereo pair has no calibration");
  if (!(std::abs(camera.baseline_m) > 1e-6))
    throw InputError(
        what +
        "rightCameraPose: no baseline (the right camera sits on the left one): the stereo pair has no calibration");
  if (static_cast<int>(left.ncols) != size.width || static_cast<int>(left.nrows) != size.height)
    throw InputError(what + "leftCamera: intrinsics for " + std::to_string(left.ncols) + "x" +
                     std::to_string(left.nrows) + " but the image is " + std::to_string(size.width) + "x" +
                     std::to_string(size.height));
  if (camera.cx_px < 0 || camera.cx_px > size.width || camera.cy_px < 0 || camera.cy_px > size.height)
    throw InputError(what + "leftCamera: principal point (" + std::to_string(camera.cx_px) + ", " +
                     std::to_string(camera.cy_px) + ") outside the " + std::to_string(size.width) + "x" +
                     std::to_string(size.height) + " image");
  return camera;
}

StereoPerception::StereoPerception(const stereo::SgmOptions& sgm, const detect::DetectorOptions& detector,
                                   const detect::FusionOptions& fusion, const std::string& data_dir, int downsample)
    : sgm_options_(sgm),
      detector_(detector, data_dir),
      fusion_(fusion),
      matcher_(std::make_unique<stereo::SemiGlobalMatcher>(ShrunkBy(sgm, downsample))),
      downsample_(downsample) {}

cv::Mat StereoPerception::Disparity(const cv::Mat& left, const cv::Mat& right) {
  if (downsample_ <= 1) return matcher_->Compute(left, right);
  const cv::Size small(left.cols / downsample_, left.rows / downsample_);
  cv::Mat l, r, disparity;
  cv::resize(left, l, small, 0, 0, cv::INTER_AREA);
  cv::resize(right, r, small, 0, 0, cv::INTER_AREA);
  cv::resize(matcher_->Compute(l, r), disparity, left.size(), 0, 0, cv::INTER_NEAREST);
  return disparity * downsample_;
}

StereoPerception::~StereoPerception() = default;

PerceivedFrame StereoPerception::Process(const mrpt::obs::CObservationStereoImages& obs,
                                         const mrpt::poses::CPose3D& map_from_base, Stamp stamp) {
  return Place(Sense(obs), map_from_base + mrpt::poses::CPose3D(obs.cameraPose), stamp);
}

SensedFrame StereoPerception::Sense(const mrpt::obs::CObservationStereoImages& obs) {
  if (!obs.hasImageRight) throw InputError("stereo observation '" + obs.sensorLabel + "' has no right image");
  const cv::Mat left = Gray(obs.imageLeft, "left"), right = Gray(obs.imageRight, "right");
  SensedFrame sensed;
  sensed.camera = CameraOf(obs, left.size());
  auto t0 = Clock::now();
  sensed.disparity = Disparity(left, right);
  sensed.stereo_ms = MsSince(t0);
  t0 = Clock::now();
  sensed.image = obs.imageLeft.asCvMatRef();
  sensed.detections = detector_.Detect(sensed.image);
  sensed.detect_ms = MsSince(t0);
  return sensed;
}

PerceivedFrame StereoPerception::Place(SensedFrame sensed, const mrpt::poses::CPose3D& map_from_camera, Stamp stamp) {
  const auto t0 = Clock::now();
  PerceivedFrame frame;
  frame.image = std::move(sensed.image);
  frame.disparity = std::move(sensed.disparity);
  frame.camera = sensed.camera;
  frame.detections = std::move(sensed.detections);
  frame.map_from_camera = map_from_camera;
  for (const auto& d : frame.detections) {
    const auto o = detect::Fuse(d, frame.disparity, frame.camera, fusion_);
    frame.obstacle_of.push_back(o ? static_cast<int>(frame.obstacles.size()) : -1);
    if (o) frame.obstacles.push_back(ToMapObstacle(*o, frame.map_from_camera, stamp, next_id_++));
  }
  stats_.stereo_ms += sensed.stereo_ms;
  stats_.detect_ms += sensed.detect_ms;
  stats_.fusion_ms += MsSince(t0);
  ++stats_.frames;
  stats_.detections += static_cast<long>(frame.detections.size());
  stats_.obstacles += static_cast<long>(frame.obstacles.size());
  return frame;
}

}  // namespace specht::pipeline
