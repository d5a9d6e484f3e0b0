#include "specht/io/g2o.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <fstream>
#include <sstream>

#include "specht/io/atomic_file.h"

namespace specht::io {
namespace {

struct BadRecord : std::runtime_error {
  using std::runtime_error::runtime_error;
};

std::vector<double> Numbers(std::istringstream& in, size_t count, const char* tag) {
  std::vector<double> v;
  std::string token;
  while (v.size() < count && in >> token) {
    char* end = nullptr;
    const double x = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0' || !std::isfinite(x)) {
      throw BadRecord(std::string(tag) + ": '" + token + "' is not a finite number");
    }
    v.push_back(x);
  }
  if (v.size() < count) {
    throw BadRecord(std::string(tag) + " needs " + std::to_string(count) + " numbers, got " + std::to_string(v.size()));
  }
  return v;
}

int Id(double v, const char* tag) {
  if (v != std::floor(v) || v < 0 || v > 2e9) throw BadRecord(std::string(tag) + ": ids must be non-negative integers");
  return static_cast<int>(v);
}

}  // namespace

G2oReadResult ReadG2o(const std::string& path, OnBadRecord on_bad) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open g2o file");
  G2oReadResult r;
  std::vector<std::pair<PoseGraphEdge, int>> edges;  // with their line numbers
  std::string line;
  int number = 0;
  auto bad = [&](int line_no, const std::string& why) {
    if (on_bad == OnBadRecord::kStop) throw DatasetError(path, line_no, -1, why);
    r.skipped.push_back(path + ":" + std::to_string(line_no) + ": " + why);
  };
  while (std::getline(in, line)) {
    ++number;
    std::istringstream s(line);
    std::string tag;
    if (!(s >> tag) || tag[0] == '#') continue;
    try {
      if (tag == "VERTEX_SE2") {
        const auto v = Numbers(s, 4, "VERTEX_SE2");
        r.graph.nodes[Id(v[0], "VERTEX_SE2")] = mrpt::poses::CPose2D(v[1], v[2], v[3]);
        r.had_vertices = true;
      } else if (tag == "EDGE_SE2") {
        const auto v = Numbers(s, 11, "EDGE_SE2");
        PoseGraphEdge e;
        e.from = Id(v[0], "EDGE_SE2");
        e.to = Id(v[1], "EDGE_SE2");
        e.measurement = mrpt::poses::CPose2D(v[2], v[3], v[4]);
        e.information << v[5], v[6], v[7], v[6], v[8], v[9], v[7], v[9], v[10];
        if (Eigen::LLT<Eigen::Matrix3d>(e.information).info() != Eigen::Success) {
          throw BadRecord("EDGE_SE2 " + std::to_string(e.from) + " -> " + std::to_string(e.to) +
                          ": information matrix is not positive definite");
        }
        edges.emplace_back(e, number);
      }
    } catch (const BadRecord& b) {
      bad(number, b.what());
    }
  }
  if (!r.had_vertices) {
    // Edges only: chain the odometry edges (i, i+1) from node 0 at the origin.
    std::map<int, const PoseGraphEdge*> odometry;
    int max_id = -1;
    for (const auto& [e, l] : edges) {
      if (e.to == e.from + 1 && odometry.count(e.from) == 0) odometry[e.from] = &e;
      max_id = std::max({max_id, e.from, e.to});
    }
    if (max_id >= 0) r.graph.nodes[0] = mrpt::poses::CPose2D();
    for (int id = 1; id <= max_id; ++id) {
      auto it = odometry.find(id - 1);
      if (it == odometry.end()) {
        throw DatasetError(path, 0, -1,
                           "edges-only graph has no odometry edge " + std::to_string(id - 1) + " -> " +
                               std::to_string(id) + " to build its initial guess from");
      }
      r.graph.nodes[id] = r.graph.nodes[id - 1] + it->second->measurement;
    }
  }
  for (auto& [e, l] : edges) {
    if (r.graph.nodes.count(e.from) == 0 || r.graph.nodes.count(e.to) == 0) {
      bad(l, "EDGE_SE2 " + std::to_string(e.from) + " -> " + std::to_string(e.to) + " names a missing vertex " +
                 std::to_string(r.graph.nodes.count(e.from) == 0 ? e.from : e.to));
      continue;
    }
    r.graph.edges.push_back(e);
  }
  return r;
}

void WriteG2o(const PoseGraph2D& graph, const std::string& path) {
  std::ostringstream out;
  out.precision(10);
  for (const auto& [id, p] : graph.nodes)
    out << "VERTEX_SE2 " << id << " " << p.x() << " " << p.y() << " " << p.phi() << "\n";
  for (const auto& e : graph.edges) {
    const auto& I = e.information;
    out << "EDGE_SE2 " << e.from << " " << e.to << " " << e.measurement.x() << " " << e.measurement.y() << " "
        << e.measurement.phi() << " " << I(0, 0) << " " << I(0, 1) << " " << I(0, 2) << " " << I(1, 1) << " " << I(1, 2)
        << " " << I(2, 2) << "\n";
  }
  WriteTextAtomically(path, out.str());
}

}  // namespace specht::io
