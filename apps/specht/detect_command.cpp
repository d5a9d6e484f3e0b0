// `specht detect <image>... [--right IMAGE]... [--calib FILE] -o DIR`
// (pipeline/image_detection.h).
#include "commands.h"
#include "specht/pipeline/image_detection.h"

namespace specht::app {
namespace {

struct DetectArgs {
  CommonArgs common;
  pipeline::ImageDetectionInputs in;
};

}  // namespace

void AddDetectCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<DetectArgs>();
  CLI::App* cmd = app.add_subcommand("detect", "CNN obstacle detection, with stereo depth when given a pair");
  cmd->add_option("images", args->in.images, "left images (8-bit)")->required();
  cmd->add_option("--right", args->in.rights, "right images, one per image: adds SGM depth and 3D positions");
  cmd->add_option("--calib", args->in.calib, "rectified calibration (KITTI calib.txt, or two ROS camera_info files)");
  AddCommonOptions(*cmd, args->common, "specht-out/detect");
  cmd->callback([args, &exit_code] {
    exit_code = pipeline::DetectInImages(LoadParams(args->common), args->in, DataDir(args->common),
                                         args->common.out_dir, args->common.quiet);
  });
}

}  // namespace specht::app
