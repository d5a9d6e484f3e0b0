// Reference trajectories (io/reference.h: TUM, "t x y theta", CARMEN), published
// relations files (io/trajectory_io.h) and the object-track CSV (io/object_tracks.h).
#include "fuzz_support.h"
#include "specht/io/object_tracks.h"
#include "specht/io/reference.h"
#include "specht/io/trajectory_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = specht::fuzz::InputFile(data, size, "input.txt");
  specht::fuzz::Expect([&] { specht::io::ReadReference(path); });
  specht::fuzz::Expect([&] { specht::io::ReadTum(path); });
  specht::fuzz::Expect([&] { specht::io::ReadRelations(path); });
  specht::fuzz::Expect([&] { specht::io::ParseObjectTracks(specht::fuzz::Text(data, size), "input.csv"); });
  return 0;
}
