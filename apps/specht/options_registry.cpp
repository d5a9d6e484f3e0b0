#include "options_registry.h"

#include "specht/ais/dataset.h"
#include "specht/ais/nmea.h"
#include "specht/classify/model.h"
#include "specht/classify/preprocess.h"
#include "specht/core/transform_tree.h"
#include "specht/detect/detector.h"
#include "specht/detect/fusion.h"
#include "specht/io/replay.h"
#include "specht/net/dds.h"
#include "specht/pipeline/closed_loop.h"
#include "specht/pipeline/nodes.h"
#include "specht/pipeline/perception.h"
#include "specht/plan/hybrid_astar.h"
#include "specht/plan/kinodynamic.h"
#include "specht/plan/local_planner.h"
#include "specht/plan/smoother.h"
#include "specht/sim/detections.h"
#include "specht/slam/graph_slam.h"
#include "specht/slam/localizer.h"
#include "specht/slam/pose_check.h"
#include "specht/slam/pose_graph_optimizer.h"
#include "specht/slam/scan_matching.h"
#include "specht/stereo/point_cloud.h"
#include "specht/stereo/sgm.h"
#include "specht/track/tracker.h"
#include "specht/world/world_model.h"

namespace specht::app {

const params::Registry& AllOptions() {
  static const params::Registry registry = [] {
    params::Registry r;
    r.Add<FramesOptions>("frames", "coordinate frames and sensor mounts (REP-103/105)");
    r.Add<io::ReplayOptions>("replay", "dataset replay: pacing, time window, bad records");
    r.Add<slam::SlamOptions>("slam", "graph SLAM: method and edge uncertainties");
    r.Add<slam::ScanMatchingOptions>("scan_matching", "scan-matching odometry: ICP against a local submap");
    r.Add<slam::LoopClosureOptions>("loop_closure", "submaps and loop-closure search (branch and bound)");
    r.Add<slam::GridOptions>("grid", "occupancy grid built from keyframes");
    r.Add<slam::PoseGraphOptions>("pose_graph", "pose-graph back end (Ceres)");
    r.Add<slam::LocalizationOptions>("localization", "localization on a saved map (--map)");
    r.Add<slam::PoseCheckOptions>("pose_check", "the believed pose against a prior map: lost, relocalised");
    r.Add<stereo::SgmOptions>("stereo", "stereo matching: semi-global matcher, guidance, OpenCV baseline");
    r.Add<stereo::CloudOptions>("stereo_cloud", "stereo depth to points and OctoMap");
    r.Add<detect::DetectorOptions>("detect", "CNN detector (cv::dnn): model, input, thresholds, class map");
    r.Add<detect::FusionOptions>("fusion", "box depth from stereo disparity, 3D position and covariance");
    r.Add<world::WorldModelOptions>("world", "the shared world model: obstacle lifetime, footprint, cost layer");
    r.Add<pipeline::PerceptionOptions>(
        "perception", "the perception pipeline: stereo, detector, tracker and OctoMap into the world model");
    r.Add<track::TrackerOptions>("track", "multi-object tracker: motion models, gating, lifecycle");
    r.Add<sim::SyntheticDetectionOptions>("synthetic_detections",
                                          "simulated detections for tracking on synthetic scenes");
    r.Add<classify::PreprocessOptions>("classify", "trajectory preprocessing: segmentation, windows, features");
    r.Add<classify::ModelOptions>("classify_model", "trajectory classifier: 1D ResNet variant and training");
    r.Add<ais::SentenceOptions>("ais_decoder", "AIS NMEA decoding: multipart reassembly");
    r.Add<ais::AisOptions>("ais", "AIS dataset preparation: coastline, harbours, threads");
    r.Add<ais::AisPreprocessOptions>("ais_classify", "AIS trajectory preprocessing (the classify chain, AIS defaults)");
    r.Add<ais::AisModelOptions>("ais_model", "AIS vessel classifier: 1D ResNet variant and training");
    r.Add<plan::CarOptions>("car", "the car: bicycle model limits and footprint");
    r.Add<plan::HybridAStarOptions>("hybrid_astar", "global search: hybrid A* over (x, y, heading)");
    r.Add<plan::HybridAStarOptions>("hybrid_astar_fine",
                                    "the fallback search where hybrid_astar finds no path (tight bays)",
                                    plan::FineSearchDefaults());
    r.Add<plan::KinodynamicOptions>("kinodynamic",
                                    "kinodynamic planner: OMPL SST / RRT / KPIECE1 over the bicycle model");
    r.Add<plan::LocalPlannerOptions>("local_planner",
                                     "the OMPL local planner over a receding horizon along the global route");
    r.Add<plan::SmootherOptions>("smoother", "path smoothing on Ceres (elastic band)");
    r.Add<plan::TrackerOptions>("tracker", "path tracking: pure pursuit and speed profile");
    r.Add<pipeline::ClosedLoopOptions>("closed_loop", "mission state machine: margins, waiting, tolerances");
    r.Add<net::Options>("dds", "DDS transport (Cyclone DDS): domain, the interface it binds, discovery peers");
    r.Add<pipeline::NodeOptions>("node", "the stack's stages as DDS nodes: topics, merging, when input ends");
    return r;
  }();
  return registry;
}

const std::vector<DefaultsFile>& DefaultsFiles() {
  static const std::vector<DefaultsFile> files = {
      {"core.yaml", {"frames"}},
      {"io.yaml", {"replay"}},
      {"slam.yaml", {"slam", "scan_matching", "loop_closure", "pose_graph", "grid", "localization", "pose_check"}},
      {"stereo.yaml", {"stereo", "stereo_cloud"}},
      {"detect.yaml", {"detect", "fusion"}},
      {"world.yaml", {"world"}},
      {"pipeline.yaml", {"perception"}},
      {"track.yaml", {"track", "synthetic_detections"}},
      {"classify.yaml", {"classify", "classify_model"}},
      {"ais.yaml", {"ais_decoder", "ais", "ais_classify", "ais_model"}},
      {"plan.yaml",
       {"car", "hybrid_astar", "hybrid_astar_fine", "kinodynamic", "local_planner", "smoother", "tracker"}},
      {"decide.yaml", {"closed_loop"}},
      {"net.yaml", {"dds", "node"}},
  };
  return files;
}

}  // namespace specht::app
