// Tabular AIS positions (ais/positions.h): NOAA, DMA and specht's own CSV layouts,
// grouped into vessels.
#include "fuzz_support.h"
#include "specht/ais/positions.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = specht::fuzz::InputFile(data, size, "input.csv");
  specht::fuzz::Expect([&] {
    specht::ais::VesselReader reader(path);
    specht::ais::Vessel v;
    while (reader.Next(v)) {
    }
  });
  return 0;
}
