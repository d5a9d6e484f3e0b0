#include "specht/tune/tune_file.h"

#include <signal.h>

#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "specht/core/error.h"
#include "specht/core/interrupt.h"
#include "specht/core/process.h"

namespace specht::tune {
namespace {

std::vector<std::string> Words(const std::string& line) {
  std::vector<std::string> w;
  std::stringstream ss(line);
  for (std::string x; ss >> x;) w.push_back(x);
  return w;
}

void Flatten(const nlohmann::json& j, const std::string& prefix, std::vector<std::string>& out) {
  if (j.is_number()) out.push_back(prefix);
  if (j.is_object())
    for (const auto& [k, v] : j.items()) Flatten(v, prefix.empty() ? k : prefix + "." + k, out);
}

}  // namespace

TuneFile LoadTuneFile(const std::string& path, const std::vector<params::ParamInfo>& declared) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw InputError(path + ": cannot open the tune file");
  } catch (const YAML::Exception& e) {
    throw InputError(path + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  if (!root.IsMap()) throw InputError(path + ": a tune file is a YAML map (run, metric, parameters, search, …)");
  TuneFile t;
  t.path = path;
  const auto at = [&](const YAML::Node& n) { return path + ":" + std::to_string(n.Mark().line + 1) + ": "; };
  try {
    for (const auto& kv : root) {
      const std::string k = kv.first.as<std::string>();
      static const std::vector<std::string> known = {"run",     "report",    "metric",     "goal",
                                                     "repeats", "timeout_s", "parameters", "search"};
      if (std::find(known.begin(), known.end(), k) == known.end())
        throw InputError(at(kv.first) + "unknown field '" + k + "' (run, report, metric, goal, repeats, timeout_s, " +
                         "parameters, search)");
    }
    const YAML::Node run = root["run"];
    if (!run) throw InputError(path + ": 'run' is missing (the command lines of one evaluation)");
    if (run.IsScalar())
      t.commands.push_back(Words(run.as<std::string>()));
    else
      for (const auto& c : run) t.commands.push_back(Words(c.as<std::string>()));
    for (const auto& c : t.commands)
      if (c.empty()) throw InputError(at(run) + "an empty command");
    if (!root["metric"]) throw InputError(path + ": 'metric' is missing (a dotted path into the report JSON)");
    t.metric = root["metric"].as<std::string>();
    if (root["report"]) t.report = root["report"].as<std::string>();
    if (root["goal"]) {
      const std::string g = root["goal"].as<std::string>();
      if (g != "minimise" && g != "maximise" && g != "minimize" && g != "maximize")
        throw InputError(at(root["goal"]) + "goal must be minimise or maximise");
      t.maximise = g.substr(0, 3) == "max";
    }
    if (root["repeats"]) t.repeats = root["repeats"].as<int>();
    if (t.repeats < 1) throw InputError(at(root["repeats"]) + "repeats must be at least 1");
    if (root["timeout_s"]) t.timeout_s = root["timeout_s"].as<double>();
    if (!(t.timeout_s > 0)) throw InputError(at(root["timeout_s"]) + "timeout_s must be positive");
    if (const YAML::Node s = root["search"]) {
      std::stringstream yaml;
      yaml << s;
      t.search = params::FromYaml<SearchOptions>(yaml.str(), path + " (search)");
    }
  } catch (const YAML::Exception& e) {
    throw InputError(path + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  t.space = SearchSpace::FromTuneFile(declared, root["parameters"], path);
  return t;
}

double MetricFromReport(const std::string& report_path, const std::string& metric) {
  std::ifstream f(report_path);
  if (!f) throw InputError(report_path + ": no report (did the run write it there?)");
  nlohmann::json j;
  try {
    f >> j;
  } catch (const std::exception& e) {
    throw InputError(report_path + ": not JSON: " + e.what());
  }
  const nlohmann::json* node = &j;
  std::stringstream parts(metric);
  for (std::string part; std::getline(parts, part, '.');) {
    if (!node->is_object() || !node->contains(part)) {
      node = nullptr;
      break;
    }
    node = &(*node)[part];
  }
  if (node && node->is_number()) return node->get<double>();
  std::vector<std::string> numeric;
  Flatten(j, "", numeric);
  const std::string nearest = params::NearestKey(metric, numeric, SIZE_MAX - 1);
  throw InputError(report_path + ": no number at '" + metric + "'" +
                   (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)"));
}

ProcessResult RunProcess(const std::vector<std::string>& argv, const std::string& log_path, double timeout_s) {
  ChildProcess child(argv, log_path);
  ProcessResult r;
  while (!child.Poll()) {
    if (InterruptRequested() && !r.interrupted) {
      child.Signal(SIGTERM);
      r.interrupted = true;
      timeout_s = std::min(timeout_s, child.seconds() + 5.0);  // then SIGKILL below
    }
    if (child.seconds() > timeout_s) {
      r.timed_out = !r.interrupted;
      child.WaitOrKill(0);
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  r.exit_code = *child.Poll();
  r.seconds = child.seconds();
  return r;
}

}  // namespace specht::tune
