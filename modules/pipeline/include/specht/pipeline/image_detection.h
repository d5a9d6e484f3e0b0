// specht/pipeline/image_detection.h: the CNN detector (section "detect") on images —
// what `specht detect` runs — and, given right images and a rectified calibration,
// our SGM and the box depth fusion (section "fusion"). Writes labels/<name>.txt (KITTI
// object labels; with depth: dimensions and the bottom centre in the camera frame),
// annotated/<name>.png (class, score, distance), detections.json (every detection
// with its 3D position and covariance) and a report (counts per class, ms per stage).
#pragma once

#include <string>
#include <vector>

#include "specht/core/params.h"

namespace specht::pipeline {

struct ImageDetectionInputs {
  std::vector<std::string> images;  // left images
  std::vector<std::string> rights;  // none, or one right image per image
  std::vector<std::string> calib;   // a rectified calibration, needed with rights
};

// `data_dir` resolves the model paths. Inputs are checked before `out_dir` is created.
int DetectInImages(const params::Params& params, const ImageDetectionInputs& in, const std::string& data_dir,
                   const std::string& out_dir, bool quiet);

}  // namespace specht::pipeline
