#include "specht/pipeline/map_artefact.h"

#include <mrpt/obs/CObservation2DRangeScan.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "specht/core/error.h"
#include "specht/io/atomic_file.h"
#include "specht/io/dataset.h"
#include "specht/io/g2o.h"
#include "specht/io/map_io.h"
#include "specht/io/rawlog_writer.h"
#include "specht/slam/localizer.h"

namespace specht::pipeline {

void WriteMapArtefact(const MapArtefact& map, const std::string& dir) {
  io::WriteRosMap(map.grid, dir + "/map.yaml");
  io::WriteMrptGridmap(map.grid, dir + "/map.gridmap");
  io::WriteG2o(map.graph, dir + "/graph.g2o");
  io::RawlogWriter keyframes(dir + "/keyframes.rawlog");
  for (const auto& kf : map.keyframes) keyframes.Write(*kf.scan);
  keyframes.Close();
  if (!map.site.empty()) io::WriteTextAtomically(dir + "/site.json", nlohmann::json{{"scenario", map.site}}.dump(2));
}

namespace {

std::string ReadSite(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) return "";
  std::ifstream in(path);
  const auto j = nlohmann::json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.is_object() || !j.contains("scenario") || !j["scenario"].is_string())
    throw InputError(path + ": not a site file (expected {\"scenario\": \"<name>\"})");
  return j["scenario"].get<std::string>();
}

}  // namespace

MapArtefact ReadMapArtefact(const std::string& dir) {
  for (const char* f : {"graph.g2o", "keyframes.rawlog", "map.gridmap"}) {
    if (!std::filesystem::is_regular_file(dir + "/" + f)) {
      throw InputError(dir + ": not a specht map (missing " + f +
                       "; write one with `specht slam -o DIR` or a mapping drive of `specht run`)");
    }
  }
  const io::G2oReadResult graph = io::ReadG2o(dir + "/graph.g2o");
  std::vector<mrpt::obs::CObservation2DRangeScan::Ptr> scans;
  auto rawlog = io::OpenRawlog(dir + "/keyframes.rawlog");
  while (auto obs = rawlog->Next()) {
    if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs->data)) scans.push_back(scan);
  }
  std::vector<mrpt::poses::CPose2D> poses;
  for (const auto& [id, pose] : graph.graph.nodes) poses.push_back(pose);
  if (scans.size() != poses.size() || scans.empty()) {
    throw InputError(dir + ": map artefact is inconsistent: " + std::to_string(scans.size()) +
                     " keyframe scans in keyframes.rawlog but " + std::to_string(poses.size()) + " nodes in graph.g2o");
  }
  return {slam::KeyframesFromGraph(scans, poses), graph.graph, io::ReadMrptGridmap(dir + "/map.gridmap"),
          ReadSite(dir + "/site.json")};
}

}  // namespace specht::pipeline
