// MRPT's graphslam-engine on a rawlog, writing a trajectory with one pose per scan
// (TUM), so that `specht eval slam` can score it against a reference like specht's own.
//
// The `graphslam-engine` app writes only its graph, whose nodes carry no time stamps
// (a node every 0.3 m / 8°), so its output cannot be paired with a reference. This
// driver runs the same engine class (mrpt::graphslam::CGraphSlamEngine, headless) with
// the app's default deciders (CICPCriteriaNRD, CICPCriteriaERD, CLevMarqGSO) and the
// same .ini, feeding the rawlog entry by entry as the app does. After every scan it
// notes the newest node and the engine's current pose seen from it; at the end each
// scan's pose is that node's final (optimised) pose composed with the offset:
//   pose(scan) = node_final ⊕ (current_estimate ⊖ node_then)
// which is how specht places scans between its keyframes.
//
// Usage: mrpt_graphslam <config.ini> <in.rawlog> <out.tum>
// CLevMarqGSO_impl.h uses CSphere without including it, so it comes first.
// clang-format off
#include <mrpt/opengl/CSphere.h>
// clang-format on

#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/graphslam/CGraphSlamEngine.h>
#include <mrpt/graphslam/ERD/CICPCriteriaERD.h>
#include <mrpt/graphslam/GSO/CLevMarqGSO.h>
#include <mrpt/graphslam/NRD/CICPCriteriaNRD.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/datetime.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace {

using Graph = mrpt::graphs::CNetworkOfPoses2DInf;
using mrpt::poses::CPose2D;

struct ScanRecord {
  double stamp = 0;
  mrpt::graphs::TNodeID node = 0;
  CPose2D offset;  // the engine's pose estimate seen from `node` at the time
};

// The 2D scan among this step's observations, if any.
mrpt::obs::CObservation2DRangeScan::Ptr ScanOf(const mrpt::obs::CSensoryFrame::Ptr& frame,
                                               const mrpt::obs::CObservation::Ptr& observation) {
  if (frame) return frame->getObservationByClass<mrpt::obs::CObservation2DRangeScan>();
  return std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(observation);
}

}  // namespace

int Run(const std::string& ini, const std::string& rawlog, const std::string& out);

int main(int argc, char** argv) {
  if (argc != 4) {
    std::cerr << "usage: mrpt_graphslam <config.ini> <in.rawlog> <out.tum>\n";
    return 2;
  }
  for (const char* path : {argv[1], argv[2]}) {
    if (!std::ifstream(path)) {
      std::cerr << "mrpt_graphslam: " << path << ": cannot be read\n";
      return 2;
    }
  }
  try {
    return Run(argv[1], argv[2], argv[3]);
  } catch (const std::exception& e) {
    // MRPT's messages carry a stack trace: its first line says what went wrong.
    const std::string what = e.what();
    std::cerr << "mrpt_graphslam: " << argv[2] << " with " << argv[1] << ": " << what.substr(0, what.find('\n'))
              << "\n";
    return 1;
  }
}

int Run(const std::string& ini, const std::string& rawlog, const std::string& out) {
  mrpt::graphslam::deciders::CICPCriteriaNRD<Graph> node_decider;
  mrpt::graphslam::deciders::CICPCriteriaERD<Graph> edge_decider;
  mrpt::graphslam::optimizers::CLevMarqGSO<Graph> optimizer;
  mrpt::graphslam::CGraphSlamEngine<Graph> engine(ini, rawlog, "", nullptr, &node_decider, &edge_decider, &optimizer);

  mrpt::io::CFileGZInputStream file(rawlog);
  auto archive = mrpt::serialization::archiveFrom(file);
  mrpt::obs::CActionCollection::Ptr action;
  mrpt::obs::CSensoryFrame::Ptr frame;
  mrpt::obs::CObservation::Ptr observation;
  size_t entry = 0;
  std::vector<ScanRecord> scans;
  while (mrpt::obs::CRawlog::getActionObservationPairOrObservation(archive, action, frame, observation, entry)) {
    engine._execGraphSlamStep(action, frame, observation, entry);
    const auto scan = ScanOf(frame, observation);
    const Graph& graph = engine.getGraph();
    if (!scan || graph.nodes.empty()) continue;
    const auto& [node, node_pose] = *graph.nodes.rbegin();
    scans.push_back({mrpt::Clock::toDouble(scan->timestamp), node, engine.getCurrentRobotPosEstimation() - node_pose});
  }

  if (scans.empty()) {  // MRPT reports a parse error on stderr and ends the read
    std::cerr << "mrpt_graphslam: " << rawlog << ": no 2D laser scan read (unreadable, empty or without scans)\n";
    return 1;
  }
  const Graph& graph = engine.getGraph();
  FILE* f = std::fopen(out.c_str(), "w");
  if (f == nullptr) {
    std::cerr << "mrpt_graphslam: cannot write " << out << "\n";
    return 1;
  }
  std::fprintf(f, "# timestamp tx ty tz qx qy qz qw  (MRPT CGraphSlamEngine, %zu nodes)\n", graph.nodes.size());
  for (const ScanRecord& s : scans) {
    const CPose2D pose = graph.nodes.at(s.node) + s.offset;
    std::fprintf(f, "%.6f %.6f %.6f 0 0 0 %.9f %.9f\n", s.stamp, pose.x(), pose.y(), std::sin(pose.phi() / 2),
                 std::cos(pose.phi() / 2));
  }
  std::fclose(f);
  std::cerr << "mrpt_graphslam: " << scans.size() << " scans, " << graph.nodes.size() << " nodes, "
            << graph.edges.size() << " edges -> " << out << "\n";
  return 0;
}
