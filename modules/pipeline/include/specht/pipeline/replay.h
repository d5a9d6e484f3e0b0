// specht/pipeline/replay.h: a dataset replayed through the stack — what `specht replay`
// and `specht slam` run:
//   dataset → replay clock → graph SLAM (mapping, continuing a saved map, or
//   localization on one) → the pose of every scan → perception (perception.h: stereo,
//   detector, fusion, tracker, OctoMap) → the world model, whose static layer follows
//   SLAM's grid as it grows and after every loop closure.
// Writes into the output directory: trajectory.tum, map.png, report.json; when
// mapping, the map artefact (map.yaml/.pgm, map.gridmap, graph.g2o, keyframes.rawlog)
// and loops.png; when perception ran, tracks.csv (io/object_tracks.h, map frame),
// snapshots.jsonl (world-model snapshots, one JSON object a line) and world.json (the
// last snapshot).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "specht/core/params.h"
#include "specht/io/dataset.h"
#include "specht/io/replay.h"
#include "specht/net/topics.h"

namespace specht::pipeline {

// `specht node slam`: the replay's input from DDS topics instead of a file, and what
// it estimates (the map every map_every_s of data, map → odom at every scan placed,
// the trajectory at the end) published there.
struct NodeIo {
  std::shared_ptr<net::Participant> participant;
  net::TopicSourceOptions topics;
  double map_every_s = 1.0;
};

// A dataset file by its kind: a ROS 2 bag (folder or .db3), an MCAP file, a ROS 1
// bag, else a rawlog or CARMEN log (io/dataset.h); the replay options choose the
// topics of a bag and what a bad record does.
std::unique_ptr<io::DatasetSource> OpenDatasetSource(const std::string& path, const io::ReplayOptions& replay);

struct ReplayInputs {
  std::string dataset;                              // "" = the rawlog shipped by Debian's mrpt-common
  std::string ground_truth;                         // "" = the dataset's own reference, when it has one
  std::string relations;                            // "" = <log stem>.relations beside the dataset, when there is one
  std::string reference_map;                        // a map_server YAML to score the map against; "" = a ROS 2
                                                    // bag folder's own map.yaml, when it has one
  std::string map_dir;                              // localize on this saved map instead of mapping
  std::string continue_dir;                         // continue this saved map
  std::string data_dir;                             // the detector's models
  std::string mcap;                                 // record the replay into this MCAP file, or ""
  std::vector<std::string> param_files, overrides;  // recorded in the report
  std::optional<NodeIo> node;                       // read and publish DDS topics instead of `dataset`
};

class Replay {
 public:
  // Opens the dataset, the reference and a saved map: throws InputError (file and
  // reason) before anything is written.
  Replay(const params::Params& params, ReplayInputs inputs, std::string command);
  ~Replay();
  Replay(const Replay&) = delete;
  Replay& operator=(const Replay&) = delete;

  // Runs to the end of the data, to where it breaks off or to an interrupt
  // (core/interrupt.h), and writes everything computed into `out_dir` (which exists).
  // Returns 0, 2 when the input broke off, 128 + the signal when interrupted.
  int Run(const std::string& out_dir, bool quiet);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace specht::pipeline
