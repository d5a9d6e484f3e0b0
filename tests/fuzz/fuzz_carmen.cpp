// CARMEN logs (io/carmen.h): lines of FLASER, ROBOTLASER1, ODOM, PARAM, ...; the
// log's corrected poses as a reference too.
#include "fuzz_support.h"
#include "specht/io/carmen.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = specht::fuzz::InputFile(data, size, "input.log");
  for (const auto on_bad : {specht::io::OnBadRecord::kStop, specht::io::OnBadRecord::kSkip}) {
    specht::fuzz::Expect([&] {
      auto source = specht::io::OpenCarmen(path, on_bad);
      while (source->Next()) {
      }
    });
  }
  specht::fuzz::Expect([&] { specht::io::ReadCarmenReference(path); });
  return 0;
}
