// specht/sim/camera.h: a rectified stereo camera rendered by ray casting the world.
//
// The world in 3D: the ground plane z = 0, every object outline extruded to its
// height (vertical faces), every agent as a box of its class's height, and the sky.
// Surfaces carry procedural textures attached to the surface (value noise over
// several octaves, bricks, stripes, checker), Lambert-shaded by a fixed sun, so both
// cameras see the same surface pattern — what stereo matching needs.
//
// Pinhole model, rectified pair: pixel (u, v) of the left camera looks along
//   d_cam = ((u − c_x) / f, (v − c_y) / f, 1)   (x right, y down, z forward),
// the right camera sits `baseline_m` to the right. The true disparity of a left pixel
// seeing a point at depth Z (along the optical axis) is d = f B / Z.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "specht/sim/scenario.h"
#include "specht/sim/world.h"

namespace specht::sim {


// A moving box as the camera sees it.
struct Box3 {
  Pose2 pose;
  double length_m = 1, width_m = 1, height_m = 1.7;
  int id = 0;
  std::string cls;  // KITTI class name: Pedestrian, Cyclist, Car
};

struct StereoFrame {
  cv::Mat left, right;     // CV_8U
  cv::Mat disparity;       // CV_32F, left camera, 0 where nothing is hit (sky)
  cv::Mat depth;           // CV_32F metres along the optical axis, 0 for sky
  cv::Mat depth_right;     // the same for the right camera (for occlusion tests)
  std::vector<std::string> kitti_labels;  // one line per visible box (KITTI object format)
};

class StereoRenderer {
 public:
  StereoRenderer(const Scenario& scenario, const World& world, StereoSpec spec);
  StereoFrame Render(const Pose2& ego, const std::vector<Box3>& boxes) const;
  const StereoSpec& spec() const { return spec_; }

 private:
  struct Hit;
  Hit Cast(const cv::Vec3d& origin, const cv::Vec3d& direction, const std::vector<Box3>& boxes) const;
  cv::Mat RenderView(const cv::Vec3d& origin, const cv::Matx33d& world_from_cam, const std::vector<Box3>& boxes,
                     cv::Mat* depth) const;

  const Scenario& scenario_;
  const World& world_;
  StereoSpec spec_;
};

}  // namespace specht::sim
