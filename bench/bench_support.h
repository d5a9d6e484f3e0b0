// bench/bench_support.h: what every benchmark reports besides its own figures.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "specht/core/progress.h"

namespace specht::bench {

using specht::PeakRssMib;  // core/progress.h
// CPU model, core count, build type: printed with every case.
nlohmann::json MachineNotes();
// Prints one JSON object on one line.
void Emit(const nlohmann::json& result);

}  // namespace specht::bench
