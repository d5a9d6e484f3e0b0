// specht/pipeline/map_artefact.h: a map saved to a directory — what `specht slam -o DIR`
// and a mapping drive of `specht run` write, and what `--map DIR` (localisation on it)
// and `--continue DIR` read back:
//   map.yaml + map.pgm   the grid for ROS's map_server
//   map.gridmap          the same grid, MRPT's format (read back here)
//   graph.g2o            the pose graph; node i is keyframe i
//   keyframes.rawlog     the keyframes' scans in node order (MRPT rawlog)
//   site.json            which scenario the map was drawn in (simulated drives only)
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <string>
#include <vector>

#include "specht/core/pose_graph.h"
#include "specht/slam/scan_matching.h"

namespace specht::pipeline {

struct MapArtefact {
  std::vector<slam::Keyframe> keyframes;  // poses are the graph's nodes
  PoseGraph2D graph;
  mrpt::maps::COccupancyGridMap2D grid;
  std::string site;  // the scenario's name for a simulated drive; "" for a dataset's map
};

// Writes every file above into `dir` (which must exist); site.json only with a site.
void WriteMapArtefact(const MapArtefact& map, const std::string& dir);

// Throws InputError naming the directory and what is missing or inconsistent.
MapArtefact ReadMapArtefact(const std::string& dir);

}  // namespace specht::pipeline
