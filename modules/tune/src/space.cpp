#include "specht/tune/space.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>

#include "specht/core/error.h"

namespace specht::tune {
namespace {

std::string Number(double v, bool integer) {
  if (integer) return std::to_string(std::llround(v));
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

std::string NearestKey(const std::vector<params::ParamInfo>& declared, const std::string& key) {
  std::vector<std::string> keys;
  for (const auto& p : declared) keys.push_back(p.key);
  const std::string nearest = params::NearestKey(key, keys, 4);
  return nearest.empty() ? "" : " (did you mean '" + nearest + "'?)";
}

// One entry of `parameters`; appends problems instead of throwing so the user sees all.
void AddDimension(const params::ParamInfo& info, const YAML::Node& spec, const std::string& where,
                  std::vector<Dimension>& out, std::vector<std::string>& problems) {
  Dimension d;
  d.key = info.key;
  if (spec && !spec.IsNull() && !spec.IsMap()) {
    problems.push_back(where + ": expected a map ({}, {min, max, scale} or {choices})");
    return;
  }
  for (const auto& kv : spec) {
    const std::string k = kv.first.as<std::string>();
    if (k != "min" && k != "max" && k != "scale" && k != "choices")
      problems.push_back(where + ": unknown field '" + k + "' (min, max, scale, choices)");
  }
  const bool has_choices = spec && spec["choices"];
  if (info.type == "bool" || info.type == "choice" || has_choices) {
    d.kind = Dimension::Kind::kChoice;
    const std::vector<std::string> allowed =
        info.type == "bool" ? std::vector<std::string>{"false", "true"} : info.choices;
    d.choices = has_choices ? spec["choices"].as<std::vector<std::string>>() : allowed;
    if (d.choices.empty()) problems.push_back(where + ": no choices (a " + info.type + " needs a choices list)");
    for (const auto& c : d.choices) {
      if (!allowed.empty()) {
        if (std::find(allowed.begin(), allowed.end(), c) == allowed.end())
          problems.push_back(where + ": choice '" + c + "' is not a valid value");
      } else if (info.range) {
        char* end = nullptr;
        const double v = std::strtod(c.c_str(), &end);
        if (end == c.c_str() || *end != '\0')
          problems.push_back(where + ": choice '" + c + "' is not a number");
        else if (!info.range->Contains(v))
          problems.push_back(where + ": choice " + c + " is outside the declared range " + info.range->ToString());
      }
    }
    out.push_back(std::move(d));
    return;
  }
  if ((info.type != "int" && info.type != "real") || !info.range) {
    problems.push_back(where + ": a " + info.type + " parameter can only be tuned with a choices list");
    return;
  }
  const params::Range& r = *info.range;
  d.kind = info.type == "int" ? Dimension::Kind::kInteger : Dimension::Kind::kReal;
  d.min = spec && spec["min"] ? spec["min"].as<double>() : r.min;
  d.max = spec && spec["max"] ? spec["max"].as<double>() : r.max;
  d.log_scale = spec && spec["scale"] ? spec["scale"].as<std::string>() == "log" : r.log_scale;
  if (spec && spec["scale"] && spec["scale"].as<std::string>() != "log" && spec["scale"].as<std::string>() != "linear")
    problems.push_back(where + ": scale must be linear or log");
  if (!std::isfinite(d.min) || !std::isfinite(d.max))
    problems.push_back(where + ": the declared range " + r.ToString() + " is open; give min and max");
  else if (d.min < r.min || d.max > r.max)
    problems.push_back(where + ": range [" + Number(d.min, false) + ", " + Number(d.max, false) +
                       "] is outside the declared range " + r.ToString(info.type == "int"));
  else if (d.min >= d.max)
    problems.push_back(where + ": min must be below max");
  else if (d.log_scale && d.min <= 0)
    problems.push_back(where + ": a log scale needs a positive range");
  out.push_back(std::move(d));
}

}  // namespace

SearchSpace SearchSpace::FromTuneFile(const std::vector<params::ParamInfo>& declared, const YAML::Node& parameters,
                                      const std::string& source) {
  if (!parameters || !parameters.IsMap() || parameters.size() == 0)
    throw InputError(source + ": 'parameters' must map at least one parameter key to its search range");
  std::vector<Dimension> dims;
  std::vector<std::string> problems;
  for (const auto& kv : parameters) {
    const std::string line = source + ":" + std::to_string(kv.first.Mark().line + 1);
    if (!kv.first.IsScalar()) {  // YAML allows a map or a list as a key
      problems.push_back(line + ": a parameter key must be a name such as stereo.p2, not a map or a list");
      continue;
    }
    const std::string key = kv.first.Scalar();
    const std::string where = line + ": parameter '" + key + "'";
    const auto it = std::find_if(declared.begin(), declared.end(), [&](const auto& p) { return p.key == key; });
    if (it == declared.end()) {
      problems.push_back(where + ": not a declared parameter" + NearestKey(declared, key));
      continue;
    }
    if (it->range && !it->range->tunable) {
      problems.push_back(where + ": declared fixed (not tunable)");
      continue;
    }
    try {
      AddDimension(*it, kv.second, where, dims, problems);
    } catch (const YAML::Exception& e) {
      problems.push_back(where + ": " + e.msg);
    }
  }
  if (!problems.empty()) {
    std::string all;
    for (const auto& p : problems) all += (all.empty() ? "" : "\n") + p;
    throw InputError(all);
  }
  return SearchSpace(std::move(dims));
}

std::vector<std::string> SearchSpace::Decode(const std::vector<double>& genes) const {
  std::vector<std::string> values;
  for (size_t i = 0; i < dimensions_.size(); ++i) {
    const Dimension& d = dimensions_[i];
    const double g = std::clamp(genes.at(i), 0.0, 1.0);
    if (d.kind == Dimension::Kind::kChoice) {
      const size_t n = d.choices.size();
      values.push_back(d.choices[std::min(n - 1, static_cast<size_t>(g * n))]);
      continue;
    }
    double v = d.log_scale ? d.min * std::pow(d.max / d.min, g) : d.min + g * (d.max - d.min);
    if (d.kind == Dimension::Kind::kInteger) v = std::clamp(std::round(v), std::ceil(d.min), std::floor(d.max));
    values.push_back(Number(v, d.kind == Dimension::Kind::kInteger));
  }
  return values;
}

namespace {

// node[parts[i]][parts[i+1]]… = value, creating the maps on the way.
void SetPath(YAML::Node node, const std::vector<std::string>& parts, size_t i, const YAML::Node& value) {
  if (i + 1 == parts.size()) {
    node[parts[i]] = value;
    return;
  }
  if (!node[parts[i]]) node[parts[i]] = YAML::Node(YAML::NodeType::Map);
  SetPath(node[parts[i]], parts, i + 1, value);
}

}  // namespace

std::string SearchSpace::OverlayYaml(const std::vector<std::string>& values) const {
  YAML::Node root(YAML::NodeType::Map);
  for (size_t i = 0; i < dimensions_.size(); ++i) {
    std::vector<std::string> parts;
    std::stringstream key(dimensions_[i].key);
    for (std::string part; std::getline(key, part, '.');) parts.push_back(part);
    SetPath(root, parts, 0, YAML::Load(values.at(i)));
  }
  YAML::Emitter out;
  out << root;
  return std::string(out.c_str()) + "\n";
}

}  // namespace specht::tune
