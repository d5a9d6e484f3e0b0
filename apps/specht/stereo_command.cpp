// `specht stereo <left> <right> [--calib FILE]... [--hints sparse.png | --lidar scan.bin]
//  [--ground-height M --ground-pitch DEG] -o DIR` (pipeline/stereo_pair.h).
#include "commands.h"
#include "specht/pipeline/stereo_pair.h"

namespace specht::app {
namespace {

struct StereoArgs {
  CommonArgs common;
  pipeline::StereoPairInputs in;
};

}  // namespace

void AddStereoCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<StereoArgs>();
  CLI::App* cmd = app.add_subcommand("stereo", "disparity, depth, point cloud and OctoMap of a stereo pair");
  cmd->add_option("left", args->in.left, "left image (8-bit)")->required();
  cmd->add_option("right", args->in.right, "right image (8-bit, same size)")->required();
  cmd->add_option("--calib", args->in.calib,
                  "calibration: KITTI calib.txt or calib_cam_to_cam.txt, OpenCV YAML, MRPT ini, or two ROS "
                  "camera_info files (left, right); unrectified pairs are rectified");
  cmd->add_option("--hints", args->in.hints, "sparse disparity hints (KITTI uint16 PNG) for guided matching");
  cmd->add_option("--lidar", args->in.lidar, "KITTI Velodyne scan (.bin) projected into the left image as hints");
  cmd->add_option("--ground-height", args->in.ground_height_m,
                  "dense ground-plane prior: camera height above ground (m)");
  cmd->add_option("--ground-pitch", args->in.ground_pitch_deg, "dense ground-plane prior: camera pitch down (deg)");
  cmd->add_option("--camera-frame", args->in.camera_frame, "the left camera's frame name")->capture_default_str();
  cmd->add_option("--frame", args->in.frame, "write points.ply in this frame (static transforms from frames.*)");
  AddCommonOptions(*cmd, args->common, "specht-out/stereo");
  cmd->callback([args, &exit_code] {
    exit_code = pipeline::RunStereoPair(LoadParams(args->common), args->in, args->common.out_dir);
  });
}

}  // namespace specht::app
