// `specht convert <dataset> -o out.rawlog`: any dataset specht reads (CARMEN logs,
// rawlogs) to an MRPT rawlog, so MRPT's tools and apps can read it. With --layout
// frames each laser scan becomes one action/sensory-frame pair whose action is the
// odometry increment since the previous scan (what icp-slam steps through).
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>

#include "commands.h"
#include "specht/core/log.h"
#include "specht/core/progress.h"
#include "specht/io/dataset.h"
#include "specht/io/rawlog_writer.h"

namespace specht::app {
namespace {

struct ConvertArgs {
  std::string dataset;
  std::string out;
  std::string layout = "observations";
  bool quiet = false;
};

int RunConvert(const ConvertArgs& a) {
  auto source = io::OpenDataset(a.dataset);
  io::RawlogWriter writer(a.out);
  ProgressLine progress("convert", "records", !a.quiet);
  mrpt::poses::CPose2D odometry, odometry_at_last_scan;
  bool have_scan = false;
  long records = 0;
  while (auto obs = source->Next()) {
    if (a.layout == "observations") {
      writer.Write(*obs->data);
    } else if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs->data)) {
      odometry = odo->odometry;
    } else if (std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs->data)) {
      writer.WriteFrame(have_scan ? odometry - odometry_at_last_scan : mrpt::poses::CPose2D(), obs->data);
      odometry_at_last_scan = odometry;
      have_scan = true;
    }
    progress.Update(static_cast<double>(++records), source->FractionRead());
  }
  writer.Close();
  progress.Finish("-> " + a.out + " (" + std::to_string(writer.count()) + " " +
                  (a.layout == "observations" ? "observations" : "frames") + ")");
  return 0;
}

}  // namespace

void AddConvertCommand(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<ConvertArgs>();
  CLI::App* cmd = app.add_subcommand("convert", "convert a dataset (CARMEN log, rawlog) to an MRPT rawlog");
  cmd->add_option("dataset", args->dataset, "input dataset")->required();
  cmd->add_option("-o,--out", args->out, "output rawlog")->required();
  cmd->add_option("--layout", args->layout, "observations, or frames (action/sensory-frame pairs, one per scan)")
      ->check(CLI::IsMember({"observations", "frames"}))
      ->capture_default_str();
  cmd->add_flag("-q,--quiet", args->quiet, "no progress line");
  cmd->callback([args, &exit_code] { exit_code = RunConvert(*args); });
}

}  // namespace specht::app
