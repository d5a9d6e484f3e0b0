// NMEA 0183 AIS (ais/decoder.h): sentences, tag blocks, multipart reassembly and
// every message type's bit fields, line by line as a log feeds them.
#include <string_view>

#include "fuzz_support.h"
#include "specht/ais/decoder.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  long messages = 0;
  specht::ais::Decoder decoder(specht::ais::SentenceOptions{}, [&](const specht::ais::Message&) { ++messages; });
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  specht::fuzz::Expect([&] {
    for (size_t start = 0; start <= text.size();) {
      const size_t end = std::min(text.find('\n', start), text.size());
      decoder.Feed(text.substr(start, end - start));
      start = end + 1;
    }
    decoder.Finish();
  });
  return 0;
}
