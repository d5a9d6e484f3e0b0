// Parameter YAML (core/params.h): a file merged into the tree and loaded against
// declared sections (nested structs, ranges, choices, relations between fields), as
// `--params` files are; and the same declarations as a tune file's search space
// (tune/tune_file.h).
#include "fuzz_support.h"
#include "specht/core/params.h"
#include "specht/core/transform_tree.h"
#include "specht/io/replay.h"
#include "specht/plan/car.h"
#include "specht/plan/hybrid_astar.h"
#include "specht/slam/graph_slam.h"
#include "specht/stereo/sgm.h"
#include "specht/tune/tune_file.h"

namespace {

const specht::params::Registry& Sections() {
  static const specht::params::Registry r = [] {
    specht::params::Registry r;
    r.Add<specht::FramesOptions>("frames", "frames");
    r.Add<specht::io::ReplayOptions>("replay", "replay");
    r.Add<specht::slam::SlamOptions>("slam", "slam");
    r.Add<specht::slam::GridOptions>("grid", "grid");
    r.Add<specht::stereo::SgmOptions>("stereo", "stereo");
    r.Add<specht::plan::CarOptions>("car", "car");
    r.Add<specht::plan::HybridAStarOptions>("hybrid_astar", "search");
    return r;
  }();
  return r;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text = specht::fuzz::Text(data, size);
  specht::fuzz::Expect([&] {
    specht::params::ParamTree tree;
    tree.MergeText(text, "input.yaml");
    Sections().Load(tree);
  });
  static const std::vector<specht::params::ParamInfo> declared = Sections().Defaults().Describe();
  const std::string path = specht::fuzz::InputFile(data, size, "tune.yaml");
  specht::fuzz::Expect([&] { specht::tune::LoadTuneFile(path, declared); });
  return 0;
}
