// Scenario files (sim/scenario.h), mission files (decide/mission.h) and launch files
// (net/launch.h).
#include "fuzz_support.h"
#include "specht/decide/mission.h"
#include "specht/net/launch.h"
#include "specht/sim/scenario.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  specht::fuzz::Expect([&] { specht::sim::ParseScenario(specht::fuzz::Text(data, size), "input.yaml"); });
  const std::string path = specht::fuzz::InputFile(data, size, "mission.yaml");
  const specht::decide::MissionSite site{"fuzz", {{"A", 10, 5, 0.5, 5, 2.5}, {"B", -4, 2, 3.1, 6, 3}}};
  specht::fuzz::Expect([&] { specht::decide::LoadMission(path, site, specht::plan::CarOptions{}); });
  specht::fuzz::Expect([&] {
    specht::net::ParseLaunchFile(specht::fuzz::Text(data, size), "launch.yaml", {"play", "slam", "record"});
  });
  return 0;
}
