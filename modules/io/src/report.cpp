#include "specht/io/report.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "specht/core/interrupt.h"
#include "specht/core/statistics.h"
#include "specht/io/atomic_file.h"

namespace specht::io {

nlohmann::json Quantiles(const std::vector<double>& values, std::initializer_list<double> levels) {
  nlohmann::json j = {{"count", values.size()}};
  for (double level : levels) j["p" + std::to_string(std::lround(100 * level))] = Percentile(values, level);
  j["max"] = values.empty() ? 0.0 : *std::max_element(values.begin(), values.end());
  return j;
}

StageTimer::Scope::Scope(StageTimer& timer, std::string stage)
    : timer_(timer), stage_(std::move(stage)), start_(std::chrono::steady_clock::now()) {}

StageTimer::Scope::~Scope() {
  timer_.Add(stage_, std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count());
}

void StageTimer::Add(const std::string& stage, double ms) {
  Entry& e = stages_[stage];
  e.total_ms += ms;
  ++e.calls;
}

double StageTimer::TotalMs(const std::string& stage) const {
  auto it = stages_.find(stage);
  return it == stages_.end() ? 0.0 : it->second.total_ms;
}

nlohmann::json StageTimer::ToJson() const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [name, e] : stages_) {
    j[name] = {{"total_ms", e.total_ms}, {"calls", e.calls}, {"ms_per_call", e.calls ? e.total_ms / e.calls : 0.0}};
  }
  return j;
}

RunReport::RunReport(std::string command) {
  json_ = {{"command", std::move(command)},      {"status", "complete"},
           {"inputs", nlohmann::json::object()}, {"counts", nlohmann::json::object()},
           {"timing", nlohmann::json::object()}, {"metrics", nlohmann::json::object()},
           {"outputs", nlohmann::json::array()}};
}

void RunReport::SetIncomplete(const std::string& error) {
  json_["status"] = "incomplete";
  json_["error"] = error;
}

void RunReport::SetInterrupted(const std::string& done) {
  json_["status"] = "interrupted";
  json_["error"] = "interrupted by " + InterruptName() + " after " + done;
}

int RunReport::Ended(const std::string& done, const std::string& stopped) {
  if (InterruptRequested()) {
    SetInterrupted(done);
    return InterruptExitCode();
  }
  if (stopped.empty()) return 0;
  SetIncomplete(stopped);
  spdlog::error("{}: {}", json_.value("command", "run"), stopped);
  return 1;
}

void RunReport::AddOutput(const std::string& file) { json_["outputs"].push_back(file); }

namespace {

std::string Cell(const nlohmann::json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number_float()) {
    std::ostringstream s;
    s.precision(6);
    s << v.get<double>();
    return s.str();
  }
  return v.dump();
}

void Table(std::ostringstream& md, const std::string& title, const nlohmann::json& obj) {
  if (!obj.is_object() || obj.empty()) return;
  md << "\n## " << title << "\n\n| | |\n|---|---|\n";
  for (const auto& [k, v] : obj.items()) {
    if (v.is_object()) {
      for (const auto& [k2, v2] : v.items()) md << "| " << k << "." << k2 << " | " << Cell(v2) << " |\n";
    } else {
      md << "| " << k << " | " << Cell(v) << " |\n";
    }
  }
}

}  // namespace

std::string RunReport::ToMarkdown(const nlohmann::json& r) {
  std::ostringstream md;
  md << "# specht " << r.value("command", "") << " report\n\n";
  md << "Status: **" << r.value("status", "") << "**";
  if (r.contains("error")) md << " — " << r["error"].get<std::string>();
  md << "\n";
  Table(md, "Inputs", r.value("inputs", nlohmann::json::object()));
  Table(md, "Counts", r.value("counts", nlohmann::json::object()));
  Table(md, "Metrics", r.value("metrics", nlohmann::json::object()));
  const auto timing = r.value("timing", nlohmann::json::object());
  if (timing.contains("stages")) {
    md << "\n## Timing\n\n| stage | total ms | calls | ms per call |\n|---|---|---|---|\n";
    for (const auto& [name, s] : timing["stages"].items()) {
      md << "| " << name << " | " << Cell(s["total_ms"]) << " | " << Cell(s["calls"]) << " | " << Cell(s["ms_per_call"])
         << " |\n";
    }
    nlohmann::json rest = timing;
    rest.erase("stages");
    Table(md, "Run", rest);
  }
  const auto outputs = r.value("outputs", nlohmann::json::array());
  if (!outputs.empty()) {
    md << "\n## Outputs\n\n";
    for (const auto& f : outputs) {
      const std::string name = f.get<std::string>();
      if (name.size() > 4 && name.substr(name.size() - 4) == ".png")
        md << "![" << name << "](" << name << ")\n\n";
      else
        md << "- `" << name << "`\n";
    }
  }
  return md.str();
}

void RunReport::Write(const std::string& dir) const {
  WriteTextAtomically(dir + "/report.json", json_.dump(2) + "\n");
  WriteTextAtomically(dir + "/report.md", ToMarkdown(json_));
}

}  // namespace specht::io
