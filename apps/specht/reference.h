// apps/specht/reference.h: reading a reference trajectory in any format specht knows.
#pragma once

#include <string>

#include "specht/core/trajectory.h"

namespace specht::app {

// A CARMEN log (its corrected laser poses), TUM (8 columns) or "t x y theta" (4).
Trajectory ReadReference(const std::string& path);

}  // namespace specht::app
