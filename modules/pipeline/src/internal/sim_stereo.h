// The simulator's stereo frames as MRPT observations, the form every other stereo
// source reaches perception in.
#pragma once

#include <mrpt/obs/CObservationStereoImages.h>

#include "specht/core/time.h"
#include "specht/sim/camera.h"
#include "specht/sim/scenario.h"

namespace specht::pipeline::internal {

// A stereo observation with the scenario camera's calibration (focal length, centred
// principal point, baseline) and mount (the left camera's optical frame — x right,
// y down, z forward — on base_link), stamped; images not set.
mrpt::obs::CObservationStereoImages::Ptr SimStereoObservation(Stamp stamp, const sim::StereoSpec& spec);

// The same with `frame`'s colour images held in memory (shared, not copied).
mrpt::obs::CObservationStereoImages::Ptr SimStereoObservation(Stamp stamp, const sim::StereoSpec& spec,
                                                              const sim::StereoFrame& frame);

}  // namespace specht::pipeline::internal
