// specht/pipeline/stereo_perception.h: the stereo perception stage. For each stereo
// observation: our SGM disparity, the CNN detector on the left image, box depth
// fusion, and the obstacles moved into the map frame:
//   map_from_camera = map_from_base (the car's pose at the observation's stamp) ⊕ cameraPose
// (the observation's mount, optical frame: x right, y down, z forward). Images stored
// outside the rawlog are read from MRPT's images directory (<rawlog>_Images).
#pragma once

#include <mrpt/obs/CObservationStereoImages.h>
#include <mrpt/poses/CPose3D.h>

#include <memory>
#include <string>
#include <vector>

#include "specht/detect/detector.h"
#include "specht/detect/fusion.h"
#include "specht/stereo/calibration.h"
#include "specht/stereo/sgm.h"
#include "specht/types/obstacle.h"

namespace specht::pipeline {

// An obstacle from a fused detection: its camera-frame position moved into the map
// frame (Σ_map = R Σ Rᵀ, horizontal block); range_m is the fused depth Z.
types::Obstacle ToMapObstacle(const detect::Obstacle3D& o, const mrpt::poses::CPose3D& map_from_camera, Stamp stamp,
                              long id);

// The rectified camera of a stereo observation. Throws InputError naming the sensor
// and the stamp when the calibration is missing (no focal length, no baseline) or
// contradicts the image (intrinsics for another size, a principal point outside it).
stereo::RectifiedCamera CameraOf(const mrpt::obs::CObservationStereoImages& obs, const cv::Size& image_size);

struct PerceptionStats {
  long frames = 0, detections = 0, obstacles = 0;
  double stereo_ms = 0, detect_ms = 0, fusion_ms = 0;
};

// What the images of one stereo frame give, before its pose is known.
struct SensedFrame {
  cv::Mat image;      // the left image as stored (BGR or grey)
  cv::Mat disparity;  // CV_32F, left image, 0 = none
  stereo::RectifiedCamera camera;
  std::vector<detect::Detection> detections;  // left image
  double stereo_ms = 0, detect_ms = 0;
};

// What one stereo frame gave.
struct PerceivedFrame {
  std::vector<types::Obstacle> obstacles;     // map frame
  std::vector<detect::Detection> detections;  // left image, with or without depth
  std::vector<int> obstacle_of;               // per detection: its obstacle's index, −1 without depth
  cv::Mat image;                              // the left image as stored (BGR or grey)
  cv::Mat disparity;                          // CV_32F, left image, 0 = none
  stereo::RectifiedCamera camera;
  mrpt::poses::CPose3D map_from_camera;
};

class StereoPerception {
 public:
  // With `downsample` k > 1 the matcher sees both images shrunk k times (area
  // averaging) and searches num_disparities / k; its disparity is brought back to the
  // full image (nearest neighbour, values × k), so fusion and the OctoMap see the
  // camera as it is. Depth Z = f·B/d keeps its scale; its resolution coarsens k times.
  StereoPerception(const stereo::SgmOptions& sgm, const detect::DetectorOptions& detector,
                   const detect::FusionOptions& fusion, const std::string& data_dir, int downsample = 1);
  ~StereoPerception();

  // One stereo observation taken at `map_from_base`: Place(Sense(obs), …).
  PerceivedFrame Process(const mrpt::obs::CObservationStereoImages& obs, const mrpt::poses::CPose3D& map_from_base,
                         Stamp stamp);
  // The heavy half, which needs the images only: SGM and the detector. Calls may come
  // from another thread than Place's, one at a time. Throws InputError on a
  // calibration CameraOf refuses or an image that does not load.
  SensedFrame Sense(const mrpt::obs::CObservationStereoImages& obs);
  // The light half, at the frame's pose: box fusion and the obstacles in the map frame.
  PerceivedFrame Place(SensedFrame sensed, const mrpt::poses::CPose3D& map_from_camera, Stamp stamp);
  const PerceptionStats& stats() const { return stats_; }

 private:
  cv::Mat Disparity(const cv::Mat& left, const cv::Mat& right);
  stereo::SgmOptions sgm_options_;
  detect::Detector detector_;
  detect::FusionOptions fusion_;
  std::unique_ptr<stereo::SemiGlobalMatcher> matcher_;
  int downsample_ = 1;
  PerceptionStats stats_;
  long next_id_ = 0;
};

}  // namespace specht::pipeline
