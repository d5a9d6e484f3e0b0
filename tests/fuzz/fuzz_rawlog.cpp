// MRPT rawlogs (io/dataset.h, the rawlog source): every record read or rejected.
#include "fuzz_support.h"
#include "specht/io/dataset.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = specht::fuzz::InputFile(data, size, "input.rawlog");
  specht::fuzz::Expect([&] {
    auto source = specht::io::OpenDataset(path, specht::io::OnBadRecord::kSkip);
    while (source->Next()) {
    }
  });
  return 0;
}
