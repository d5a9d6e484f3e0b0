// specht/pipeline/simulation.h: a simulated drive recorded as a real run would be —
// what `specht sim` writes into its output directory:
//   sim.rawlog        LiDAR scans, wheel odometry, IMU (MRPT rawlog, observations)
//   ground_truth.tum  the ego's true pose at every scan (TUM)
//   true_map.yaml/.pgm/.gridmap   the true occupancy grid
//   agents.csv        time,id,class,x,y,yaw,vx,vy,speed,yaw_rate at 10 Hz
//   world.png         the true map with the ego's and the agents' paths
// and, when the scenario has a stereo camera:
//   sim_Images/       left_NNNNNN.png, right_NNNNNN.png (the rawlog's stereo
//                     observations refer to them, as MRPT's external images do)
//   stereo/disparity/NNNNNN.png  true disparity, KITTI uint16 (value / 256, 0 = none)
//   stereo/labels/NNNNNN.txt     KITTI object labels of the agents in view
//   stereo/agents.csv            the same per frame with the agent's id, sprite, box
//                                (pixels, x1 y1 exclusive), visible share and range
//   report.json/.md   counts, per-class speed and turn-rate statistics, timing
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace specht::pipeline {

struct SimulationOptions {
  std::string scenario;  // scenario YAML
  std::string out_dir;
  std::optional<uint64_t> seed;      // default: the scenario's
  std::optional<double> duration_s;  // default: the scenario's
  std::string data_dir;              // holds sprites/ ("" = $SPECHT_DATA_DIR)
  // The agents in the camera: auto (photographs when the data has them, else boxes),
  // tuning, held_out, all (photograph sets), none (boxes).
  std::string sprites = "auto";
  bool no_camera = false;  // LiDAR, odometry and IMU only
  bool quiet = false;      // no progress line
};

// Throws InputError (file, key, reason) on a bad scenario, an unknown sprite set or
// sprite, or a missing sprites directory, before anything is written. Returns 0, or
// 128 + the signal when interrupted (the drive so far is written).
int RecordSimulation(const SimulationOptions& options);

}  // namespace specht::pipeline
