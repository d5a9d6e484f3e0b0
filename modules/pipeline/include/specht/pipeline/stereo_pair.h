// specht/pipeline/stereo_pair.h: one stereo pair through our semi-global matcher
// (or OpenCV's, section "stereo") — what `specht stereo` runs. Writes disparity.png
// (KITTI uint16) and disparity_color.png; guided by sparse hints, LiDAR projected
// through the calibration or a ground-plane prior, also the unguided run beside it
// (comparison.png, hints.png); with a calibration (rectifying an unrectified pair
// first) depth.png (uint16 mm), points.ply (camera frame, or `frame` through the
// static transforms of section "frames") and octomap.bt.
#pragma once

#include <string>
#include <vector>

#include "specht/core/params.h"

namespace specht::pipeline {

struct StereoPairInputs {
  std::string left, right;                           // 8-bit images of the same size
  std::vector<std::string> calib;                    // KITTI, OpenCV YAML, MRPT ini, or two ROS camera_info files
  std::string hints, lidar;                          // sparse disparity PNG, or a KITTI Velodyne scan (needs calib)
  double ground_height_m = 0, ground_pitch_deg = 0;  // dense ground-plane prior when height > 0 (needs calib)
  std::string camera_frame = "stereo_left", frame;   // the left camera's frame; points.ply's frame ("" = camera)
};

// Inputs are read and checked (InputError naming the file and reason) before
// `out_dir` is created.
int RunStereoPair(const params::Params& params, const StereoPairInputs& in, const std::string& out_dir);

}  // namespace specht::pipeline
