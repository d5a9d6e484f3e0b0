// specht/core/params.h: parameters, declared once per options struct.
//
// Every component has one options struct with defaults. It declares its parameters
// in a single `Visit` member template, and that one declaration drives
//   1. loading from YAML (ParamTree + Reader): unknown keys are errors naming the
//      file, line and nearest valid key;
//   2. validation: ranges and choices, then the struct's own relations between
//      fields (an optional `std::vector<std::string> Relations() const`);
//   3. dumping the effective parameters next to every run's outputs (Writer);
//   4. the tuner's search space (Describer: key, type, range, log scale, choices).
//
//   struct IcpOptions {
//     int max_iterations = 80;
//     double max_pair_distance_m = 0.5;
//     template <class V> void Visit(V& v) {
//       v.Param("max_iterations", max_iterations, "ICP iterations per scan", Range::Of(1, 1000));
//       v.Param("max_pair_distance_m", max_pair_distance_m, "...", Range::Of(0.01, 5).Log());
//     }
//   };
//
// Parameter files are YAML maps of sections ("odometry:", "grid:", ...). Keys are
// addressed with dots ("odometry.icp.max_iterations"), as in `--set key=value`.
// A file may start with `include: other.yaml` (or a list): included files are
// merged first, relative to the including file, then the file's own keys.
#pragma once

#include <yaml-cpp/yaml.h>

#include <any>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "specht/core/error.h"

namespace specht::params {

// Bounds of a numeric parameter: checked on load, and the tuner's search space.
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool log_scale = false;  // tuner samples log-uniformly (min > 0)
  bool tunable = false;    // only bounded ranges are tunable

  static Range Of(double min, double max) { return Range{min, max, false, true}; }
  static Range AtLeast(double min) { return Range{min, std::numeric_limits<double>::infinity(), false, false}; }
  Range Log() const {
    Range r = *this;
    r.log_scale = true;
    return r;
  }
  // Validated, but not offered to the tuner (e.g. a sensor's physical constant).
  Range Fixed() const {
    Range r = *this;
    r.tunable = false;
    return r;
  }
  bool Contains(double v) const { return v >= min && v <= max; }
  // "[min, max]" (integers without decimals), "log", "fixed" as they apply.
  std::string ToString(bool integer = false) const;
};

// A description of one declared parameter (for --help, dumps and the tuner).
struct ParamInfo {
  std::string key;   // full dotted key
  std::string type;  // "bool", "int", "real", "string", "choice", ...
  std::string doc;
  std::optional<Range> range;
  std::vector<std::string> choices;  // for "choice"
  YAML::Node default_value;
};

// How a C++ type is read from and written to YAML. Decode returns false and sets
// *why on a wrong type or malformed value.
template <class T, class Enable = void>
struct Codec;

template <>
struct Codec<bool> {
  static const char* Name() { return "bool"; }
  static bool Decode(const YAML::Node& n, bool& out, std::string* why);
  static YAML::Node Encode(bool v) { return YAML::Node(v); }
};
template <>
struct Codec<int> {
  static const char* Name() { return "int"; }
  static bool Decode(const YAML::Node& n, int& out, std::string* why);
  static YAML::Node Encode(int v) { return YAML::Node(v); }
};
template <>
struct Codec<double> {
  static const char* Name() { return "real"; }
  static bool Decode(const YAML::Node& n, double& out, std::string* why);
  static YAML::Node Encode(double v);
};
template <>
struct Codec<std::string> {
  static const char* Name() { return "string"; }
  static bool Decode(const YAML::Node& n, std::string& out, std::string* why);
  static YAML::Node Encode(const std::string& v) { return YAML::Node(v); }
};
template <>
struct Codec<std::vector<double>> {
  static const char* Name() { return "real list"; }
  static bool Decode(const YAML::Node& n, std::vector<double>& out, std::string* why);
  static YAML::Node Encode(const std::vector<double>& v);
};

template <>
struct Codec<std::vector<std::string>> {
  static const char* Name() { return "string list"; }
  static bool Decode(const YAML::Node& n, std::vector<std::string>& out, std::string* why);
  static YAML::Node Encode(const std::vector<std::string>& v);
};

// One value of a merged parameter file, and where it came from.
struct Leaf {
  YAML::Node value;
  std::string file;  // "--set" for command-line overrides
  int line = 0;
  bool used = false;
};

// The merged contents of parameter files and --set overrides, flattened to dotted
// keys. Maps are groups; scalars and sequences are values.
class ParamTree {
 public:
  void MergeFile(const std::string& path);
  void MergeText(const std::string& yaml, const std::string& source_name);
  // "a.b.c=value"; the value is parsed as YAML ("--set grid.resolution=0.1").
  void Set(const std::string& assignment);

  Leaf* Find(const std::string& key);
  // Keys present in the tree but never read, in file order of appearance.
  std::vector<std::pair<std::string, const Leaf*>> Unused() const;
  void ResetUsed();

 private:
  void MergeNode(const YAML::Node& node, const std::string& prefix, const std::string& file);
  void MergeFileImpl(const std::string& path, std::vector<std::string>& stack);

  std::map<std::string, Leaf> leaves_;
  std::vector<std::string> order_;
};

std::string JoinKey(const std::string& prefix, const std::string& key);

// The "name=value" entries of a string-list parameter (class maps, per-class
// settings), split at the last '='. A malformed entry is described in *problems
// (when given, naming `key`) and skipped.
std::vector<std::pair<std::string, std::string>> SplitAssignments(const std::vector<std::string>& entries,
                                                                  const std::string& key,
                                                                  std::vector<std::string>* problems);

// The "name=number" entries (per-class margins, thresholds, noise), in order. An
// entry whose value is not a number or fails `valid` is described in *problems as
// "key: 'value' for 'name' is not <requirement>" and skipped.
std::vector<std::pair<std::string, double>> ParseNumberAssignments(const std::vector<std::string>& entries,
                                                                   const std::string& key,
                                                                   const std::function<bool(double)>& valid,
                                                                   const std::string& requirement,
                                                                   std::vector<std::string>* problems);

// Checks a decoded value against its range; empty string when fine.
std::string CheckRange(double value, const Range& range, bool integer);

// --- visitors over an options struct's Visit(v) declaration -------------------

// Reads fields from the tree, marking keys used; collects one message per problem.
class Reader {
 public:
  Reader(ParamTree& tree, std::string prefix, std::vector<std::string>& errors)
      : tree_(tree), prefix_(std::move(prefix)), errors_(errors) {}

  template <class T>
  void Param(const char* key, T& field, const char* /*doc*/, Range range = {}) {
    const std::string full = JoinKey(prefix_, key);
    Leaf* leaf = tree_.Find(full);
    std::string why;
    if (leaf != nullptr) {
      leaf->used = true;
      T value{};
      if (!Codec<T>::Decode(leaf->value, value, &why)) {
        errors_.push_back(Where(leaf->file, leaf->line) + "key '" + full + "': " + why);
        return;
      }
      field = std::move(value);
    }
    if constexpr (std::is_arithmetic_v<T>) {
      why = CheckRange(static_cast<double>(field), range, std::is_integral_v<T>);
      if (!why.empty()) errors_.push_back(Located(leaf) + "key '" + full + "': " + why);
    }
  }

  void Choice(const char* key, std::string& field, const std::vector<std::string>& choices, const char* doc);

  template <class O>
  void Group(const char* key, O& group) {
    Reader nested(tree_, JoinKey(prefix_, key), errors_);
    group.Visit(nested);
  }

 private:
  static std::string Located(const Leaf* leaf);
  ParamTree& tree_;
  std::string prefix_;
  std::vector<std::string>& errors_;
};

// Writes fields to a YAML emitter, optionally with each parameter's doc as a comment.
class Writer {
 public:
  Writer(YAML::Emitter& out, bool with_docs) : out_(out), with_docs_(with_docs) {}

  template <class T>
  void Param(const char* key, T& field, const char* doc, Range range = {}) {
    Emit(key, Codec<T>::Encode(field), doc, std::is_arithmetic_v<T> ? range.ToString(std::is_integral_v<T>) : "");
  }
  void Choice(const char* key, std::string& field, const std::vector<std::string>& choices, const char* doc);
  template <class O>
  void Group(const char* key, O& group) {
    out_ << YAML::Key << key << YAML::Value << YAML::BeginMap;
    group.Visit(*this);
    out_ << YAML::EndMap;
  }

 private:
  void Emit(const char* key, const YAML::Node& value, const char* doc, const std::string& bounds);
  YAML::Emitter& out_;
  bool with_docs_;
};

// Lists every declared parameter with its type, range and default.
class Describer {
 public:
  Describer(std::string prefix, std::vector<ParamInfo>& out) : prefix_(std::move(prefix)), out_(out) {}

  template <class T>
  void Param(const char* key, T& field, const char* doc, Range range = {}) {
    ParamInfo info{JoinKey(prefix_, key), Codec<T>::Name(), doc, std::nullopt, {}, Codec<T>::Encode(field)};
    if constexpr (std::is_arithmetic_v<T> && !std::is_same_v<T, bool>) info.range = range;
    out_.push_back(std::move(info));
  }
  void Choice(const char* key, std::string& field, const std::vector<std::string>& choices, const char* doc);
  template <class O>
  void Group(const char* key, O& group) {
    Describer nested(JoinKey(prefix_, key), out_);
    group.Visit(nested);
  }

 private:
  std::string prefix_;
  std::vector<ParamInfo>& out_;
};

// Detects an optional `std::vector<std::string> Relations() const` on an options struct.
template <class O, class = void>
struct HasRelations : std::false_type {};
template <class O>
struct HasRelations<O, std::void_t<decltype(std::declval<const O&>().Relations())>> : std::true_type {};

// --- the set of all sections -----------------------------------------------------

class Params;

// Every options struct the program knows, by section name. Loading checks the whole
// tree against it, so a misspelled key in any section is caught, whatever the command.
class Registry {
 public:
  // `defaults`: the section's values where the tree is silent (one options struct
  // can serve two sections with different defaults).
  template <class O>
  void Add(const std::string& section, const std::string& doc, const O& defaults = O{}) {
    Entry e;
    e.section = section;
    e.doc = doc;
    e.load = [section, defaults](ParamTree& tree, std::vector<std::string>& errors) -> std::any {
      O options = defaults;
      Reader reader(tree, section, errors);
      options.Visit(reader);
      if constexpr (HasRelations<O>::value) {
        for (const std::string& problem : options.Relations()) {
          errors.push_back("section '" + section + "': " + problem);
        }
      }
      return options;
    };
    e.emit = [](YAML::Emitter& out, const std::any& value, bool docs) {
      O options = std::any_cast<const O&>(value);
      Writer writer(out, docs);
      options.Visit(writer);
    };
    e.describe = [section](const std::any& value) {
      O options = std::any_cast<const O&>(value);
      std::vector<ParamInfo> infos;
      Describer describer(section, infos);
      options.Visit(describer);
      return infos;
    };
    // A struct's keys do not depend on its values: listed once, for the hints.
    for (ParamInfo& info : e.describe(defaults)) declared_keys_.push_back(std::move(info.key));
    entries_.push_back(std::move(e));
  }

  // Decodes every section (defaults where the tree is silent), validates, rejects
  // unknown keys. Throws InputError with one line per problem.
  Params Load(ParamTree& tree) const;
  // Built-in defaults only.
  Params Defaults() const;
  std::vector<std::string> Sections() const;

 private:
  friend class Params;
  struct Entry {
    std::string section;
    std::string doc;
    std::function<std::any(ParamTree&, std::vector<std::string>&)> load;
    std::function<void(YAML::Emitter&, const std::any&, bool)> emit;
    std::function<std::vector<ParamInfo>(const std::any&)> describe;
  };
  std::vector<Entry> entries_;
  std::vector<std::string> declared_keys_;  // every section's, for "did you mean"
};

// Decoded, validated options of every section.
class Params {
 public:
  template <class O>
  const O& Get(const std::string& section) const {
    auto it = values_.find(section);
    if (it == values_.end()) throw RuntimeError("params: no section '" + section + "' registered");
    return std::any_cast<const O&>(it->second);
  }
  // The effective parameters as a YAML document (with docs and ranges as comments).
  std::string ToYaml(bool with_docs) const;
  // Only the given sections (e.g. for the per-module default files in params/).
  std::string ToYaml(const std::vector<std::string>& sections, bool with_docs) const;
  std::vector<ParamInfo> Describe() const;

 private:
  friend class Registry;
  const Registry* registry_ = nullptr;
  std::map<std::string, std::any> values_;
};

// One options struct as a YAML map and back, for artefacts that must carry the
// options they were made with (a classifier remembers its preprocessing).
// FromYaml starts from the defaults and throws InputError naming `source` on an
// unknown key, a wrong type or a value out of range.
template <class O>
std::string ToYaml(O options) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  Writer writer(out, false);
  options.Visit(writer);
  out << YAML::EndMap;
  return out.c_str();
}
template <class O>
O FromYaml(const std::string& yaml, const std::string& source) {
  ParamTree tree;
  tree.MergeText(yaml, source);
  O options;
  std::vector<std::string> errors;
  Reader reader(tree, "", errors);
  options.Visit(reader);
  for (const auto& [key, leaf] : tree.Unused()) errors.push_back(source + ": unknown key '" + key + "'");
  if (!errors.empty()) throw InputError(errors.front());
  return options;
}

// Edit distance (Levenshtein), for "did you mean" suggestions. Counting stops past
// `cap`: the result is then cap + 1.
size_t EditDistance(const std::string& a, const std::string& b, size_t cap = SIZE_MAX - 1);

// The candidate nearest to `key` by edit distance, for "did you mean" hints; empty when
// none is within `max_distance` edits (by default a third of the key, at least 3).
std::string NearestKey(const std::string& key, const std::vector<std::string>& candidates);
std::string NearestKey(const std::string& key, const std::vector<std::string>& candidates, size_t max_distance);

}  // namespace specht::params
