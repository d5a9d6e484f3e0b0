#include "internal/stack_link.h"

namespace specht::pipeline::internal {
namespace {

class Local : public StackLink {
 public:
  Local(const sim::Scenario& scenario, uint64_t seed, const std::vector<decide::Goal>& mission,
        const ClosedLoopConfig& config, Stamp start, ClosedLoopResult& r, OnTracks on_tracks)
      : stack_(scenario, seed, mission, config, start, r), on_tracks_(std::move(on_tracks)) {}

  void Observe(Stamp t, double t_s, const mrpt::obs::CObservation::Ptr& observation) override {
    stack_.Observe(t, t_s, observation);
  }
  void Detections(std::vector<types::Obstacle> in_car, Stamp stamp) override {
    on_tracks_(stamp, stack_.Detections(std::move(in_car), stamp));
  }
  void OracleEgo(const sim::Pose2& truth) override { stack_.OracleEgo(truth); }
  void OracleAgents(const std::vector<sim::AgentTruth>& agents, Stamp stamp) override {
    on_tracks_(stamp, stack_.OracleAgents(agents, stamp));
  }
  StackDecision Control(double t_s, Stamp stamp, double speed_mps, double steer_rad) override {
    const plan::Command command = stack_.Control(t_s, stamp, speed_mps, steer_rad);
    return {command, stack_.Believed(), stack_.state(), stack_.tracks_seen(), stack_.OnLocalPath(), stack_.Final()};
  }
  void Finish(double t_s, Stamp end, const std::string& time_limit, ClosedLoopResult&) override {
    if (!time_limit.empty()) stack_.TimeLimit(t_s, time_limit);
    stack_.Finish(end);
  }
  LoopStack* local() override { return &stack_; }

 private:
  LoopStack stack_;
  OnTracks on_tracks_;
};

nlohmann::json PathToJson(const plan::Path& path) {
  nlohmann::json points = nlohmann::json::array();
  for (const auto& p : path.points) points.push_back({p.pose.x, p.pose.y, p.pose.theta, p.direction});
  return points;
}

plan::Path PathFromJson(const nlohmann::json& points) {
  plan::Path path;
  for (const auto& p : points)
    path.points.push_back({{p[0].get<double>(), p[1].get<double>(), p[2].get<double>()}, p[3].get<int>()});
  return path;
}

}  // namespace

std::unique_ptr<StackLink> LocalStackLink(const sim::Scenario& scenario, uint64_t seed,
                                          const std::vector<decide::Goal>& mission, const ClosedLoopConfig& config,
                                          Stamp start, ClosedLoopResult& r, StackLink::OnTracks on_tracks) {
  return std::make_unique<Local>(scenario, seed, mission, config, start, r, std::move(on_tracks));
}

// Every field LoopStack writes, as the values themselves (doubles print exactly in
// nlohmann's JSON), so that the run merging them reports what an in-process run does.
nlohmann::json StackFiguresToJson(const ClosedLoopResult& r) {
  nlohmann::json transitions = nlohmann::json::array(), paths = nlohmann::json::array();
  for (const auto& t : r.transitions) transitions.push_back({t.t_s, t.from, t.to, t.reason});
  for (const auto& p : r.paths) paths.push_back(PathToJson(p));
  const auto& l = r.local;
  return {{"success", r.success},
          {"failure", r.failure},
          {"believed_park_error_m", r.believed_park_error_m},
          {"believed_park_error_deg", r.believed_park_error_deg},
          {"plan_ms", r.plan_ms},
          {"limited_s", r.limited_s},
          {"map_replans", r.map_replans},
          {"local",
           {{"calls", l.calls},
            {"found", l.found},
            {"skipped", l.skipped},
            {"failed", l.failed},
            {"ms", l.ms},
            {"max_iterations", l.max_iterations},
            {"over_budget", l.over_budget},
            {"driving_s", l.driving_s},
            {"on_local_s", l.on_local_s},
            {"on_manoeuvre_s", l.on_manoeuvre_s},
            {"failures", l.failures}}},
          {"stage_ms", r.stage_ms},
          {"transitions", transitions},
          {"paths", paths},
          {"stack", r.stack},
          {"static_layer", r.static_layer},
          {"mcap", r.mcap},
          {"localization", r.localization},
          {"perception", r.perception}};
}

void StackFiguresFromJson(const nlohmann::json& j, ClosedLoopResult& r) {
  r.success = j.at("success").get<bool>();
  if (r.failure.empty()) r.failure = j.at("failure").get<std::string>();
  r.believed_park_error_m = j.at("believed_park_error_m").get<double>();
  r.believed_park_error_deg = j.at("believed_park_error_deg").get<double>();
  r.plan_ms = j.at("plan_ms").get<std::vector<double>>();
  r.limited_s = j.at("limited_s").get<std::map<std::string, double>>();
  r.map_replans = j.at("map_replans").get<int>();
  const auto& l = j.at("local");
  r.local.calls = l.at("calls").get<int>(), r.local.found = l.at("found").get<int>();
  r.local.skipped = l.at("skipped").get<int>(), r.local.failed = l.at("failed").get<int>();
  r.local.ms = l.at("ms").get<std::vector<double>>();
  r.local.max_iterations = l.at("max_iterations").get<long>(), r.local.over_budget = l.at("over_budget").get<int>();
  r.local.driving_s = l.at("driving_s").get<double>(), r.local.on_local_s = l.at("on_local_s").get<double>();
  r.local.on_manoeuvre_s = l.at("on_manoeuvre_s").get<double>();
  r.local.failures = l.at("failures").get<std::map<std::string, int>>();
  for (const auto& [stage, ms] : j.at("stage_ms").items()) r.stage_ms[stage] += ms.get<double>();
  r.transitions.clear();
  for (const auto& t : j.at("transitions"))
    r.transitions.push_back(
        {t[0].get<double>(), t[1].get<std::string>(), t[2].get<std::string>(), t[3].get<std::string>()});
  r.paths.clear();
  for (const auto& p : j.at("paths")) r.paths.push_back(PathFromJson(p));
  r.stack = j.at("stack").get<std::string>();
  r.static_layer = j.at("static_layer").get<std::string>();
  r.mcap = j.at("mcap").get<std::string>();
  r.localization = j.at("localization");
  r.perception = j.at("perception");
}

}  // namespace specht::pipeline::internal
