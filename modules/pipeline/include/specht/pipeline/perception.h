// specht/pipeline/perception.h: everything the car perceives, into the world model.
//
// For every stereo frame of a replay (or a drive), in stamp order:
//   our SGM and the CNN detector on its images as soon as it arrives (on a worker
//   thread, one frame at a time, when `pipelined`)
//   → the car's pose at the frame's own stamp (pose_history.h: interpolated between the
//   scans SLAM placed before and after it; a frame waits for the scan after it)
//   → box fusion → obstacles in the map frame
//   → the multi-object tracker (per-class motion models, track/tracker.h)
//   → the online trajectory classifier (online_classifier.h), when a model is set:
//     each confirmed track's latest window with the distance to the static layer's
//     occupied cells; a track's class probabilities are the mean over its windows
//   → one frame's stereo points every octree_period_s into the OctoMap (every
//     octree_decimation-th pixel)
//   → one world-model update holding that frame's obstacles and tracks (and, every
//     snapshot_period_s, the OctoMap: copying it every frame would cost more than
//     building it), so a reader never sees the layers of two different frames.
// The static layer comes from SLAM (SetStaticMap, as the map grows and after loop
// closures). Snapshots of the world model are kept every snapshot_period_s of data
// time; tracks.csv holds every reported track at every frame (io/object_tracks.h).
// With WriteVideosTo, every frame adds to camera.mp4 (the left image, detections
// with class, distance and track id) and birds_eye.mp4 (the world model around the
// car: cost layer, obstacles, tracks with predictions).
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation.h>

#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "specht/core/params.h"
#include "specht/core/trajectory.h"
#include "specht/io/object_tracks.h"
#include "specht/io/video.h"
#include "specht/pipeline/online_classifier.h"
#include "specht/pipeline/stereo_perception.h"
#include "specht/world/world_model.h"

namespace specht::pipeline {

// Section "perception".
struct PerceptionOptions {
  std::string mode = "auto";
  double map_update_s = 2.0;
  double snapshot_period_s = 0.5;
  bool pipelined = true;
  int stereo_downsample = 1;
  bool octree = true;
  int octree_decimation = 8;
  double octree_period_s = 0.5;
  double max_pose_wait_s = 1.0;
  std::string classifier_model;  // a `specht classify train` output directory
  bool classifier_network_only = false;
  int classifier_threads = 1;
  std::string video = "mp4";
  double video_fps = 10;
  double birds_eye_extent_m = 50;
  int birds_eye_px = 600;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Choice("mode", mode, {"auto", "on", "off"},
             "stereo frames through SGM + detector + fusion + tracker into the world model: auto = when the "
             "dataset has stereo and the models load, on = required, off = never");
    v.Param("map_update_s", map_update_s,
            "the world model's static layer is rebuilt from SLAM's keyframes this often (data time) and after "
            "every loop closure",
            Range::Of(0.1, 3600.0).Log());
    v.Param("snapshot_period_s", snapshot_period_s, "a world-model snapshot is kept this often (data time)",
            Range::Of(0.05, 3600.0).Log());
    v.Param("pipelined", pipelined,
            "SGM and the detector on a worker thread as each frame arrives, while SLAM places the scans around it; "
            "OctoMap insertion and video frames on another, while the next frames are tracked (false: all on the "
            "caller's thread)");
    v.Param("stereo_downsample", stereo_downsample,
            "SGM on the images shrunk this many times (and num_disparities alike), its disparity brought back to "
            "the full image: k² fewer pixels, depth resolution k times coarser",
            Range::Of(1, 4));
    v.Param("octree", octree, "stereo points into the world model's OctoMap");
    v.Param("octree_decimation", octree_decimation, "every N-th pixel in each direction enters the OctoMap",
            Range::Of(1, 32));
    v.Param("octree_period_s", octree_period_s,
            "one frame's stereo points enter the OctoMap this often (data time; 0 = every frame): consecutive "
            "frames see nearly the same points",
            Range::Of(0.0, 60.0));
    v.Param("max_pose_wait_s", max_pose_wait_s,
            "a frame waits at most this long (data time) for the scan after it, then takes the latest pose",
            Range::Of(0.0, 60.0));
    v.Param("classifier_model", classifier_model,
            "the trajectory classifier on the tracks: a `specht classify train` output directory (empty = none)");
    v.Param("classifier_network_only", classifier_network_only,
            "the classifier's network alone (default: combined with the forest.yml beside it)");
    v.Param("classifier_threads", classifier_threads,
            "libtorch threads for the classifier: with SGM, the detector and the mapping worker busy, a second "
            "thread only waits",
            Range::Of(1, 64).Fixed());
    v.Choice("video", video, {"mp4", "png", "off"},
             "camera.mp4 (the left image with detections, distances, track ids) and birds_eye.mp4 (the world model "
             "around the car): MP4 (PNG frames where no encoder opens), PNG frames, or none");
    v.Param("video_fps", video_fps, "frames per second the videos play at", Range::Of(1.0, 120.0));
    v.Param("birds_eye_extent_m", birds_eye_extent_m, "the bird's-eye view's width and height around the car",
            Range::Of(5.0, 1000.0).Log());
    v.Param("birds_eye_px", birds_eye_px, "the bird's-eye video's size", Range::Of(100, 2000));
  }
};

struct PerceptionSummary {
  PerceptionStats stereo;  // frames, detections, obstacles; SGM, detector and fusion time
  long track_updates = 0, tracks_confirmed = 0;
  long frames_at_held_pose = 0;  // no later scan came in time: placed at the latest pose
  long windows_classified = 0;
  double track_ms = 0, classify_ms = 0, octree_ms = 0, world_ms = 0, video_ms = 0;
  nlohmann::json ToJson() const;
};

class PerceptionPipeline {
 public:
  // Loads the trajectory classifier (InputError naming the file when it cannot) and
  // nothing else until the first stereo frame; a detector that cannot load (no
  // models in `data_dir`) turns perception off with a warning under mode auto and
  // throws InputError under mode on.
  PerceptionPipeline(const params::Params& params, std::string data_dir);
  ~PerceptionPipeline();
  PerceptionPipeline(const PerceptionPipeline&) = delete;
  PerceptionPipeline& operator=(const PerceptionPipeline&) = delete;

  // Every observation, in stamp order: stereo frames are queued for their pose.
  void Add(Stamp t, const mrpt::obs::CObservation::Ptr& observation);
  // The car's pose (base_link in the map frame) at `t`, e.g. each scan SLAM placed;
  // processes every queued frame it covers.
  void AddPose(Stamp t, const mrpt::poses::CPose3D& map_from_base);
  // The static layer (SLAM's grid) as of `t`, written once the frames before `t` are.
  void SetStaticMap(const mrpt::maps::COccupancyGridMap2D& grid, Stamp t);
  // Whether the static layer should be rebuilt at `t` (map_update_s since the last).
  bool StaticMapDue(Stamp t) const;
  // The frames still queued, at the latest pose; call once after the last observation.
  void Finish();
  // Writes the videos (option `video`) into `dir` from the next frame on.
  void WriteVideosTo(const std::string& dir);
  // Closes the videos; returns the outputs written (file or frame-directory names).
  std::vector<std::string> CloseVideos();

  bool active() const;
  const world::WorldModel& world() const { return world_; }
  PerceptionSummary summary() const;
  // Every reported track at every frame (id "t<track id>", class = the track's
  // detection vote, class probabilities = the classifier's).
  const std::vector<io::ObjectSample>& track_samples() const { return track_samples_; }
  // The snapshots kept, one JSON object each (Snapshot::ToJson).
  const std::vector<nlohmann::json>& snapshots() const { return snapshots_; }
  // Obstacles seen, per class, as map markers.
  const std::map<std::string, Trajectory>& seen() const { return seen_; }

 private:
  struct Stages;
  void ProcessQueued(bool flush);
  void ProcessFrame(const PerceivedFrame& frame, Stamp t, const mrpt::poses::CPose3D& pose);
  void KeepSnapshot();
  void ApplyPendingStaticMap();
  // On the mapping worker when pipelined, else at once.
  void RunMapping(std::function<void()> task);
  bool Start();

  const params::Params& params_;
  PerceptionOptions options_;
  std::string data_dir_;
  world::WorldModel world_;
  std::unique_ptr<Stages> stages_;
  std::unique_ptr<OnlineClassifier> classifier_;
  classify::MapFeatures map_features_;  // of the static layer, for the classifier
  std::vector<io::ObjectSample> track_samples_;
  std::vector<nlohmann::json> snapshots_;
  std::map<std::string, Trajectory> seen_;
  std::optional<Stamp> last_map_, last_snapshot_, last_octree_, first_frame_;
  // SLAM's latest grid, until the frames older than it are processed.
  std::optional<std::pair<std::shared_ptr<const mrpt::maps::COccupancyGridMap2D>, Stamp>> pending_static_;
  std::unique_ptr<io::VideoSink> camera_video_, birds_eye_video_;
};

}  // namespace specht::pipeline
