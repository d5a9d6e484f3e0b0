#include "specht/core/csv.h"

namespace specht {

void SplitCsv(std::string_view line, std::vector<std::string>& cells) {
  cells.clear();
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  size_t i = 0;
  while (true) {
    std::string cell;
    while (i < line.size() && line[i] == ' ') ++i;
    if (i < line.size() && line[i] == '"') {
      for (++i; i < line.size(); ++i) {
        if (line[i] != '"') {
          cell.push_back(line[i]);
        } else if (i + 1 < line.size() && line[i + 1] == '"') {
          cell.push_back('"');
          ++i;
        } else {
          ++i;
          break;
        }
      }
      while (i < line.size() && line[i] != ',') ++i;  // text after the closing quote
    } else {
      const size_t end = line.find(',', i);
      cell.assign(line.substr(i, end == std::string_view::npos ? std::string_view::npos : end - i));
      i = end == std::string_view::npos ? line.size() : end;
      while (!cell.empty() && cell.back() == ' ') cell.pop_back();
    }
    cells.push_back(std::move(cell));
    if (i >= line.size()) break;
    ++i;  // the comma
    if (i == line.size()) {
      cells.emplace_back();
      break;
    }
  }
}

std::vector<std::string> SplitCsv(std::string_view line) {
  std::vector<std::string> cells;
  SplitCsv(line, cells);
  return cells;
}

}  // namespace specht
