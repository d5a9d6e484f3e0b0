#include "internal/sim_stereo.h"

#include <cmath>

namespace specht::pipeline::internal {

mrpt::obs::CObservationStereoImages::Ptr SimStereoObservation(Stamp stamp, const sim::StereoSpec& spec) {
  auto obs = mrpt::obs::CObservationStereoImages::Create();
  obs->hasImageRight = true;
  const double cx = (spec.width - 1) / 2.0, cy = (spec.height - 1) / 2.0;
  for (auto* cam : {&obs->leftCamera, &obs->rightCamera}) {
    cam->ncols = spec.width, cam->nrows = spec.height;
    cam->setIntrinsicParamsFromValues(spec.focal_px, spec.focal_px, cx, cy);
  }
  obs->cameraPose = mrpt::poses::CPose3DQuat(
      mrpt::poses::CPose3D(spec.x_m, spec.y_m, spec.z_m, spec.yaw_rad - M_PI / 2, 0, -M_PI / 2 - spec.pitch_rad));
  obs->rightCameraPose = mrpt::poses::CPose3DQuat(mrpt::poses::CPose3D(spec.baseline_m, 0, 0, 0, 0, 0));
  obs->sensorLabel = "STEREO";
  obs->timestamp = ToMrpt(stamp);
  return obs;
}

mrpt::obs::CObservationStereoImages::Ptr SimStereoObservation(Stamp stamp, const sim::StereoSpec& spec,
                                                              const sim::StereoFrame& frame) {
  auto obs = SimStereoObservation(stamp, spec);
  obs->imageLeft = mrpt::img::CImage(frame.left_bgr, mrpt::img::SHALLOW_COPY);
  obs->imageRight = mrpt::img::CImage(frame.right_bgr, mrpt::img::SHALLOW_COPY);
  return obs;
}

}  // namespace specht::pipeline::internal
