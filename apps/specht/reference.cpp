#include "reference.h"

#include <fstream>
#include <sstream>

#include "specht/core/error.h"
#include "specht/io/carmen.h"
#include "specht/io/trajectory_io.h"

namespace specht::app {

Trajectory ReadReference(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open reference trajectory");
  if (io::LooksLikeCarmen(path)) return io::ReadCarmenReference(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string token;
    int columns = 0;
    while (s >> token) ++columns;
    return columns == 8 ? io::ReadTum(path) : io::ReadPose2DText(path);
  }
  throw InputError(path + ": reference trajectory is empty");
}

}  // namespace specht::app
