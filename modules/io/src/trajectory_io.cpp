#include "specht/io/trajectory_io.h"

#include <mrpt/math/CQuaternion.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "specht/core/error.h"
#include "specht/io/atomic_file.h"

namespace specht::io {
namespace {

// Parses whitespace-separated numbers of each non-comment line; `expect` per line.
// on_line(numbers, line number).
template <class Fn>
void ReadNumberLines(const std::string& path, size_t expect, const char* layout, Fn&& on_line) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open trajectory file");
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    std::vector<double> v;
    std::string token;
    while (fields >> token) {
      char* end = nullptr;
      const double x = std::strtod(token.c_str(), &end);
      if (end == token.c_str() || *end != '\0' || !std::isfinite(x)) {
        throw InputError(Where(path, number) + "'" + token + "' is not a finite number (expected " + layout + ")");
      }
      v.push_back(x);
    }
    if (v.size() != expect) {
      throw InputError(Where(path, number) + "expected " + std::to_string(expect) + " numbers (" + layout + "), got " +
                       std::to_string(v.size()));
    }
    try {
      on_line(v, number);
    } catch (const InputError& e) {  // what the line means is wrong: name the line
      throw InputError(Where(path, number) + e.what());
    }
  }
}

}  // namespace

void WriteTum(const Trajectory& trajectory, const std::string& path) {
  std::string text = "# timestamp tx ty tz qx qy qz qw\n";
  char buf[256];
  for (const auto& p : trajectory) {
    mrpt::math::CQuaternionDouble q;
    p.pose.getAsQuaternion(q);
    // Print the time from its integer nanoseconds so no rounding creeps in.
    const int64_t sec = p.stamp.ns / 1000000000LL, nsec = p.stamp.ns % 1000000000LL;
    std::snprintf(buf, sizeof(buf), "%lld.%09lld %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n", static_cast<long long>(sec),
                  static_cast<long long>(nsec), p.pose.x(), p.pose.y(), p.pose.z(), q.x(), q.y(), q.z(), q.r());
    text += buf;
  }
  WriteTextAtomically(path, text);
}

Trajectory ReadTum(const std::string& path) {
  Trajectory out;
  ReadNumberLines(path, 8, "t x y z qx qy qz qw", [&](const std::vector<double>& v, int) {
    // Normalised here: MRPT's quaternion rejects one that is not of unit length.
    const double norm = std::sqrt(v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]);
    if (!(norm > 1e-9) || !std::isfinite(norm)) throw InputError("the quaternion (qx qy qz qw) has no length");
    const mrpt::math::CQuaternionDouble q(v[7] / norm, v[4] / norm, v[5] / norm, v[6] / norm);
    out.push_back({Stamp::FromSeconds(v[0]), mrpt::poses::CPose3D(q, v[1], v[2], v[3])});
  });
  return out;
}

Trajectory ReadPose2DText(const std::string& path) {
  Trajectory out;
  ReadNumberLines(path, 4, "t x y theta", [&](const std::vector<double>& v, int) {
    out.push_back({Stamp::FromSeconds(v[0]), mrpt::poses::CPose3D(v[1], v[2], 0, v[3], 0, 0)});
  });
  return out;
}

RelationsFile ReadRelations(const std::string& path) {
  RelationsFile out{path, {}};
  ReadNumberLines(path, 8, "t1 t2 x y z roll pitch yaw", [&](const std::vector<double>& v, int line) {
    out.relations.push_back(
        {Stamp::FromSeconds(v[0]), Stamp::FromSeconds(v[1]), mrpt::poses::CPose2D(v[2], v[3], v[7]), line});
  });
  if (out.relations.empty()) throw InputError(path + ": no relations (an empty file, or only comments)");
  return out;
}

std::string DefaultRelationsPath(const std::string& dataset) {
  std::filesystem::path p(dataset);
  if (p.extension() == ".bz2" || p.extension() == ".gz") p = p.parent_path() / p.stem();
  p = p.parent_path() / (p.stem().string() + ".relations");
  return std::filesystem::exists(p) ? p.string() : "";
}

}  // namespace specht::io
