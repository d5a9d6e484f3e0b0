#include "specht/pipeline/perception.h"

#include <chrono>
#include <deque>
#include <set>

#include <mrpt/obs/CObservationStereoImages.h>
#include <octomap/OcTree.h>
#include <opencv2/imgproc.hpp>

#include "specht/core/error.h"
#include "specht/core/log.h"
#include "internal/perception_video.h"
#include "specht/pipeline/map_features.h"
#include "specht/pipeline/pose_history.h"
#include "specht/pipeline/stereo_perception.h"
#include "specht/stereo/point_cloud.h"
#include "specht/track/tracker.h"

namespace specht::pipeline {
namespace {

using Clock = std::chrono::steady_clock;
double MsSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// The disparity at 1/k of the resolution, with the camera that goes with it: pixel
// coordinates and disparities both scale by 1/k, so depth f·B/d is unchanged.
std::pair<cv::Mat, stereo::RectifiedCamera> Decimated(const cv::Mat& disparity, stereo::RectifiedCamera camera,
                                                      int k) {
  if (k <= 1) return {disparity, camera};
  cv::Mat small;
  cv::resize(disparity, small, cv::Size(disparity.cols / k, disparity.rows / k), 0, 0, cv::INTER_NEAREST);
  small /= k;
  camera.size = small.size();
  camera.focal_px /= k;
  camera.cx_px /= k;
  camera.cy_px /= k;
  return {small, camera};
}

}  // namespace

nlohmann::json PerceptionSummary::ToJson() const {
  const long frames = stereo.frames;
  const auto per_frame = [&](double ms) { return frames > 0 ? ms / frames : 0.0; };
  return {{"frames", frames},
          {"detections", stereo.detections},
          {"obstacles", stereo.obstacles},
          {"track_updates", track_updates},
          {"tracks_confirmed", tracks_confirmed},
          {"frames_at_held_pose", frames_at_held_pose},
          {"windows_classified", windows_classified},
          {"ms_per_frame",
           {{"stereo", per_frame(stereo.stereo_ms)},
            {"detect", per_frame(stereo.detect_ms)},
            {"fusion", per_frame(stereo.fusion_ms)},
            {"track", per_frame(track_ms)},
            {"classify", per_frame(classify_ms)},
            {"octree", per_frame(octree_ms)},
            {"world", per_frame(world_ms)},
            {"video", per_frame(video_ms)}}}};
}

struct PerceptionPipeline::Stages {
  StereoPerception perception;
  track::Tracker tracker;
  stereo::CloudOptions cloud;
  std::unique_ptr<octomap::OcTree> octree;
  PoseHistory poses;
  std::deque<std::pair<Stamp, mrpt::obs::CObservation::Ptr>> queued;
  PerceptionSummary summary;
  std::set<long> confirmed;

  Stages(const params::Params& p, const std::string& data_dir, bool with_octree)
      : perception(p.Get<stereo::SgmOptions>("stereo"), p.Get<detect::DetectorOptions>("detect"),
                   p.Get<detect::FusionOptions>("fusion"), data_dir),
        tracker(p.Get<track::TrackerOptions>("track")),
        cloud(p.Get<stereo::CloudOptions>("stereo_cloud")) {
    if (with_octree) octree = std::make_unique<octomap::OcTree>(cloud.octree_resolution_m);
  }
};

PerceptionPipeline::PerceptionPipeline(const params::Params& params, std::string data_dir)
    : params_(params), options_(params.Get<PerceptionOptions>("perception")), data_dir_(std::move(data_dir)),
      world_(params.Get<world::WorldModelOptions>("world")) {
  if (options_.mode == "off" || options_.classifier_model.empty()) return;
  classifier_ = std::make_unique<OnlineClassifier>(
      std::make_shared<classify::TrajectoryClassifier>(
          classify::TrajectoryClassifier::LoadDirectory(options_.classifier_model, options_.classifier_network_only)),
      OnlineClassifier::Averaging::kTrack);
}

PerceptionPipeline::~PerceptionPipeline() = default;

bool PerceptionPipeline::active() const { return stages_ != nullptr; }

bool PerceptionPipeline::Start() {
  try {
    stages_ = std::make_unique<Stages>(params_, data_dir_, options_.octree);
  } catch (const InputError& e) {
    if (options_.mode == "on") throw;
    spdlog::warn("perception off: {}", e.what());
    options_.mode = "off";
    return false;
  }
  return true;
}

void PerceptionPipeline::Add(Stamp t, const mrpt::obs::CObservation::Ptr& o) {
  if (options_.mode == "off" || !std::dynamic_pointer_cast<mrpt::obs::CObservationStereoImages>(o)) return;
  if (!stages_ && !Start()) return;
  stages_->queued.emplace_back(t, o);
  ProcessQueued(false);
}

void PerceptionPipeline::AddPose(Stamp t, const mrpt::poses::CPose3D& map_from_base) {
  if (!stages_) return;
  stages_->poses.Add(t, map_from_base);
  ProcessQueued(false);
}

void PerceptionPipeline::Finish() {
  if (stages_) ProcessQueued(true);
}

// A frame goes once a pose at or after its stamp is known, or when the newest
// observation is max_pose_wait_s past it (then at the latest pose), or at the end.
void PerceptionPipeline::ProcessQueued(bool flush) {
  auto& q = stages_->queued;
  while (!q.empty()) {
    const auto [t, frame] = q.front();
    const bool covered = stages_->poses.Covers(t);
    const bool waited = SecondsBetween(t, q.back().first) > options_.max_pose_wait_s;
    if (!covered && !waited && !flush) return;
    const auto pose = stages_->poses.At(t);
    if (!covered) ++stages_->summary.frames_at_held_pose;
    q.pop_front();
    ProcessFrame(frame, t, pose.value_or(mrpt::poses::CPose3D()));
  }
}

void PerceptionPipeline::ProcessFrame(const mrpt::obs::CObservation::Ptr& o, Stamp t,
                                      const mrpt::poses::CPose3D& pose) {
  Stages& s = *stages_;
  const auto& stereo_obs = static_cast<const mrpt::obs::CObservationStereoImages&>(*o);
  const PerceivedFrame frame = s.perception.Process(stereo_obs, pose, t);

  auto t0 = Clock::now();
  s.tracker.Update(frame.obstacles, t);
  std::vector<types::Track> tracks = s.tracker.Tracks();
  s.summary.track_ms += MsSince(t0);
  if (classifier_) {
    t0 = Clock::now();
    classifier_->Update(tracks, map_features_);
    s.summary.classify_ms += MsSince(t0);
  }

  world::WorldUpdate update;
  update.stamp = t;
  update.obstacles = frame.obstacles;
  update.tracks = tracks;
  // The OctoMap grows every frame but is published (copied) with the snapshots only:
  // a kept snapshot holds all its layers of one frame.
  const bool snapshot_due =
      !last_snapshot_ || SecondsBetween(*last_snapshot_, t) >= options_.snapshot_period_s - 1e-9;
  if (s.octree) {
    t0 = Clock::now();
    const auto [disparity, camera] = Decimated(frame.disparity, frame.camera, options_.octree_decimation);
    std::vector<stereo::ColouredPoint> points = stereo::DisparityToPoints(disparity, camera, cv::Mat(), s.cloud);
    stereo::TransformPoints(points, frame.map_from_camera);
    const cv::Point3f origin(static_cast<float>(frame.map_from_camera.x()), static_cast<float>(frame.map_from_camera.y()),
                             static_cast<float>(frame.map_from_camera.z()));
    stereo::InsertIntoOctree(*s.octree, points, origin, s.cloud);
    if (snapshot_due) update.octree = std::make_shared<const octomap::OcTree>(*s.octree);
    s.summary.octree_ms += MsSince(t0);
  }
  t0 = Clock::now();
  world_.Apply(update);
  s.summary.world_ms += MsSince(t0);

  for (const auto& tr : tracks) {
    track_samples_.push_back({"t" + std::to_string(tr.id), t.Seconds(), tr.x_m, tr.y_m, tr.cls, "", false,
                              tr.class_probabilities});
    if (tr.state == "confirmed") s.confirmed.insert(tr.id);
  }
  for (const auto& ob : frame.obstacles)
    seen_[ob.cls].push_back({ob.stamp, mrpt::poses::CPose3D(ob.x_m, ob.y_m, 0, 0, 0, 0)});
  ++s.summary.track_updates;
  if (snapshot_due) KeepSnapshot();
  if (camera_video_) {
    t0 = Clock::now();
    WriteVideoFrames(frame, tracks, pose);
    s.summary.video_ms += MsSince(t0);
  }
}

void PerceptionPipeline::WriteVideosTo(const std::string& dir) {
  if (options_.mode == "off" || options_.video == "off") return;
  const auto format = options_.video == "png" ? io::VideoSink::Format::kPng : io::VideoSink::Format::kMp4;
  camera_video_ = std::make_unique<io::VideoSink>(dir + "/camera.mp4", options_.video_fps, format);
  birds_eye_video_ = std::make_unique<io::VideoSink>(dir + "/birds_eye.mp4", options_.video_fps, format);
}

void PerceptionPipeline::WriteVideoFrames(const PerceivedFrame& frame, const std::vector<types::Track>& tracks,
                                          const mrpt::poses::CPose3D& pose) {
  const auto snapshot = world_.snapshot();
  if (!first_frame_) first_frame_ = snapshot->stamp;
  camera_video_->Write(internal::AnnotatedCamera(frame, tracks));
  birds_eye_video_->Write(internal::BirdsEye(*snapshot, pose, SecondsBetween(*first_frame_, snapshot->stamp),
                                             options_.birds_eye_extent_m, options_.birds_eye_px));
}

std::vector<std::string> PerceptionPipeline::CloseVideos() {
  std::vector<std::string> written;
  for (auto* video : {camera_video_.get(), birds_eye_video_.get()})
    if (video)
      if (std::string name = video->Close(); !name.empty()) written.push_back(name);
  return written;
}

void PerceptionPipeline::KeepSnapshot() {
  const auto snapshot = world_.snapshot();
  snapshots_.push_back(snapshot->ToJson());
  last_snapshot_ = snapshot->stamp;
}

void PerceptionPipeline::SetStaticMap(const mrpt::maps::COccupancyGridMap2D& grid, Stamp t) {
  if (!stages_) return;
  world_.SetStaticMap(grid, t);
  if (classifier_) map_features_ = GridMapFeatures(grid);
  last_map_ = t;
}

bool PerceptionPipeline::StaticMapDue(Stamp t) const {
  return stages_ && (!last_map_ || SecondsBetween(*last_map_, t) >= options_.map_update_s);
}

PerceptionSummary PerceptionPipeline::summary() const {
  if (!stages_) return {};
  PerceptionSummary out = stages_->summary;
  out.stereo = stages_->perception.stats();
  out.tracks_confirmed = static_cast<long>(stages_->confirmed.size());
  if (classifier_) out.windows_classified = classifier_->windows();
  return out;
}

}  // namespace specht::pipeline
