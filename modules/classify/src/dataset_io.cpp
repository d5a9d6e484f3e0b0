#include "specht/classify/dataset_io.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include "specht/classify/baseline.h"
#include "specht/core/error.h"
#include "specht/io/atomic_file.h"

namespace specht::classify {

void WriteNpy(const std::string& path, const std::vector<float>& data, const std::vector<size_t>& shape) {
  std::string dims;
  for (size_t d : shape) dims += std::to_string(d) + ", ";
  if (shape.size() > 1) dims.resize(dims.size() - 2);
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (" + dims + "), }";
  // Magic (6) + version (2) + length (2) + header, padded with spaces to a multiple of 64, ending in '\n'.
  while ((10 + header.size() + 1) % 64) header += ' ';
  header += '\n';
  std::string bytes = "\x93NUMPY";
  bytes += '\x01', bytes += '\x00';
  bytes += static_cast<char>(header.size() & 0xff), bytes += static_cast<char>(header.size() >> 8);
  bytes += header;
  bytes.append(reinterpret_cast<const char*>(data.data()), data.size() * sizeof(float));
  io::WriteTextAtomically(path, bytes);
}

std::vector<float> ReadNpy(const std::string& path, std::vector<size_t>& shape) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path + ": cannot open");
  std::stringstream buffer;
  buffer << f.rdbuf();
  const std::string s = buffer.str();
  if (s.size() < 10 || s.compare(0, 6, "\x93NUMPY") != 0) throw InputError(path + ": not a .npy file");
  const size_t hlen = static_cast<unsigned char>(s[8]) | (static_cast<unsigned char>(s[9]) << 8);
  if (s[6] != 1 || 10 + hlen > s.size()) throw InputError(path + ": unsupported or truncated .npy header");
  const std::string header = s.substr(10, hlen);
  if (header.find("'descr': '<f4'") == std::string::npos) throw InputError(path + ": dtype is not float32 ('<f4')");
  if (header.find("'fortran_order': False") == std::string::npos) throw InputError(path + ": Fortran order");
  const size_t open = header.find('('), close = header.find(')');
  if (open == std::string::npos || close == std::string::npos) throw InputError(path + ": no shape in the header");
  shape.clear();
  size_t count = 1;
  std::stringstream dims(header.substr(open + 1, close - open - 1));
  std::string item;
  while (std::getline(dims, item, ',')) {
    if (item.find_first_not_of(' ') == std::string::npos) continue;
    char* end = nullptr;
    const unsigned long long v = std::strtoull(item.c_str(), &end, 10);
    if (end == item.c_str()) throw InputError(path + ": bad shape entry \"" + item + "\"");
    shape.push_back(v);
    if (v && count > (1ULL << 40) / v) throw InputError(path + ": shape too large");
    count *= v;
  }
  if (s.size() - 10 - hlen != count * sizeof(float))
    throw InputError(path + ": " + std::to_string(s.size() - 10 - hlen) + " data bytes, the shape needs " +
                     std::to_string(count * sizeof(float)));
  std::vector<float> out(count);
  if (count) std::memcpy(out.data(), s.data() + 10 + hlen, count * sizeof(float));
  return out;
}

bool HasSpans(const PreparedDataset& d) {
  return d.t0_s.size() == d.windows.size() && d.t1_s.size() == d.windows.size() &&
         std::none_of(d.t0_s.begin(), d.t0_s.end(), [](double t) { return std::isnan(t); });
}

void WritePrepared(const PreparedDataset& d, const std::string& dir) {
  const auto& w = d.windows;
  WriteNpy(dir + "/windows.npy", w.x, {w.size(), static_cast<size_t>(w.features), static_cast<size_t>(w.length)});
  WriteNpy(dir + "/handcrafted.npy", d.handcrafted, {w.size(), static_cast<size_t>(HandcraftedFeatureCount())});
  const bool spans = HasSpans(d);
  std::string csv = spans ? "index,object_id,label,t0_s,t1_s\n" : "index,object_id,label\n";
  char span[64] = "\n";
  for (size_t i = 0; i < w.size(); ++i) {
    if (spans) std::snprintf(span, sizeof(span), ",%.3f,%.3f\n", d.t0_s[i], d.t1_s[i]);
    csv += std::to_string(i) + "," + w.object_ids[i] + "," + d.labels[i] + span;
  }
  io::WriteTextAtomically(dir + "/windows.csv", csv);
  nlohmann::json info = d.info;
  info["classes"] = d.classes;
  io::WriteTextAtomically(dir + "/dataset.json", info.dump(2) + "\n");
}

namespace {

// windows.csv: index,object_id,label[,t0_s,t1_s] (the spans since 2026-11-29).
void ReadWindowsCsv(const std::string& path, PreparedDataset& d) {
  std::ifstream csv(path);
  if (!csv) throw InputError(path + ": cannot open");
  std::string line;
  std::getline(csv, line);
  const bool spans = line.rfind("index,object_id,label,t0_s,t1_s", 0) == 0;
  if (!spans && line.rfind("index,object_id,label", 0) != 0)
    throw InputError(path + ":1: the header must be index,object_id,label[,t0_s,t1_s]");
  int line_no = 1;
  while (std::getline(csv, line)) {
    ++line_no;
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    const size_t columns = spans ? 5 : 3;
    if (cells.size() != columns)
      throw InputError(path + ":" + std::to_string(line_no) + ": " + std::to_string(cells.size()) + " fields, need " +
                       (spans ? "index,object_id,label,t0_s,t1_s" : "index,object_id,label"));
    d.windows.object_ids.push_back(cells[1]);
    d.labels.push_back(cells[2]);
    const auto it = std::find(d.classes.begin(), d.classes.end(), d.labels.back());
    d.windows.y.push_back(it == d.classes.end() ? -1 : static_cast<int>(it - d.classes.begin()));
    double t0 = std::nan(""), t1 = std::nan("");
    if (spans) {
      char *end0 = nullptr, *end1 = nullptr;
      t0 = std::strtod(cells[3].c_str(), &end0), t1 = std::strtod(cells[4].c_str(), &end1);
      if (cells[3].empty() || *end0 || cells[4].empty() || *end1 || !(t0 <= t1))
        throw InputError(path + ":" + std::to_string(line_no) + ": t0_s, t1_s must be two times with t0_s <= t1_s");
    }
    d.t0_s.push_back(t0), d.t1_s.push_back(t1);
  }
}

}  // namespace

void PreparedDataset::AddWindow(const Window& w, int y) {
  windows.y.push_back(y);
  windows.object_ids.push_back(w.object_id);
  labels.push_back(w.label);
  t0_s.push_back(w.points.empty() ? w.t0_s : w.points.front().t_s);
  t1_s.push_back(w.points.empty() ? w.t0_s : w.points.back().t_s);
}

PreparedDataset ReadPrepared(const std::string& dir) {
  PreparedDataset d;
  std::ifstream f(dir + "/dataset.json");
  if (!f) throw InputError(dir + "/dataset.json: cannot open (run `specht classify prepare` first)");
  try {
    f >> d.info;
    d.classes = d.info.at("classes").get<std::vector<std::string>>();
  } catch (const std::exception& e) {
    throw InputError(dir + "/dataset.json: " + e.what());
  }
  std::vector<size_t> shape;
  d.windows.x = ReadNpy(dir + "/windows.npy", shape);
  if (shape.size() != 3) throw InputError(dir + "/windows.npy: expected windows × features × length");
  d.windows.features = static_cast<int>(shape[1]), d.windows.length = static_cast<int>(shape[2]);
  const size_t windows = shape[0];
  d.handcrafted = ReadNpy(dir + "/handcrafted.npy", shape);
  if (shape.size() != 2 || shape[0] != windows || shape[1] != static_cast<size_t>(HandcraftedFeatureCount()))
    throw InputError(dir + "/handcrafted.npy: expected " + std::to_string(windows) + " windows × " +
                     std::to_string(HandcraftedFeatureCount()) +
                     " features, as windows.npy (a dataset of an older version: prepare it again)");
  ReadWindowsCsv(dir + "/windows.csv", d);
  if (d.windows.size() * d.windows.features * d.windows.length != d.windows.x.size())
    throw InputError(dir + ": windows.csv has " + std::to_string(d.windows.size()) +
                     " rows, windows.npy another count");
  return d;
}

namespace {

PreparedDataset SubsetOf(const PreparedDataset& d, const std::vector<size_t>& rows) {
  PreparedDataset out;
  out.windows = d.windows.Subset(rows);
  out.handcrafted = HandcraftedRows(d, rows);
  for (size_t r : rows) out.labels.push_back(d.labels[r]);
  if (HasSpans(d))
    for (size_t r : rows) out.t0_s.push_back(d.t0_s[r]), out.t1_s.push_back(d.t1_s[r]);
  out.classes = d.classes;
  out.info = d.info;
  return out;
}

}  // namespace

PreparedDataset SplitOffUnlabelled(PreparedDataset& d) {
  std::vector<size_t> labelled, unlabelled;
  for (size_t i = 0; i < d.windows.size(); ++i) (d.windows.y[i] < 0 ? unlabelled : labelled).push_back(i);
  PreparedDataset rest = SubsetOf(d, unlabelled);
  if (!unlabelled.empty()) d = SubsetOf(d, labelled);
  return rest;
}

Dataset PseudoLabelled(const std::vector<float>& p, const PreparedDataset& unlabelled, double votes, int k,
                       std::vector<long>& per_class) {
  if (p.size() != unlabelled.windows.size() * static_cast<size_t>(k))
    throw InputError("pseudo-labels: the teacher's probabilities are not one row of " + std::to_string(k) +
                     " classes per unlabelled window");
  std::vector<size_t> kept;
  std::vector<int> classes;
  per_class.assign(static_cast<size_t>(k), 0);
  for (size_t i = 0; i < unlabelled.windows.size(); ++i) {
    const auto first = p.begin() + static_cast<long>(i * k);
    const auto best = std::max_element(first, first + k);
    if (*best + 1e-6 < votes) continue;  // vote fractions are n / trees in float: 120 / 200 may fall short of 0.6
    kept.push_back(i);
    classes.push_back(static_cast<int>(best - first));
    ++per_class[static_cast<size_t>(classes.back())];
  }
  Dataset out = unlabelled.windows.Subset(kept);
  out.y = classes;
  out.teacher.clear();
  const size_t kc = static_cast<size_t>(k);
  for (size_t i : kept) out.teacher.insert(out.teacher.end(), p.begin() + i * kc, p.begin() + (i + 1) * kc);
  return out;
}

std::vector<float> HandcraftedRows(const PreparedDataset& d, const std::vector<size_t>& rows) {
  const size_t width = static_cast<size_t>(HandcraftedFeatureCount());
  std::vector<float> out;
  out.reserve(rows.size() * width);
  for (size_t r : rows)
    out.insert(out.end(), d.handcrafted.begin() + r * width, d.handcrafted.begin() + (r + 1) * width);
  return out;
}

}  // namespace specht::classify
