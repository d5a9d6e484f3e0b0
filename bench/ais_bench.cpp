// ais_bench <data dir>: AIS decoding and dataset preparation throughput.
//   decode   every NMEA log of ais/nmea, repeated until ≥ 1 s of work: sentences/s
//            (lines fed through the whole chain: sentence layer, decoding, joining)
//   prepare  both ais/tracks files with the default AIS options on 2 threads:
//            points/s (reading gzip CSV, splitting, windows, features with the
//            coast and harbour lookups, handcrafted baseline features)
#include <chrono>
#include <fstream>

#include "bench_support.h"
#include "specht/ais/dataset.h"
#include "specht/ais/decoder.h"

namespace {

double Since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  const std::string data = argc > 1 ? argv[1] : SPECHT_DATA_DIR;
  std::vector<std::string> lines;
  for (const char* name : {"gpsd-sample.aivdm", "gpsd-ais-nmea.log", "libais-test.aivdm", "pyais-nmea-sample.txt",
                           "signalk-nais400-merrimac.log"}) {
    std::ifstream in(data + "/ais/nmea/" + name);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
  }
  if (lines.empty()) {
    std::fprintf(stderr, "ais_bench: no NMEA logs under %s/ais/nmea\n", data.c_str());
    return 2;
  }
  long sentences = 0, messages = 0;
  const auto t0 = std::chrono::steady_clock::now();
  while (Since(t0) < 1.0) {
    specht::ais::Decoder d({}, [&](const specht::ais::Message&) { ++messages; });
    for (const auto& l : lines) d.Feed(l);
    d.Finish();
    sentences += d.stats().sentences.sentences;
  }
  const double decode_s = Since(t0);
  specht::bench::Emit({{"name", "ais/decode"},
                       {"sentences", sentences},
                       {"messages", messages},
                       {"sentences_per_s", sentences / decode_s},
                       {"us_per_sentence", 1e6 * decode_s / sentences},
                       {"peak_rss_mib", specht::bench::PeakRssMib()},
                       {"machine", specht::bench::MachineNotes()}});

  const specht::ais::AisOptions o;
  const auto g0 = std::chrono::steady_clock::now();
  const specht::ais::Geography geo = specht::ais::Geography::Load(o, data);
  const double geo_s = Since(g0);
  specht::ais::PrepareReport report;
  const auto p0 = std::chrono::steady_clock::now();
  const auto d =
      specht::ais::PrepareDataset({data + "/ais/tracks/brest-dev.csv.gz", data + "/ais/tracks/mpa-dev.csv.gz"}, o,
                                  specht::ais::AisPreprocessOptions(), geo, report);
  const double prepare_s = Since(p0);
  specht::bench::Emit({{"name", "ais/prepare"},
                       {"points", report.points},
                       {"windows", d.windows.size()},
                       {"threads", o.threads},
                       {"points_per_s", report.points / prepare_s},
                       {"seconds", prepare_s},
                       {"geography_load_s", geo_s},
                       {"peak_rss_mib", specht::bench::PeakRssMib()},
                       {"machine", specht::bench::MachineNotes()}});
  return 0;
}
