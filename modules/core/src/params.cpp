#include "specht/core/params.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <utility>

namespace specht::params {
namespace {

std::string FormatReal(double v) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%.15g", v);
  std::string s(buf);
  // Keep reals recognisable as reals in YAML ("1" -> "1.0").
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string Describe(const YAML::Node& n) {
  if (n.IsScalar()) return "'" + n.Scalar() + "'";
  if (n.IsSequence()) return "a list";
  if (n.IsMap()) return "a map";
  return "nothing";
}

std::string FormatNumber(double v, bool integer) {
  return integer ? std::to_string(static_cast<long long>(v)) : FormatReal(v);
}

}  // namespace

std::string Range::ToString(bool integer) const {
  const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
  if (!has_min && !has_max) return "";
  std::string s;
  if (has_min && has_max)
    s = "[" + FormatNumber(min, integer) + ", " + FormatNumber(max, integer) + "]";
  else if (has_min)
    s = ">= " + FormatNumber(min, integer);
  else
    s = "<= " + FormatNumber(max, integer);
  if (log_scale) s += " log";
  if (!tunable) s += " fixed";
  return s;
}

std::string CheckRange(double value, const Range& range, bool integer) {
  if (range.Contains(value)) return "";
  return "value " + FormatNumber(value, integer) + " is outside " + range.ToString(integer);
}

std::string JoinKey(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : prefix + "." + key;
}

// --- codecs ------------------------------------------------------------------------

bool Codec<bool>::Decode(const YAML::Node& n, bool& out, std::string* why) {
  if (n.IsScalar()) {
    try {
      out = n.as<bool>();
      return true;
    } catch (const YAML::Exception&) {
    }
  }
  *why = "expected a bool (true/false), got " + Describe(n);
  return false;
}

bool Codec<int>::Decode(const YAML::Node& n, int& out, std::string* why) {
  if (n.IsScalar()) {
    try {
      out = n.as<int>();
      return true;
    } catch (const YAML::Exception&) {
    }
  }
  *why = "expected an integer, got " + Describe(n);
  return false;
}

bool Codec<double>::Decode(const YAML::Node& n, double& out, std::string* why) {
  if (n.IsScalar()) {
    try {
      const double v = n.as<double>();
      if (std::isfinite(v)) {
        out = v;
        return true;
      }
    } catch (const YAML::Exception&) {
    }
  }
  *why = "expected a finite real number, got " + Describe(n);
  return false;
}

YAML::Node Codec<double>::Encode(double v) { return YAML::Node(FormatReal(v)); }

bool Codec<std::string>::Decode(const YAML::Node& n, std::string& out, std::string* why) {
  if (n.IsScalar()) {
    out = n.Scalar();
    return true;
  }
  *why = "expected a string, got " + Describe(n);
  return false;
}

bool Codec<std::vector<double>>::Decode(const YAML::Node& n, std::vector<double>& out, std::string* why) {
  if (!n.IsSequence()) {
    *why = "expected a list of reals, got " + Describe(n);
    return false;
  }
  out.clear();
  for (size_t i = 0; i < n.size(); ++i) {
    double v = 0;
    if (!Codec<double>::Decode(n[i], v, why)) {
      *why = "element " + std::to_string(i) + ": " + *why;
      return false;
    }
    out.push_back(v);
  }
  return true;
}

YAML::Node Codec<std::vector<double>>::Encode(const std::vector<double>& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (double x : v) n.push_back(FormatReal(x));
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

bool Codec<std::vector<std::string>>::Decode(const YAML::Node& n, std::vector<std::string>& out, std::string* why) {
  if (!n.IsSequence()) {
    *why = "expected a list of strings, got " + Describe(n);
    return false;
  }
  out.clear();
  for (size_t i = 0; i < n.size(); ++i) {
    std::string v;
    if (!Codec<std::string>::Decode(n[i], v, why)) {
      *why = "element " + std::to_string(i) + ": " + *why;
      return false;
    }
    out.push_back(v);
  }
  return true;
}

YAML::Node Codec<std::vector<std::string>>::Encode(const std::vector<std::string>& v) {
  YAML::Node n(YAML::NodeType::Sequence);
  for (const auto& x : v) n.push_back(x);
  n.SetStyle(YAML::EmitterStyle::Flow);
  return n;
}

std::vector<std::pair<std::string, std::string>> SplitAssignments(const std::vector<std::string>& entries,
                                                                  const std::string& key,
                                                                  std::vector<std::string>* problems) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& e : entries) {
    const auto eq = e.rfind('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == e.size()) {
      if (problems != nullptr) problems->push_back(key + ": '" + e + "' is not of the form name=value");
      continue;
    }
    out.emplace_back(e.substr(0, eq), e.substr(eq + 1));
  }
  return out;
}

std::vector<std::pair<std::string, double>> ParseNumberAssignments(const std::vector<std::string>& entries,
                                                                   const std::string& key,
                                                                   const std::function<bool(double)>& valid,
                                                                   const std::string& requirement,
                                                                   std::vector<std::string>* problems) {
  std::vector<std::pair<std::string, double>> out;
  for (const auto& [name, text] : SplitAssignments(entries, key, problems)) {
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (*end != '\0' || !valid(value)) {
      if (problems != nullptr) problems->push_back(key + ": '" + text + "' for '" + name + "' is not " + requirement);
      continue;
    }
    out.emplace_back(name, value);
  }
  return out;
}

// --- tree ----------------------------------------------------------------------------

void ParamTree::MergeNode(const YAML::Node& node, const std::string& prefix, const std::string& file) {
  if (node.IsMap()) {
    for (const auto& kv : node) {
      const std::string key = kv.first.Scalar();
      MergeNode(kv.second, JoinKey(prefix, key), file);
    }
    return;
  }
  if (node.IsNull() && !prefix.empty()) return;  // "section:" with nothing under it
  auto [it, inserted] = leaves_.try_emplace(prefix);
  if (inserted) order_.push_back(prefix);
  it->second = Leaf{node, file, node.Mark().line + 1, false};
}

void ParamTree::MergeFile(const std::string& path) {
  std::vector<std::string> stack;
  MergeFileImpl(path, stack);
}

void ParamTree::MergeFileImpl(const std::string& path, std::vector<std::string>& stack) {
  if (std::find(stack.begin(), stack.end(), path) != stack.end()) {
    throw InputError(Where(path) + "include cycle");
  }
  std::ifstream in(path);
  if (!in) {
    throw InputError(Where(path) + "cannot read parameter file: " + std::strerror(errno));
  }
  std::stringstream text;
  text << in.rdbuf();
  YAML::Node root;
  try {
    root = YAML::Load(text.str());
  } catch (const YAML::ParserException& e) {
    throw InputError(Where(path, e.mark.line + 1) + "YAML syntax error: " + e.msg);
  }
  if (root.IsNull()) return;
  if (!root.IsMap()) throw InputError(Where(path, 1) + "a parameter file must be a map of sections");
  stack.push_back(path);
  if (const YAML::Node inc = root["include"]) {
    const auto dir = std::filesystem::path(path).parent_path();
    std::vector<std::string> files;
    if (inc.IsScalar())
      files.push_back(inc.Scalar());
    else if (inc.IsSequence())
      for (const auto& f : inc) files.push_back(f.as<std::string>());
    else
      throw InputError(Where(path, inc.Mark().line + 1) + "'include' must be a file name or a list");
    for (const std::string& f : files) MergeFileImpl((dir / f).lexically_normal().string(), stack);
  }
  stack.pop_back();
  for (const auto& kv : root) {
    if (kv.first.Scalar() == "include") continue;
    MergeNode(kv.second, kv.first.Scalar(), path);
  }
}

void ParamTree::MergeText(const std::string& yaml, const std::string& source_name) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml);
  } catch (const YAML::ParserException& e) {
    throw InputError(Where(source_name, e.mark.line + 1) + "YAML syntax error: " + e.msg);
  }
  if (root.IsNull()) return;
  if (!root.IsMap()) throw InputError(Where(source_name) + "parameters must be a map of sections");
  MergeNode(root, "", source_name);
}

void ParamTree::Set(const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw InputError("--set '" + assignment + "': expected key=value (e.g. grid.resolution=0.1)");
  }
  const std::string key = assignment.substr(0, eq);
  YAML::Node value;
  try {
    value = YAML::Load(assignment.substr(eq + 1));
  } catch (const YAML::ParserException& e) {
    throw InputError("--set '" + assignment + "': value is not valid YAML: " + e.msg);
  }
  auto [it, inserted] = leaves_.try_emplace(key);
  if (inserted) order_.push_back(key);
  it->second = Leaf{value, "--set", 0, false};
}

Leaf* ParamTree::Find(const std::string& key) {
  auto it = leaves_.find(key);
  return it == leaves_.end() ? nullptr : &it->second;
}

std::vector<std::pair<std::string, const Leaf*>> ParamTree::Unused() const {
  std::vector<std::pair<std::string, const Leaf*>> out;
  for (const std::string& key : order_) {
    const Leaf& leaf = leaves_.at(key);
    if (!leaf.used) out.emplace_back(key, &leaf);
  }
  return out;
}

void ParamTree::ResetUsed() {
  for (auto& kv : leaves_) kv.second.used = false;
}

// --- visitors ------------------------------------------------------------------------

std::string Reader::Located(const Leaf* leaf) {
  return leaf != nullptr ? Where(leaf->file, leaf->line) : std::string("(built-in default): ");
}

void Reader::Choice(const char* key, std::string& field, const std::vector<std::string>& choices, const char* doc) {
  const std::string full = JoinKey(prefix_, key);
  Leaf* leaf = tree_.Find(full);
  if (leaf != nullptr) {
    leaf->used = true;
    std::string why;
    std::string value;
    if (!Codec<std::string>::Decode(leaf->value, value, &why)) {
      errors_.push_back(Located(leaf) + "key '" + full + "': " + why);
      return;
    }
    field = value;
  }
  if (std::find(choices.begin(), choices.end(), field) == choices.end()) {
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
    errors_.push_back(Located(leaf) + "key '" + full + "': '" + field + "' is not one of: " + list);
  }
}

void Writer::Emit(const char* key, const YAML::Node& value, const char* doc, const std::string& bounds) {
  out_ << YAML::Key << key << YAML::Value << value;
  if (with_docs_) out_ << YAML::Comment(bounds.empty() ? std::string(doc) : std::string(doc) + " — " + bounds);
}

void Writer::Choice(const char* key, std::string& field, const std::vector<std::string>& choices, const char* doc) {
  std::string list;
  for (const auto& c : choices) list += (list.empty() ? "one of " : "|") + c;
  Emit(key, YAML::Node(field), doc, list);
}

void Describer::Choice(const char* key, std::string& field, const std::vector<std::string>& choices, const char* doc) {
  out_.push_back(ParamInfo{JoinKey(prefix_, key), "choice", doc, std::nullopt, choices, YAML::Node(field)});
}

// --- registry ------------------------------------------------------------------------

// Row by row over a, keeping only the previous row of the table
//   D(i, j) = min(D(i-1, j) + 1, D(i, j-1) + 1, D(i-1, j-1) + [a_i ≠ b_j]).
// D(i, j) ≥ |i − j|, so with a cap only the band |i − j| ≤ cap is computed (cells
// outside it count as cap + 1). A row's minimum never decreases down the table, so
// once it passes `cap` the distance does too. Before any row, two bounds from below:
// |len a − len b|, and half the L1 distance between the strings' letter counts (an
// edit moves at most one letter in and one out).
size_t EditDistance(const std::string& a, const std::string& b, size_t cap) {
  cap = std::min(cap, std::max(a.size(), b.size()));  // no distance is larger
  const size_t n = b.size(), over = cap + 1;
  if ((a.size() > n ? a.size() - n : n - a.size()) > cap) return over;
  if (cap < std::max(a.size(), n)) {
    // Half the letter-count difference bounds the distance from below. Summed over
    // the letters of a and b only (each taken once), not all 256: this runs per
    // candidate key and per unknown key.
    std::array<int, 256> count{};
    for (unsigned char c : a) ++count[c];
    for (unsigned char c : b) --count[c];
    size_t l1 = 0;
    for (const std::string* s : {&a, &b}) {
      for (unsigned char c : *s) l1 += static_cast<size_t>(std::abs(std::exchange(count[c], 0)));
    }
    if ((l1 + 1) / 2 > cap) return over;
  }
  std::vector<size_t> prev(n + 2, over), cur(n + 2, over);
  for (size_t j = 0; j <= std::min(n, cap); ++j) prev[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    const size_t lo = i > cap ? i - cap : 1;
    const size_t hi = cap >= n || i + cap >= n ? n : i + cap;
    cur[lo - 1] = lo == 1 ? std::min(i, over) : over;
    size_t row_min = cur[lo - 1];
    for (size_t j = lo; j <= hi; ++j) {
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1), over});
      row_min = std::min(row_min, cur[j]);
    }
    cur[hi + 1] = over;  // the next row's band reaches one cell further
    if (row_min > cap) return over;
    std::swap(prev, cur);
  }
  return std::min(prev[n], over);
}

std::string NearestKey(const std::string& key, const std::vector<std::string>& candidates, size_t max_distance) {
  std::string best;
  size_t best_distance = max_distance + 1;
  for (const std::string& c : candidates) {
    // Only a strictly nearer candidate can win: count no further than that.
    if (const size_t d = EditDistance(key, c, best_distance - 1); d < best_distance) best_distance = d, best = c;
  }
  return best;
}

std::string NearestKey(const std::string& key, const std::vector<std::string>& candidates) {
  return NearestKey(key, candidates, std::clamp<size_t>(key.size() / 3, 3, 10));
}

namespace {

std::string UnknownKeyMessage(const std::string& key, const Leaf& leaf, const std::vector<std::string>& known) {
  std::string message = Where(leaf.file, leaf.line) + "unknown key '" + key + "'";
  // A declared key below this one means a group was given a value.
  const std::string group = key + ".";
  for (const std::string& k : known) {
    if (k.compare(0, group.size(), group) == 0) {
      return message + ": '" + key + "' is a group of parameters and needs a map";
    }
  }
  if (const std::string nearest = NearestKey(key, known); !nearest.empty()) {
    message += " (did you mean '" + nearest + "'?)";
  }
  return message;
}

}  // namespace

Params Registry::Load(ParamTree& tree) const {
  Params params;
  params.registry_ = this;
  std::vector<std::string> errors;
  tree.ResetUsed();
  for (const Entry& e : entries_) params.values_[e.section] = e.load(tree, errors);
  // As a compiler stops at an error limit: past twenty, more lines (and the search
  // for a near key behind each) help nobody; the count says how many were left out.
  constexpr size_t kReportedUnknownKeys = 20;
  const auto unused = tree.Unused();
  for (size_t i = 0; i < std::min(unused.size(), kReportedUnknownKeys); ++i)
    errors.push_back(UnknownKeyMessage(unused[i].first, *unused[i].second, declared_keys_));
  if (unused.size() > kReportedUnknownKeys)
    errors.push_back("... and " + std::to_string(unused.size() - kReportedUnknownKeys) + " more unknown keys");
  if (!errors.empty()) {
    std::string all;
    for (const auto& e : errors) all += (all.empty() ? "" : "\n") + e;
    throw InputError(all);
  }
  return params;
}

Params Registry::Defaults() const {
  ParamTree empty;
  return Load(empty);
}

std::vector<std::string> Registry::Sections() const {
  std::vector<std::string> out;
  for (const Entry& e : entries_) out.push_back(e.section);
  return out;
}

std::string Params::ToYaml(bool with_docs) const { return ToYaml(registry_->Sections(), with_docs); }

std::string Params::ToYaml(const std::vector<std::string>& sections, bool with_docs) const {
  YAML::Emitter out;
  out << YAML::BeginMap;
  for (const auto& e : registry_->entries_) {
    if (std::find(sections.begin(), sections.end(), e.section) == sections.end()) continue;
    out << YAML::Key << e.section;
    if (with_docs) out << YAML::Comment(e.doc);
    out << YAML::Value << YAML::BeginMap;
    e.emit(out, values_.at(e.section), with_docs);
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

std::vector<ParamInfo> Params::Describe() const {
  std::vector<ParamInfo> out;
  for (const auto& e : registry_->entries_) {
    auto infos = e.describe(values_.at(e.section));
    out.insert(out.end(), infos.begin(), infos.end());
  }
  return out;
}

}  // namespace specht::params
