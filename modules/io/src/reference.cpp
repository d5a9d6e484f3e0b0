#include "specht/io/reference.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "specht/core/error.h"
#include "specht/io/carmen.h"
#include "specht/io/trajectory_io.h"

namespace specht::io {

Trajectory ReadReference(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open reference trajectory");
  if (LooksLikeCarmen(path)) return ReadCarmenReference(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string token;
    int columns = 0;
    while (s >> token) ++columns;
    return columns == 8 ? ReadTum(path) : ReadPose2DText(path);
  }
  throw InputError(path + ": reference trajectory is empty");
}

std::string DefaultReferencePath(const std::string& dataset, const std::string& format) {
  if (format == "carmen") return IsCorrectedCarmenLog(dataset) ? dataset : "";
  if (std::filesystem::exists(dataset + ".GT.txt")) return dataset + ".GT.txt";
  const std::filesystem::path path(dataset);
  const auto simulated = path.parent_path() / "ground_truth.tum";
  if (path.filename() == "sim.rawlog" && std::filesystem::exists(simulated)) return simulated.string();
  return "";
}

}  // namespace specht::io
