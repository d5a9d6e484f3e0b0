// specht/core/transform_tree.h: coordinate frames and the transforms between them.
//
// Frames follow REP-103/105: `map` (global, fixed), `odom` (continuous, drifts),
// `base_link` (the car), and one frame per sensor named after its sensor label.
// The tree holds static transforms (sensor mounts, from the parameter file) and
// time-stamped dynamic ones (map->odom from SLAM, odom->base_link from odometry),
// each child with exactly one parent. Lookup composes along the tree:
//
//   T_target_from_source = inverse(T_root_from_target) * T_root_from_source
//
// where T_root_from_x is the product of parent-from-child transforms from the root
// down to x. A pose "of x in frame p" is the same thing as T_p_from_x.
#pragma once

#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DInterpolator.h>

#include <map>
#include <string>
#include <vector>

#include "specht/core/params.h"
#include "specht/core/time.h"

namespace specht {

// A fixed mount: the pose of `child` in `parent`, from the parameter file.
struct StaticTransform {
  std::string parent;
  std::string child;
  std::vector<double> xyz_m{0, 0, 0};
  std::vector<double> rpy_deg{0, 0, 0};  // roll, pitch, yaw (applied yaw, pitch, roll)

  mrpt::poses::CPose3D Pose() const;
};

// Frame names and static transforms (section "frames").
struct FramesOptions {
  std::string map_frame = "map";
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  std::vector<StaticTransform> static_transforms;

  template <class V>
  void Visit(V& v) {
    v.Param("map_frame", map_frame, "global fixed frame (REP-105)");
    v.Param("odom_frame", odom_frame, "continuous odometry frame (REP-105)");
    v.Param("base_frame", base_frame, "the car's body frame (REP-103: x forward, y left, z up)");
    v.Param("static_transforms", static_transforms,
            "sensor mounts: list of {parent, child, xyz_m: [x,y,z], rpy_deg: [r,p,y]}; a child named "
            "after a sensor label overrides the mount recorded in the dataset");
  }
  std::vector<std::string> Relations() const;
};

class TransformTree {
 public:
  TransformTree() = default;
  explicit TransformTree(const FramesOptions& options);

  // Adds or replaces a fixed transform: the pose of `child` in `parent`.
  void SetStatic(const std::string& parent, const std::string& child, const mrpt::poses::CPose3D& pose);
  // Adds a time-stamped pose of `child` in `parent` (history kept for interpolation).
  void Set(const std::string& parent, const std::string& child, Stamp stamp, const mrpt::poses::CPose3D& pose);

  // The pose of frame `source` in frame `target` at `stamp` (dynamic edges are
  // interpolated; a stamp outside an edge's history throws RuntimeError).
  mrpt::poses::CPose3D Lookup(const std::string& target, const std::string& source, Stamp stamp) const;
  // The same for trees with static edges only.
  mrpt::poses::CPose3D LookupStatic(const std::string& target, const std::string& source) const;

  bool Has(const std::string& frame) const;
  std::string ParentOf(const std::string& frame) const;
  std::vector<std::string> Frames() const;

 private:
  struct Edge {
    std::string parent;
    bool is_static = true;
    mrpt::poses::CPose3D fixed;
    mrpt::poses::CPose3DInterpolator history;
  };
  void CheckParent(const std::string& parent, const std::string& child) const;
  mrpt::poses::CPose3D RootFrom(const std::string& frame, Stamp stamp, bool static_only, std::string* root) const;

  std::map<std::string, Edge> edges_;  // by child frame
};

namespace params {
template <>
struct Codec<std::vector<StaticTransform>> {
  static const char* Name() { return "transform list"; }
  static bool Decode(const YAML::Node& n, std::vector<StaticTransform>& out, std::string* why);
  static YAML::Node Encode(const std::vector<StaticTransform>& v);
};
}  // namespace params

}  // namespace specht
