// bench/bench_support.h: what every benchmark reports besides its own figures.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace specht::bench {

// Peak resident memory of this process so far, in MiB.
double PeakRssMib();
// CPU model, core count, build type: printed with every case.
nlohmann::json MachineNotes();
// Prints one JSON object on one line.
void Emit(const nlohmann::json& result);

}  // namespace specht::bench
