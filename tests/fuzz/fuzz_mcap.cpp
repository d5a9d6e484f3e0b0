// MCAP files (io/mcap.h) read linearly: records, chunks (zstd, lz4, none), and the
// ROS source on top (io/ros_bag.h: /tf_static, LaserScan and Odometry decoded).
#include "fuzz_support.h"
#include "specht/io/mcap.h"
#include "specht/io/ros_bag.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = specht::fuzz::InputFile(data, size, "input.mcap");
  specht::fuzz::Expect([&] {
    specht::io::McapReader reader(path);
    for (int i = 0; i < 10000 && reader.Next(); ++i) {
    }
  });
  for (const auto on_bad : {specht::io::OnBadRecord::kStop, specht::io::OnBadRecord::kSkip})
    specht::fuzz::Expect([&] {
      auto source = specht::io::OpenMcap(path, {}, on_bad);
      for (int i = 0; i < 10000 && source->Next(); ++i) {
      }
    });
  return 0;
}
