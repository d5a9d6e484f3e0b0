// specht/tune/space.h: what `specht tune` may vary. Every parameter is declared
// once with its range in its options struct (core/params.h); a tune file picks
// some of them and may narrow a range, set the scale, or list choices:
//
//   parameters:
//     stereo.p1: {}                        # the declared range
//     stereo.p2: {min: 20, max: 190, scale: log}
//     stereo.census_width: {choices: [3, 5, 7, 9]}
//
// A candidate is a point in the unit cube, one gene in [0, 1] per dimension, so the
// searches (search.h) need not know about types; Decode maps genes to values:
//   real     min + g·(max − min)                (log: min·(max/min)^g)
//   integer  round of the same, clamped         (log scale alike)
//   choice   choices[⌊g·n⌋] (bool: false, true)
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "specht/core/params.h"

namespace specht::tune {

struct Dimension {
  enum class Kind { kReal, kInteger, kChoice };
  std::string key;  // full dotted key, e.g. "stereo.p2"
  Kind kind = Kind::kReal;
  double min = 0, max = 1;
  bool log_scale = false;
  std::vector<std::string> choices;  // kChoice
};

class SearchSpace {
 public:
  // From the declared parameters and the tune file's `parameters` node (`source`
  // names the file for errors). Throws InputError, one line per problem: a key not
  // declared (with the nearest declared key), one declared fixed (not tunable), a
  // range outside the declared one, a log scale over a range that is not positive,
  // a choice that is not a valid value.
  static SearchSpace FromTuneFile(const std::vector<params::ParamInfo>& declared, const YAML::Node& parameters,
                                  const std::string& source);
  explicit SearchSpace(std::vector<Dimension> dimensions) : dimensions_(std::move(dimensions)) {}

  size_t size() const { return dimensions_.size(); }
  const std::vector<Dimension>& dimensions() const { return dimensions_; }
  // Genes → one value per dimension, as YAML scalars ("0.25", "7", "census").
  std::vector<std::string> Decode(const std::vector<double>& genes) const;
  // The values as a parameter overlay: nested YAML maps by section.
  std::string OverlayYaml(const std::vector<std::string>& values) const;

 private:
  std::vector<Dimension> dimensions_;
};

}  // namespace specht::tune
