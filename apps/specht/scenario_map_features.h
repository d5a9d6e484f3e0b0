// apps/specht/scenario_map_features.h: the classifier's map features of a simulated
// scene — distance to the static occupied cells of its true grid (0.1 m) and to its
// parking bays as points of interest. Used by `specht classify` (by scenario name
// in the track ids) and by `specht track --model` (online).
#pragma once

#include "specht/classify/preprocess.h"
#include "specht/sim/scenario.h"

namespace specht::app {

classify::MapFeatures ScenarioMapFeatures(const sim::Scenario& scenario);

}  // namespace specht::app
