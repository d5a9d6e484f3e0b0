#include "specht/core/transform_tree.h"

#include <mrpt/core/bits_math.h>

#include <set>

#include "specht/core/error.h"

namespace specht {

mrpt::poses::CPose3D StaticTransform::Pose() const {
  return mrpt::poses::CPose3D(xyz_m[0], xyz_m[1], xyz_m[2], mrpt::DEG2RAD(rpy_deg[2]), mrpt::DEG2RAD(rpy_deg[1]),
                              mrpt::DEG2RAD(rpy_deg[0]));
}

std::vector<std::string> FramesOptions::Relations() const {
  std::vector<std::string> problems;
  std::set<std::string> children;
  for (const auto& t : static_transforms) {
    if (t.child == map_frame || t.child == odom_frame || t.child == base_frame) {
      problems.push_back("static_transforms: '" + t.child +
                         "' is a dynamic frame and cannot be the child of a static transform");
    }
    if (!children.insert(t.child).second) {
      problems.push_back("static_transforms: frame '" + t.child + "' is given two parents");
    }
  }
  return problems;
}

TransformTree::TransformTree(const FramesOptions& options) {
  for (const auto& t : options.static_transforms) SetStatic(t.parent, t.child, t.Pose());
}

void TransformTree::CheckParent(const std::string& parent, const std::string& child) const {
  if (parent == child) throw InputError("transform tree: frame '" + child + "' cannot be its own parent");
  auto it = edges_.find(child);
  if (it != edges_.end() && it->second.parent != parent) {
    throw InputError("transform tree: frame '" + child + "' already has parent '" + it->second.parent +
                     "', cannot also hang from '" + parent + "'");
  }
  // Walking up from the parent must not reach the child (no cycles).
  for (std::string f = parent; edges_.count(f) != 0; f = edges_.at(f).parent) {
    if (edges_.at(f).parent == child) {
      throw InputError("transform tree: '" + parent + "' -> '" + child + "' would close a cycle");
    }
  }
}

void TransformTree::SetStatic(const std::string& parent, const std::string& child, const mrpt::poses::CPose3D& pose) {
  CheckParent(parent, child);
  Edge& e = edges_[child];
  e.parent = parent;
  e.is_static = true;
  e.fixed = pose;
}

void TransformTree::Set(const std::string& parent, const std::string& child, Stamp stamp,
                        const mrpt::poses::CPose3D& pose) {
  CheckParent(parent, child);
  Edge& e = edges_[child];
  e.parent = parent;
  e.is_static = false;
  e.history.insert(ToMrpt(stamp), pose.asTPose());
}

mrpt::poses::CPose3D TransformTree::RootFrom(const std::string& frame, Stamp stamp, bool static_only,
                                             std::string* root) const {
  mrpt::poses::CPose3D root_from_frame;  // identity
  std::string f = frame;
  for (auto it = edges_.find(f); it != edges_.end(); it = edges_.find(f)) {
    const Edge& e = it->second;
    mrpt::poses::CPose3D parent_from_child = e.fixed;
    if (!e.is_static) {
      if (static_only) throw RuntimeError("transform tree: '" + f + "' is a dynamic frame; give a stamp");
      mrpt::math::TPose3D p;
      bool valid = false;
      e.history.interpolate(ToMrpt(stamp), p, valid);
      if (!valid) {
        throw RuntimeError("transform tree: no transform '" + e.parent + "' -> '" + f +
                           "' at t=" + std::to_string(stamp.Seconds()));
      }
      parent_from_child = mrpt::poses::CPose3D(p);
    }
    root_from_frame = parent_from_child + root_from_frame;
    f = e.parent;
  }
  *root = f;
  return root_from_frame;
}

mrpt::poses::CPose3D TransformTree::Lookup(const std::string& target, const std::string& source, Stamp stamp) const {
  for (const auto* f : {&target, &source}) {
    if (!Has(*f)) throw RuntimeError("transform tree: unknown frame '" + *f + "'");
  }
  std::string root_t, root_s;
  const auto root_from_target = RootFrom(target, stamp, false, &root_t);
  const auto root_from_source = RootFrom(source, stamp, false, &root_s);
  if (root_t != root_s) {
    throw RuntimeError("transform tree: frames '" + target + "' and '" + source + "' are not connected");
  }
  return root_from_source - root_from_target;  // inverse(root_from_target) * root_from_source
}

mrpt::poses::CPose3D TransformTree::LookupStatic(const std::string& target, const std::string& source) const {
  for (const auto* f : {&target, &source}) {
    if (!Has(*f)) throw RuntimeError("transform tree: unknown frame '" + *f + "'");
  }
  std::string root_t, root_s;
  const auto root_from_target = RootFrom(target, Stamp{}, true, &root_t);
  const auto root_from_source = RootFrom(source, Stamp{}, true, &root_s);
  if (root_t != root_s) {
    throw RuntimeError("transform tree: frames '" + target + "' and '" + source + "' are not connected");
  }
  return root_from_source - root_from_target;
}

bool TransformTree::Has(const std::string& frame) const {
  if (edges_.count(frame) != 0) return true;
  for (const auto& kv : edges_) {
    if (kv.second.parent == frame) return true;
  }
  return false;
}

std::string TransformTree::ParentOf(const std::string& frame) const {
  auto it = edges_.find(frame);
  return it == edges_.end() ? std::string() : it->second.parent;
}

std::vector<std::string> TransformTree::Frames() const {
  std::set<std::string> all;
  for (const auto& kv : edges_) {
    all.insert(kv.first);
    all.insert(kv.second.parent);
  }
  return {all.begin(), all.end()};
}

namespace params {

bool Codec<std::vector<StaticTransform>>::Decode(const YAML::Node& n, std::vector<StaticTransform>& out,
                                                 std::string* why) {
  if (!n.IsSequence()) {
    *why = "expected a list of {parent, child, xyz_m, rpy_deg}, got " + std::string(n.IsMap() ? "a map" : "a value");
    return false;
  }
  out.clear();
  for (size_t i = 0; i < n.size(); ++i) {
    const YAML::Node& item = n[i];
    const std::string at = "entry " + std::to_string(i) + ": ";
    if (!item.IsMap()) {
      *why = at + "expected a map";
      return false;
    }
    StaticTransform t;
    for (const auto& kv : item) {
      const std::string k = kv.first.Scalar();
      std::string inner;
      bool ok = true;
      if (k == "parent")
        ok = Codec<std::string>::Decode(kv.second, t.parent, &inner);
      else if (k == "child")
        ok = Codec<std::string>::Decode(kv.second, t.child, &inner);
      else if (k == "xyz_m")
        ok = Codec<std::vector<double>>::Decode(kv.second, t.xyz_m, &inner);
      else if (k == "rpy_deg")
        ok = Codec<std::vector<double>>::Decode(kv.second, t.rpy_deg, &inner);
      else {
        *why = at + "unknown field '" + k + "' (parent, child, xyz_m, rpy_deg)";
        return false;
      }
      if (!ok) {
        *why = at + k + ": " + inner;
        return false;
      }
    }
    if (t.parent.empty() || t.child.empty()) {
      *why = at + "needs both 'parent' and 'child'";
      return false;
    }
    if (t.xyz_m.size() != 3 || t.rpy_deg.size() != 3) {
      *why = at + "xyz_m and rpy_deg need exactly 3 numbers each";
      return false;
    }
    out.push_back(std::move(t));
  }
  return true;
}

YAML::Node Codec<std::vector<StaticTransform>>::Encode(const std::vector<StaticTransform>& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (const auto& t : v) {
    YAML::Node item;
    item["parent"] = t.parent;
    item["child"] = t.child;
    item["xyz_m"] = Codec<std::vector<double>>::Encode(t.xyz_m);
    item["rpy_deg"] = Codec<std::vector<double>>::Encode(t.rpy_deg);
    n.push_back(item);
  }
  n.SetStyle(YAML::EmitterStyle::Block);
  return n;
}

}  // namespace params
}  // namespace specht
