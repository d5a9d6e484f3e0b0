// Scenario files (sim/scenario.h) and mission files (decide/mission.h).
#include "fuzz_support.h"
#include "specht/decide/mission.h"
#include "specht/sim/scenario.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  specht::fuzz::Expect([&] { specht::sim::ParseScenario(specht::fuzz::Text(data, size), "input.yaml"); });
  const std::string path = specht::fuzz::InputFile(data, size, "mission.yaml");
  const specht::decide::MissionSite site{"fuzz", {{"A", 10, 5, 0.5, 5, 2.5}, {"B", -4, 2, 3.1, 6, 3}}};
  specht::fuzz::Expect([&] { specht::decide::LoadMission(path, site, specht::plan::CarOptions{}); });
  return 0;
}
