#include "specht/io/object_tracks.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "specht/core/csv.h"
#include "specht/core/error.h"
#include "specht/io/atomic_file.h"

namespace specht::io {

std::vector<ObjectSample> ParseObjectTracks(const std::string& text, const std::string& source) {
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  std::map<std::string, int> column;
  while (column.empty() && std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#' || line == "\r") continue;
    const auto names = SplitCsv(line);
    for (size_t i = 0; i < names.size(); ++i) column[names[i]] = static_cast<int>(i);
    for (const char* required : {"id", "t_s", "x_m", "y_m"})
      if (!column.count(required))
        throw InputError(source + ":" + std::to_string(line_no) + ": header: no column \"" + required +
                         "\" (need id,t_s,x_m,y_m[,class][,truth_class])");
  }
  if (column.empty()) throw InputError(source + ": empty file (need a header id,t_s,x_m,y_m[,class])");
  int width = 0;
  for (const auto& [name, i] : column) width = std::max(width, i + 1);
  const int cls = column.count("class") ? column["class"] : -1;
  const int truth = column.count("truth_class") ? column["truth_class"] : -1;
  const int ignore = column.count("ignore") ? column["ignore"] : -1;
  std::vector<std::pair<std::string, int>> probability;  // (class, column) of each p_<class>
  for (const auto& [name, i] : column)
    if (name.size() > 2 && name.rfind("p_", 0) == 0) probability.push_back({name.substr(2), i});
  std::vector<ObjectSample> out;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#' || line == "\r") continue;
    const auto cells = SplitCsv(line);
    const std::string where = source + ":" + std::to_string(line_no) + ": ";
    if (static_cast<int>(cells.size()) < width)
      throw InputError(where + "row has " + std::to_string(cells.size()) + " columns, the header " +
                       std::to_string(width));
    ObjectSample s;
    s.id = cells[column["id"]];
    if (s.id.empty()) throw InputError(where + "id: empty");
    auto number_at = [&](int index, const std::string& name) {
      const std::string& cell = cells[index];
      char* end = nullptr;
      const double v = std::strtod(cell.c_str(), &end);
      if (cell.empty() || *end != '\0' || !std::isfinite(v))
        throw InputError(where + name + ": \"" + cell + "\" is not a finite number");
      return v;
    };
    auto number = [&](const char* name) { return number_at(column[name], name); };
    s.t_s = number("t_s");
    s.x_m = number("x_m");
    s.y_m = number("y_m");
    if (cls >= 0) s.cls = cells[cls];
    if (truth >= 0) s.truth_cls = cells[truth];
    if (ignore >= 0) {
      if (cells[ignore] != "0" && cells[ignore] != "1")
        throw InputError(where + "ignore: \"" + cells[ignore] + "\" is not 0 or 1");
      s.ignore = cells[ignore] == "1";
    }
    for (const auto& [cls, i] : probability)
      if (!cells[i].empty()) s.class_probabilities[cls] = number_at(i, "p_" + cls);
    out.push_back(std::move(s));
  }
  return out;
}

std::vector<ObjectSample> ReadObjectTracks(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError(path + ": cannot open");
  std::stringstream buffer;
  buffer << f.rdbuf();
  return ParseObjectTracks(buffer.str(), path);
}

void WriteObjectTracks(const std::vector<ObjectSample>& samples, const std::string& path) {
  bool with_truth = false, with_ignore = false;
  std::set<std::string> classes;  // of the p_<class> columns
  for (const auto& s : samples) {
    with_truth |= !s.truth_cls.empty(), with_ignore |= s.ignore;
    for (const auto& [cls, p] : s.class_probabilities) classes.insert(cls);
  }
  std::string text =
      std::string("id,t_s,x_m,y_m,class") + (with_truth ? ",truth_class" : "") + (with_ignore ? ",ignore" : "");
  for (const auto& c : classes) text += ",p_" + c;
  text += "\n";
  char row[160];
  for (const auto& s : samples) {
    std::snprintf(row, sizeof(row), ",%.3f,%.3f,%.3f,", s.t_s, s.x_m, s.y_m);
    text += s.id + row + s.cls + (with_truth ? "," + s.truth_cls : "") + (with_ignore ? (s.ignore ? ",1" : ",0") : "");
    for (const auto& c : classes) {
      const auto p = s.class_probabilities.find(c);
      if (p == s.class_probabilities.end()) {
        text += ",";
        continue;
      }
      std::snprintf(row, sizeof(row), ",%.4f", p->second);
      text += row;
    }
    text += "\n";
  }
  WriteTextAtomically(path, text);
}

}  // namespace specht::io
