// replay_bench <dataset> [name]: the replay pipeline (read, scan matching, grid) on one
// dataset, with default parameters. Prints one JSON object:
//   ms_per_scan p50/p95/mean (scan matching per scan), real_time_factor (data seconds
//   per wall second, whole pipeline), peak_rss_mib.
#include <chrono>
#include <iostream>

#include <mrpt/obs/CObservation2DRangeScan.h>

#include "bench_support.h"
#include "specht/io/dataset.h"
#include "specht/slam/scan_matching.h"

using Clock = std::chrono::steady_clock;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: replay_bench <dataset> [name]\n";
    return 2;
  }
  const std::string dataset = argv[1];
  const std::string name = argc > 2 ? argv[2] : dataset;
  const auto t0 = Clock::now();
  auto source = specht::io::OpenDataset(dataset);
  specht::slam::ScanMatchingMapper mapper(specht::slam::ScanMatchingOptions{}, nullptr, "base_link");
  std::vector<double> scan_ms;
  std::optional<specht::Stamp> first, last;
  while (auto obs = source->Next()) {
    const bool is_scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs->data) != nullptr;
    const auto s = Clock::now();
    mapper.Add(obs->stamp, obs->data);
    if (is_scan) scan_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - s).count());
    if (!first) first = obs->stamp;
    last = obs->stamp;
  }
  const auto grid = specht::slam::BuildGrid(mapper.keyframes(), specht::slam::GridOptions{});
  const double wall_s = std::chrono::duration<double>(Clock::now() - t0).count();
  const double data_s = first ? specht::SecondsBetween(*first, *last) : 0.0;
  double sum = 0;
  for (double v : scan_ms) sum += v;
  specht::bench::Emit({{"name", "replay/" + name},
                       {"scans", scan_ms.size()},
                       {"keyframes", mapper.keyframes().size()},
                       {"ms_per_scan_p50", specht::bench::Percentile(scan_ms, 0.5)},
                       {"ms_per_scan_p95", specht::bench::Percentile(scan_ms, 0.95)},
                       {"ms_per_scan_mean", scan_ms.empty() ? 0.0 : sum / scan_ms.size()},
                       {"data_s", data_s},
                       {"wall_s", wall_s},
                       {"real_time_factor", wall_s > 0 ? data_s / wall_s : 0.0},
                       {"peak_rss_mib", specht::bench::PeakRssMib()},
                       {"map_cells", grid.getSizeX() * grid.getSizeY()},
                       {"machine", specht::bench::MachineNotes()}});
  return 0;
}
