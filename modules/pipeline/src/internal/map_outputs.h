// Replay's outputs beside the map: reference metrics, map entropy, the map artefact
// (what `--map` and `--continue` read back) and the loop report.
#pragma once

#include <mrpt/maps/COccupancyGridMap2D.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "specht/core/trajectory.h"
#include "specht/io/map_io.h"
#include "specht/io/trajectory_io.h"
#include "specht/pipeline/map_artefact.h"
#include "specht/slam/graph_slam.h"
#include "specht/slam/pose_graph_optimizer.h"

namespace specht::pipeline::internal {

// Metrics against the reference, when there is one; returns the reference moved into
// the map frame for the picture.
Trajectory AddReferenceMetrics(const Trajectory& trajectory, const Trajectory& reference, nlohmann::json& metrics);

// The Kümmerle metric on a published relations file (eval/relation_error.h), and
// relations.png: the worst relations on the map. A trajectory that does not hold
// every relation's scans (a run cut short) gets the reason instead of figures.
void AddPublishedRelationMetrics(const Trajectory& trajectory, const io::RelationsFile& relations,
                                 const mrpt::maps::COccupancyGridMap2D& grid, const std::string& out,
                                 nlohmann::json& metrics);

// The estimate and the segments of its worst relations (eval::RelationSegments), as
// relations.png draws them.
std::vector<io::PathOverlay> RelationOverlays(const Trajectory& estimate, const Trajectory& worst, size_t count);

// The map against a reference map of the same place (eval/map_agreement.h; a
// map_server YAML): the agreement in `metrics` ("reference_map") and
// map_vs_reference.png, both maps in the reference's frame — the reference's walls
// red, ours blue, where they agree purple.
void AddReferenceMapMetrics(const mrpt::maps::COccupancyGridMap2D& grid, const std::string& reference_yaml,
                            const std::string& out, nlohmann::json& metrics);

// Mean map entropy of the keyframe scans at the estimated poses and, with a
// reference, of the same scans at the estimate's and at the reference's poses
// (eval/map_quality.h): whether the reference's map is sharper than ours.
void AddMapEntropy(const std::vector<slam::Keyframe>& keyframes, const Trajectory& reference, nlohmann::json& metrics);

// The map artefact of a SLAM run (specht/pipeline/map_artefact.h).
void WriteMapArtefact(const slam::GraphSlam& slam, const mrpt::maps::COccupancyGridMap2D& grid, const std::string& out);

// The loop closures as the final graph holds them, their weights and errors, and
// loops.png (see replay.cpp's report).
void ReportLoops(const slam::GraphSlam& slam, const slam::PoseGraphOptions& options,
                 const mrpt::maps::COccupancyGridMap2D& grid, const Trajectory& trajectory, const std::string& out,
                 nlohmann::json& metrics);

}  // namespace specht::pipeline::internal
