// g2o pose graphs (io/g2o.h): VERTEX_SE2, EDGE_SE2 and whatever else a file holds.
#include "fuzz_support.h"
#include "specht/io/g2o.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = specht::fuzz::InputFile(data, size, "input.g2o");
  for (const auto on_bad : {specht::io::OnBadRecord::kStop, specht::io::OnBadRecord::kSkip})
    specht::fuzz::Expect([&] { specht::io::ReadG2o(path, on_bad); });
  return 0;
}
