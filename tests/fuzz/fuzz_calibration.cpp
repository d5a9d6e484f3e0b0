// Stereo calibrations (stereo/calibration.h): KITTI calib files, OpenCV YAML and ROS
// camera_info, recognised by content.
#include "fuzz_support.h"
#include "specht/stereo/calibration.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = specht::fuzz::InputFile(data, size, "calib.txt");
  specht::fuzz::Expect([&] { specht::stereo::LoadCalibration({path}); });
  return 0;
}
