#include "specht/pipeline/perception.h"

#include <mrpt/obs/CObservationStereoImages.h>
#include <octomap/OcTree.h>

#include <chrono>
#include <deque>
#include <future>
#include <opencv2/imgproc.hpp>
#include <set>

#include "internal/perception_video.h"
#include "specht/core/error.h"
#include "specht/core/log.h"
#include "specht/core/serial_worker.h"
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
std::pair<cv::Mat, stereo::RectifiedCamera> Decimated(const cv::Mat& disparity, stereo::RectifiedCamera camera, int k) {
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

// Whether `period_s` (data time, to a nanosecond) has passed since `last`, or nothing was done yet.
bool PeriodDue(const std::optional<Stamp>& last, Stamp t, double period_s) {
  return !last || SecondsBetween(*last, t) >= period_s - 1e-9;
}

// One frame's stereo points (every k-th pixel) into the OctoMap, rays from the camera.
void InsertIntoOctree(octomap::OcTree& octree, const cv::Mat& full_disparity,
                      const stereo::RectifiedCamera& full_camera, const mrpt::poses::CPose3D& map_from_camera, int k,
                      const stereo::CloudOptions& cloud) {
  const auto [disparity, camera] = Decimated(full_disparity, full_camera, k);
  std::vector<stereo::ColouredPoint> points = stereo::DisparityToPoints(disparity, camera, cv::Mat(), cloud);
  stereo::TransformPoints(points, map_from_camera);
  const cv::Point3f origin(static_cast<float>(map_from_camera.x()), static_cast<float>(map_from_camera.y()),
                           static_cast<float>(map_from_camera.z()));
  stereo::InsertIntoOctree(octree, points, origin, cloud);
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
  // A frame waiting for its pose, its images being sensed (or sensed) meanwhile.
  struct Queued {
    Stamp t;
    std::shared_ptr<const mrpt::obs::CObservationStereoImages> observation;
    std::shared_future<SensedFrame> sensed;
  };
  std::deque<Queued> queued;
  std::shared_future<SensedFrame> last_sensed;  // the newest frame's: the next one's sensing waits for it
  PerceptionSummary summary;
  std::set<long> confirmed;
  SerialWorker mapping;  // OctoMap insertion and video frames, in frame order

  Stages(const params::Params& p, const std::string& data_dir, const PerceptionOptions& o)
      : perception(p.Get<stereo::SgmOptions>("stereo"), p.Get<detect::DetectorOptions>("detect"),
                   p.Get<detect::FusionOptions>("fusion"), data_dir, o.stereo_downsample),
        tracker(p.Get<track::TrackerOptions>("track")),
        cloud(p.Get<stereo::CloudOptions>("stereo_cloud")) {
    if (o.octree) octree = std::make_unique<octomap::OcTree>(cloud.octree_resolution_m);
  }
};

PerceptionPipeline::PerceptionPipeline(const params::Params& params, std::string data_dir)
    : params_(params),
      options_(params.Get<PerceptionOptions>("perception")),
      data_dir_(std::move(data_dir)),
      world_(params.Get<world::WorldModelOptions>("world")) {
  if (options_.mode == "off" || options_.classifier_model.empty()) return;
  auto classifier = std::make_shared<classify::TrajectoryClassifier>(
      classify::TrajectoryClassifier::LoadDirectory(options_.classifier_model, options_.classifier_network_only));
  classifier->set_threads(options_.classifier_threads);
  classifier_ = std::make_unique<OnlineClassifier>(classifier, OnlineClassifier::Averaging::kTrack);
}

PerceptionPipeline::~PerceptionPipeline() {
  // The mapping worker's tasks write the videos and the OctoMap: let them finish first.
  try {
    if (stages_) stages_->mapping.Wait();
  } catch (const std::exception& e) {
    spdlog::error("perception: {}", e.what());
  }
}

bool PerceptionPipeline::active() const { return stages_ != nullptr; }

bool PerceptionPipeline::Start() {
  try {
    stages_ = std::make_unique<Stages>(params_, data_dir_, options_);
  } catch (const InputError& e) {
    if (options_.mode == "on") throw;
    spdlog::warn("perception off: {}", e.what());
    options_.mode = "off";
    return false;
  }
  return true;
}

// Each frame's images are sensed (SGM, detector) as it arrives, on a worker thread
// when `pipelined` (one frame at a time, in order: a frame's task waits for the one
// before), so that SLAM and the previous frames' tracking and mapping run meanwhile.
void PerceptionPipeline::Add(Stamp t, const mrpt::obs::CObservation::Ptr& o) {
  auto stereo = std::dynamic_pointer_cast<const mrpt::obs::CObservationStereoImages>(o);
  if (options_.mode == "off" || !stereo) return;
  if (!stages_ && !Start()) return;
  Stages& s = *stages_;
  StereoPerception* perception = &s.perception;
  const auto launch = options_.pipelined ? std::launch::async : std::launch::deferred;
  s.last_sensed = std::async(launch, [perception, stereo, previous = s.last_sensed] {
                    if (previous.valid()) previous.wait();
                    return perception->Sense(*stereo);
                  }).share();
  s.queued.push_back({t, stereo, s.last_sensed});
  ProcessQueued(false);
}

void PerceptionPipeline::AddPose(Stamp t, const mrpt::poses::CPose3D& map_from_base) {
  if (!stages_) return;
  stages_->poses.Add(t, map_from_base);
  ProcessQueued(false);
}

void PerceptionPipeline::Finish() {
  if (!stages_) return;
  ProcessQueued(true);
  stages_->mapping.Wait();
}

// A frame goes once a pose at or after its stamp is known (and, pipelined, the next
// frame has arrived), or when the newest frame is max_pose_wait_s past it (then at
// the latest pose), or at the end.
void PerceptionPipeline::ProcessQueued(bool flush) {
  auto& q = stages_->queued;
  while (!q.empty()) {
    const Stages::Queued frame = q.front();
    const bool covered = stages_->poses.Covers(frame.t);
    const bool waited = SecondsBetween(frame.t, q.back().t) > options_.max_pose_wait_s;
    // Pipelined, a frame also waits for the next one to arrive, whose sensing then
    // runs while this one is tracked and mapped (one frame of latency).
    const bool next_arrived = !options_.pipelined || q.size() >= 2;
    if (!((covered && next_arrived) || waited || flush)) return;
    const auto pose = stages_->poses.At(frame.t).value_or(mrpt::poses::CPose3D());
    if (!covered) ++stages_->summary.frames_at_held_pose;
    q.pop_front();
    const mrpt::poses::CPose3D map_from_camera = pose + mrpt::poses::CPose3D(frame.observation->cameraPose);
    ProcessFrame(stages_->perception.Place(frame.sensed.get(), map_from_camera, frame.t), frame.t, pose);
    ApplyPendingStaticMap();
  }
}

void PerceptionPipeline::ProcessFrame(const PerceivedFrame& frame, Stamp t, const mrpt::poses::CPose3D& pose) {
  Stages& s = *stages_;

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
  // The OctoMap takes a frame's points every octree_period_s (on the mapping worker)
  // and is published (copied) with the snapshots only: a kept snapshot holds all its
  // layers of one frame.
  const bool snapshot_due = PeriodDue(last_snapshot_, t, options_.snapshot_period_s);
  const bool octree_due = PeriodDue(last_octree_, t, options_.octree_period_s);
  if (s.octree && octree_due) {
    last_octree_ = t;
    RunMapping([this, &s, disparity = frame.disparity, camera = frame.camera, to_map = frame.map_from_camera] {
      const auto t0 = Clock::now();
      InsertIntoOctree(*s.octree, disparity, camera, to_map, options_.octree_decimation, s.cloud);
      s.summary.octree_ms += MsSince(t0);
    });
  }
  t0 = Clock::now();  // publishing: the OctoMap's copy (once its insertions are done) and the update
  if (s.octree && snapshot_due) {
    if (options_.pipelined) s.mapping.Wait();
    update.octree = std::make_shared<const octomap::OcTree>(*s.octree);
  }
  world_.Apply(update);
  s.summary.world_ms += MsSince(t0);

  for (const auto& tr : tracks) {
    track_samples_.push_back(
        {"t" + std::to_string(tr.id), t.Seconds(), tr.x_m, tr.y_m, tr.cls, "", false, tr.class_probabilities});
    if (tr.state == "confirmed") s.confirmed.insert(tr.id);
  }
  for (const auto& ob : frame.obstacles)
    seen_[ob.cls].push_back({ob.stamp, mrpt::poses::CPose3D(ob.x_m, ob.y_m, 0, 0, 0, 0)});
  ++s.summary.track_updates;
  if (snapshot_due) KeepSnapshot();
  if (camera_video_) {
    const auto snapshot = world_.snapshot();
    if (!first_frame_) first_frame_ = t;
    RunMapping([this, &s, frame, tracks, pose, snapshot, t_s = SecondsBetween(*first_frame_, t)] {
      const auto t0 = Clock::now();
      camera_video_->Write(internal::AnnotatedCamera(frame, tracks));
      birds_eye_video_->Write(
          internal::BirdsEye(*snapshot, pose, t_s,
                             internal::BirdsEyeView::Around(pose, options_.birds_eye_extent_m, options_.birds_eye_px)));
      s.summary.video_ms += MsSince(t0);
    });
  }
}

void PerceptionPipeline::RunMapping(std::function<void()> task) {
  if (options_.pipelined)
    stages_->mapping.Post(std::move(task));
  else
    task();
}

void PerceptionPipeline::WriteVideosTo(const std::string& dir) {
  if (options_.mode == "off" || options_.video == "off") return;
  const auto format = options_.video == "png" ? io::VideoSink::Format::kPng : io::VideoSink::Format::kMp4;
  camera_video_ = std::make_unique<io::VideoSink>(dir + "/camera.mp4", options_.video_fps, format);
  birds_eye_video_ = std::make_unique<io::VideoSink>(dir + "/birds_eye.mp4", options_.video_fps, format);
}

std::vector<std::string> PerceptionPipeline::CloseVideos() {
  if (stages_) stages_->mapping.Wait();
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

// The static layer is written in stamp order with the frames: after every queued
// frame older than it (pipelined, frames wait for the next one to arrive).
void PerceptionPipeline::SetStaticMap(const mrpt::maps::COccupancyGridMap2D& grid, Stamp t) {
  if (!stages_) return;
  pending_static_ = {std::make_shared<const mrpt::maps::COccupancyGridMap2D>(grid), t};
  last_map_ = t;
  ApplyPendingStaticMap();
}

void PerceptionPipeline::ApplyPendingStaticMap() {
  if (!pending_static_ || (!stages_->queued.empty() && stages_->queued.front().t < pending_static_->second)) return;
  world::WorldUpdate update;
  update.stamp = pending_static_->second;
  update.static_map = pending_static_->first;
  world_.Apply(update);
  if (classifier_) map_features_ = GridMapFeatures(*update.static_map);
  pending_static_.reset();
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
