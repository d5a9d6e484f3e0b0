// specht/io/map_io.h: occupancy grids to and from files users have tools for.
//   ROS map_server:  <name>.pgm (P5, 0 occupied, 254 free, 205 unknown) + <name>.yaml
//                    (image, resolution, origin, thresholds), as map_saver writes them.
//   MRPT .gridmap:   the serialized COccupancyGridMap2D, read by MRPT's apps.
//   PNG picture:     the map with trajectories drawn on it, a scale bar and a legend.
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <array>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "specht/core/trajectory.h"

namespace specht::io {

// map_saver's trinary thresholds on the occupancy probability.
constexpr double kRosOccupiedThresh = 0.65;
constexpr double kRosFreeThresh = 0.196;

void WriteRosMap(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& yaml_path);
// Reads a map_server YAML + PGM (trinary or scale mode). Throws InputError naming
// the file and field on bad input.
mrpt::maps::COccupancyGridMap2D ReadRosMap(const std::string& yaml_path);

void WriteMrptGridmap(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& path);
mrpt::maps::COccupancyGridMap2D ReadMrptGridmap(const std::string& path);

// Any image as PNG, written atomically (RuntimeError naming the path on failure).
void WritePng(const cv::Mat& image, const std::string& path);

struct PathOverlay {
  const Trajectory* trajectory = nullptr;
  std::array<unsigned char, 3> rgb{30, 90, 220};
  std::string label;
  bool markers = false;   // one dot per pose instead of a line (e.g. obstacles)
  bool segments = false;  // poses 0–1, 2–3, … as separate thin lines (e.g. loop closures)
};

// Renders the known part of the map (cropped, with a margin) at least `min_width_px`
// wide, the paths on top (start: circle, end: square), a scale bar and a legend.
void WriteMapPng(const mrpt::maps::COccupancyGridMap2D& grid, const std::vector<PathOverlay>& paths,
                 const std::string& path, int min_width_px = 900);

// Trajectories alone on a white background, same conventions as WriteMapPng.
void WriteTrajectoryPng(const std::vector<PathOverlay>& paths, const std::string& path, int min_width_px = 900);

}  // namespace specht::io
