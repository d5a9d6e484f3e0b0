#include "specht/pipeline/simulation.h"

#include <mrpt/obs/CObservationStereoImages.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>

#include "internal/sim_stereo.h"
#include "specht/core/error.h"
#include "specht/core/interrupt.h"
#include "specht/core/log.h"
#include "specht/core/progress.h"
#include "specht/core/statistics.h"
#include "specht/io/atomic_file.h"
#include "specht/io/data_dir.h"
#include "specht/io/map_io.h"
#include "specht/io/rawlog_writer.h"
#include "specht/io/report.h"
#include "specht/io/trajectory_io.h"
#include "specht/sim/simulator.h"
#include "specht/sim/sprites.h"

namespace specht::pipeline {
namespace {

// The sprites agents are drawn with: none for "none" or a scenario without camera;
// under "auto" the library when the data directory has one (else boxes, with a
// warning); a set's name also selects that set.
std::optional<sim::SpriteLibrary> LoadSprites(const SimulationOptions& a, sim::Scenario& scenario) {
  if (!scenario.stereo || a.sprites == "none") return std::nullopt;
  if (a.sprites != "auto") {
    sim::ParseSpriteSet(a.sprites, "--sprites");
    scenario.stereo->sprites = a.sprites;
  }
  const auto data = io::ResolveDataDir(a.data_dir);
  const bool named =
      std::any_of(scenario.agents.begin(), scenario.agents.end(), [](auto& g) { return !g.sprite.empty(); });
  if (!data || !std::filesystem::is_directory(*data + "/sprites")) {
    if (a.sprites != "auto" || named)
      throw InputError("--sprites: no sprites directory in the data directory (--data-dir or $SPECHT_DATA_DIR)");
    spdlog::warn("sim: no sprites in the data directory: agents are drawn as boxes");
    return std::nullopt;
  }
  sim::SpriteLibrary library = sim::SpriteLibrary::Load(*data + "/sprites");
  // An unknown name fails before anything is written.
  for (size_t i = 0; i < scenario.agents.size(); ++i) {
    if (scenario.agents[i].sprite.empty()) continue;
    try {
      library.Named(scenario.agents[i].sprite);
    } catch (const InputError& e) {
      throw InputError(scenario.path + ": agents[" + std::to_string(i) + "].sprite: " + e.what());
    }
  }
  return library;
}

struct ClassStats {
  std::vector<double> speed, turn_rate;
};

// Writes one rendered stereo frame and returns the rawlog observation referring to it.
mrpt::obs::CObservation::Ptr WriteStereoFrame(const std::string& out, int index, Stamp stamp, const sim::StereoFrame& f,
                                              const sim::StereoSpec& spec) {
  char name[16];
  std::snprintf(name, sizeof(name), "%06d", index);
  io::WritePng(f.left_bgr, out + "/sim_Images/left_" + name + ".png");
  io::WritePng(f.right_bgr, out + "/sim_Images/right_" + name + ".png");
  cv::Mat kitti(f.disparity.size(), CV_16U);
  f.disparity.convertTo(kitti, CV_16U, 256.0);
  io::WritePng(kitti, out + "/stereo/disparity/" + std::string(name) + ".png");
  std::string labels;
  for (const auto& line : f.kitti_labels) labels += line + "\n";
  io::WriteTextAtomically(out + "/stereo/labels/" + std::string(name) + ".txt", labels);

  auto obs = internal::SimStereoObservation(stamp, spec);
  obs->imageLeft.setExternalStorage(std::string("left_") + name + ".png");
  obs->imageRight.setExternalStorage(std::string("right_") + name + ".png");
  return obs;
}

}  // namespace

int RecordSimulation(const SimulationOptions& a) {
  sim::Scenario scenario = sim::LoadScenario(a.scenario);
  if (a.seed) scenario.seed = *a.seed;
  if (a.duration_s) {
    if (!(*a.duration_s > 0)) throw InputError("--duration: must be positive");
    scenario.duration_s = *a.duration_s;
  }
  if (a.no_camera) scenario.stereo.reset();
  const std::optional<sim::SpriteLibrary> sprites = LoadSprites(a, scenario);
  io::MakeOutputDir(a.out_dir);
  const std::string out = a.out_dir;
  sim::Simulator simulator(scenario, scenario.seed, sprites ? &*sprites : nullptr);

  io::RawlogWriter rawlog(out + "/sim.rawlog");
  if (scenario.stereo) {
    for (const char* d : {"/sim_Images", "/stereo/disparity", "/stereo/labels"}) io::MakeOutputDir(out + d);
  }
  int stereo_frames = 0;
  long labelled_boxes = 0;
  std::string views = "frame,t_s,id,class,sprite,x0_px,y0_px,x1_px,y1_px,visible,truncated,range_m\n";
  Trajectory truth;
  std::map<int, Trajectory> agent_paths;
  std::map<std::string, ClassStats> stats;
  std::string csv = "time_s,id,class,x_m,y_m,yaw_rad,vx_mps,vy_mps,speed_mps,yaw_rate_rad_s\n";
  std::map<std::string, long> counts;
  ProgressLine progress("sim", "s simulated", !a.quiet);
  io::StageTimer timer;
  const long steps = std::lround(scenario.duration_s / sim::Simulator::kStepS);
  {
    auto t = timer.Time("simulate");
    for (long k = 0; k < steps && !InterruptRequested(); ++k) {
      simulator.Step(
          [&](Stamp, const mrpt::obs::CObservation::Ptr& obs) {
            rawlog.Write(*obs);
            ++counts[obs->GetRuntimeClass()->className];
          },
          [&](Stamp stamp, const sim::StereoFrame& frame) {
            rawlog.Write(*WriteStereoFrame(out, stereo_frames++, stamp, frame, *scenario.stereo));
            labelled_boxes += static_cast<long>(frame.kitti_labels.size());
            for (const auto& v : frame.agents) {
              char row[320];
              std::snprintf(row, sizeof(row), "%d,%.3f,%d,%s,%s,%.0f,%.0f,%.0f,%.0f,%.3f,%.3f,%.3f\n",
                            stereo_frames - 1, simulator.time_s(), v.id, v.cls.c_str(), v.sprite.c_str(), v.box.x,
                            v.box.y, v.box.br().x, v.box.br().y, v.visible, v.truncated, v.range_m);
              views += row;
            }
            ++counts["mrpt::obs::CObservationStereoImages"];
          });
      const double t_s = simulator.time_s();
      if (simulator.scanned()) {
        const auto& p = simulator.ego().pose;
        truth.push_back({simulator.stamp(), mrpt::poses::CPose3D(p.x, p.y, 0, p.yaw_rad, 0, 0)});
      }
      if ((k + 1) % 10 == 0) {  // 10 Hz agent truth
        for (const auto& ag : simulator.agents()) {
          char line[256];
          const double vx = ag.speed_mps * std::cos(ag.pose.yaw_rad), vy = ag.speed_mps * std::sin(ag.pose.yaw_rad);
          std::snprintf(line, sizeof(line), "%.2f,%d,%s,%.4f,%.4f,%.5f,%.4f,%.4f,%.4f,%.5f\n", t_s, ag.id,
                        sim::Name(ag.cls), ag.pose.x, ag.pose.y, ag.pose.yaw_rad, vx, vy, ag.speed_mps, ag.yaw_rate);
          csv += line;
          agent_paths[ag.id].push_back({simulator.stamp(), mrpt::poses::CPose3D(ag.pose.x, ag.pose.y, 0, 0, 0, 0)});
          stats[sim::Name(ag.cls)].speed.push_back(ag.speed_mps);
          stats[sim::Name(ag.cls)].turn_rate.push_back(std::abs(ag.yaw_rate));
        }
      }
      if (k % 100 == 0) progress.Update(t_s, t_s / scenario.duration_s);
    }
  }
  progress.Finish();
  rawlog.Close();
  {
    auto t = timer.Time("write");
    io::WriteTum(truth, out + "/ground_truth.tum");
    io::WriteTextAtomically(out + "/agents.csv", csv);
    if (scenario.stereo) io::WriteTextAtomically(out + "/stereo/agents.csv", views);
    const auto grid = simulator.world().TrueGrid(0.05);
    io::WriteRosMap(grid, out + "/true_map.yaml");
    io::WriteMrptGridmap(grid, out + "/true_map.gridmap");
    std::vector<io::PathOverlay> paths{{&truth, {30, 90, 220}, "ego"}};
    for (const auto& [id, path] : agent_paths) paths.push_back({&path, {200, 60, 40}, ""});
    io::WriteMapPng(grid, paths, out + "/world.png");
  }
  io::RunReport report("sim");
  auto& j = report.json();
  j["inputs"] = {
      {"scenario", a.scenario},
      {"name", scenario.name},
      {"seed", scenario.seed},
      {"sprites", sprites ? scenario.stereo->sprites + " (" + std::to_string(sprites->size()) + ")" : "none"},
      {"duration_s", scenario.duration_s}};
  if (InterruptRequested()) report.SetInterrupted(std::to_string(simulator.time_s()) + " s simulated");
  j["counts"] = {{"observations", counts},
                 {"scans", truth.size()},
                 {"agents", scenario.agents.size()},
                 {"stereo_frames", stereo_frames},
                 {"labelled_boxes", labelled_boxes}};
  for (const auto& [cls, s] : stats) {
    j["metrics"]["agents"][cls] = {{"samples", s.speed.size()},
                                   {"speed_mean_mps", Mean(s.speed)},
                                   {"speed_p10_mps", Percentile(s.speed, 0.1)},
                                   {"speed_p90_mps", Percentile(s.speed, 0.9)},
                                   {"turn_rate_mean_rad_s", Mean(s.turn_rate)},
                                   {"turn_rate_p90_rad_s", Percentile(s.turn_rate, 0.9)}};
  }
  j["metrics"]["ego_path_length_m"] = PathLength(truth);
  const double render_s = simulator.render_seconds();
  const double sim_s = timer.TotalMs("simulate") / 1000.0 - render_s;
  if (stereo_frames > 0) j["timing"]["ms_per_stereo_frame"] = 1000.0 * render_s / stereo_frames;
  j["timing"]["stages"] = timer.ToJson();
  j["timing"]["simulated_s_per_wall_s"] = sim_s > 0 ? simulator.time_s() / sim_s : 0.0;
  for (const char* f : {"sim.rawlog", "ground_truth.tum", "true_map.yaml", "true_map.pgm", "true_map.gridmap",
                        "agents.csv", "world.png"}) {
    report.AddOutput(f);
  }
  report.Write(out);
  spdlog::info("sim: {} ({}), seed {}, {:.0f} s simulated, {} scans, ego drove {:.1f} m, {:.0f}x real time",
               scenario.name, a.scenario, scenario.seed, simulator.time_s(), truth.size(), PathLength(truth),
               sim_s > 0 ? simulator.time_s() / sim_s : 0.0);
  return InterruptExitCode();
}

}  // namespace specht::pipeline
