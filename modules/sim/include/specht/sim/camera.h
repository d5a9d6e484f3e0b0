// specht/sim/camera.h: a rectified stereo camera, rendered by rasterising the world.
//
// The world in 3D: the ground plane z = 0, every object outline extruded to its
// height (vertical faces), every agent as an upright photograph (sprites.h) on a
// vertical plane through its centre facing the left camera — or, without sprites, as
// a box of its class's height — and the sky. Faces carry procedural textures in
// surface coordinates (value noise, bricks, stripes, checker; precomputed tiles), so
// both cameras see the same pattern on the same point — what stereo matching needs.
//
// Pinhole model, rectified pair: pixel (u, v) of the left camera looks along
//   r = ((u − c_x) / f, (v − c_y) / f, 1)   (x right, y down, z forward),
// the right camera sits `baseline_m` to the right. A plane n·p = n·c is drawn over
// the screen box of its clipped outline: for each pixel the ray o + t R r meets it at
//   t = n·(c − o) / ((Rᵀn)·r),
// and since r is affine in (u, v), so are the denominator and the surface coordinates'
// numerators — one division a pixel. t is the depth along the optical axis (r_z = 1);
// the nearest t wins (depth buffer); the true disparity is d = f B / t. An agent's
// plane is the same in both cameras, so its disparity is exact too.
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "specht/sim/scenario.h"
#include "specht/sim/sprites.h"
#include "specht/sim/world.h"

namespace specht::sim {

// A moving agent as the camera sees it.
struct Box3 {
  Pose2 pose;
  double length_m = 1, width_m = 1, height_m = 1.7;
  int id = 0;
  std::string cls;     // KITTI class name: Pedestrian, Cyclist, Car
  std::string sprite;  // a sprite by name; "" = chosen by the view (see Render)
};

// The driving class (sprites.h, detect/) of a KITTI class name: "Car" → "car",
// "Cyclist" → "cyclist", "Pedestrian" → "pedestrian".
std::string DrivingClassOf(const std::string& kitti_name);

// One agent in the left image.
struct AgentView {
  int id = 0;
  std::string cls;       // KITTI class name
  std::string sprite;    // the sprite drawn ("" for a box)
  cv::Rect2d box;        // its full extent in the image, clipped to it
  double truncated = 0;  // share of the full extent outside the image
  double visible = 0;    // share of its pixels in the image not hidden by nearer things
  double range_m = 0;    // depth of its centre along the optical axis
};

struct StereoFrame {
  cv::Mat left_bgr, right_bgr;            // CV_8UC3: what the cameras record, what the detector sees
  cv::Mat left, right;                    // CV_8U: the same in grey, what stereo matching takes
  cv::Mat disparity;                      // CV_32F, left camera, 0 where nothing is hit (sky)
  cv::Mat depth;                          // CV_32F metres along the optical axis, 0 for sky
  cv::Mat depth_right;                    // the same for the right camera (for occlusion tests)
  std::vector<AgentView> agents;          // the agents in view (at least 5 % visible)
  std::vector<std::string> kitti_labels;  // the same, one line each (KITTI object format)
};

class StereoRenderer {
 public:
  // With `sprites`, agents are drawn as sprites of spec.sprites' set; without, as boxes.
  StereoRenderer(const Scenario& scenario, const World& world, StereoSpec spec, const SpriteLibrary* sprites = nullptr);
  // An agent without a named sprite shows the sprite of its class whose aspect is
  // nearest the width its box shows the camera over its height (a car side-on gets a
  // side view, from behind a rear view); ties go by the agent's id.
  StereoFrame Render(const Pose2& ego, const std::vector<Box3>& boxes) const;
  const StereoSpec& spec() const { return spec_; }

  struct View;  // one camera's pose and buffers (camera.cpp)

 private:
  const Sprite* SpriteFor(const Box3& box, const cv::Vec3d& camera) const;

  const Scenario& scenario_;
  const World& world_;
  StereoSpec spec_;
  const SpriteLibrary* sprites_;
  SpriteSet set_ = SpriteSet::kAll;
};

}  // namespace specht::sim
