#include "specht/sim/scenario.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "internal/geometry.h"
#include "specht/core/error.h"
#include "specht/core/params.h"

namespace specht::sim {

const char* Name(AgentClass c) {
  switch (c) {
    case AgentClass::kPedestrian:
      return "pedestrian";
    case AgentClass::kCyclist:
      return "cyclist";
    case AgentClass::kCar:
      return "car";
  }
  return "?";
}

namespace {

using internal::InsidePolygon;
using internal::SegmentsCross;

// Reads YAML maps key by key, collecting one message per problem.
class Reader {
 public:
  Reader(std::string file, std::vector<std::string>& errors) : file_(std::move(file)), errors_(errors) {}

  // `at` may be a key that is not there (an invalid node, which has no line).
  void Error(const YAML::Node& at, const std::string& key, const std::string& why) {
    errors_.push_back(Where(file_, at.IsDefined() ? at.Mark().line + 1 : 0) + key + ": " + why);
  }

  // Every key of `map` must be one of `allowed`.
  bool Map(const YAML::Node& map, const std::string& ctx, const std::set<std::string>& allowed) {
    if (!map.IsMap()) {
      Error(map, ctx, "expected a map");
      return false;
    }
    for (const auto& kv : map) {
      const std::string key = kv.first.Scalar();
      if (allowed.count(key) != 0) continue;
      std::string why = "unknown key";
      const std::string nearest = params::NearestKey(key, {allowed.begin(), allowed.end()});
      if (!nearest.empty()) why += " (did you mean '" + nearest + "'?)";
      Error(kv.first, Join(ctx, key), why);
    }
    return true;
  }

  double Number(const YAML::Node& map, const std::string& ctx, const char* key, double fallback, double min,
                double max) {
    const YAML::Node n = map[key];
    if (!n) return fallback;
    double v = fallback;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      Error(n, Join(ctx, key),
            "expected a number, got '" +
                (n.IsScalar() ? n.Scalar() : std::string("a ") + (n.IsMap() ? "map" : "list")) + "'");
      return fallback;
    }
    if (!std::isfinite(v) || v < min || v > max) {
      std::ostringstream why;
      why << "value " << v << " is outside [" << min << ", " << max << "]";
      Error(n, Join(ctx, key), why.str());
      return fallback;
    }
    return v;
  }

  std::string String(const YAML::Node& map, const std::string& ctx, const char* key, const std::string& fallback,
                     const std::set<std::string>& choices = {}) {
    const YAML::Node n = map[key];
    if (!n) return fallback;
    if (!n.IsScalar()) {
      Error(n, Join(ctx, key), "expected a string");
      return fallback;
    }
    if (!choices.empty() && choices.count(n.Scalar()) == 0) {
      std::string list;
      for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
      Error(n, Join(ctx, key), "'" + n.Scalar() + "' is not one of: " + list);
      return fallback;
    }
    return n.Scalar();
  }

  bool Bool(const YAML::Node& map, const std::string& ctx, const char* key, bool fallback) {
    const YAML::Node n = map[key];
    if (!n) return fallback;
    try {
      return n.as<bool>();
    } catch (const YAML::Exception&) {
      Error(n, Join(ctx, key), "expected true or false");
      return fallback;
    }
  }

  // `n` is a list (of entries named `what`); else an error and false.
  bool List(const YAML::Node& n, const std::string& ctx, const std::string& what) {
    if (n.IsSequence()) return true;
    Error(n, ctx, "expected a list of " + what);
    return false;
  }

  // A list of exactly `count` finite numbers (`layout` names them for the message).
  bool Numbers(const YAML::Node& n, const std::string& ctx, size_t count, const std::string& layout,
               std::vector<double>& out) {
    if (!n.IsSequence() || n.size() != count) {
      Error(n, ctx, "expected " + layout);
      return false;
    }
    out.clear();
    try {
      for (size_t i = 0; i < count; ++i) out.push_back(n[i].as<double>());
    } catch (const YAML::Exception&) {
      Error(n, ctx, "expected " + layout + ": " + std::to_string(count) + " numbers");
      return false;
    }
    for (double v : out)
      if (!std::isfinite(v)) {
        Error(n, ctx, "numbers must be finite");
        return false;
      }
    return true;
  }

  // One [x, y] point.
  bool Point(const YAML::Node& p, const std::string& ctx, Vec2& out) {
    if (!p || !p.IsSequence() || p.size() != 2) {
      Error(p, ctx, "expected [x, y]");
      return false;
    }
    try {
      out = {p[0].as<double>(), p[1].as<double>()};
    } catch (const YAML::Exception&) {
      Error(p, ctx, "expected two numbers");
      return false;
    }
    if (!std::isfinite(out.x) || !std::isfinite(out.y)) {
      Error(p, ctx, "coordinates must be finite");
      return false;
    }
    return true;
  }

  // A list of [x, y] points.
  std::vector<Vec2> Points(const YAML::Node& n, const std::string& ctx) {
    std::vector<Vec2> out;
    if (!n.IsSequence()) {
      Error(n, ctx, "expected a list of [x, y] points");
      return out;
    }
    for (size_t i = 0; i < n.size(); ++i) {
      Vec2 v;
      if (Point(n[i], ctx + "[" + std::to_string(i) + "]", v)) out.push_back(v);
    }
    return out;
  }

  // [x, y, yaw_deg]
  Pose2 Pose(const YAML::Node& map, const std::string& ctx, const char* key, Pose2 fallback) {
    const YAML::Node n = map[key];
    if (!n) return fallback;
    if (!n.IsSequence() || n.size() != 3) {
      Error(n, Join(ctx, key), "expected [x_m, y_m, yaw_deg]");
      return fallback;
    }
    try {
      return {n[0].as<double>(), n[1].as<double>(), n[2].as<double>() * internal::kDeg};
    } catch (const YAML::Exception&) {
      Error(n, Join(ctx, key), "expected three numbers");
      return fallback;
    }
  }

  static std::string Join(const std::string& ctx, const std::string& key) {
    return ctx.empty() ? key : ctx + "." + key;
  }

 private:
  std::string file_;
  std::vector<std::string>& errors_;
};

bool SelfIntersects(const std::vector<Vec2>& p, bool closed) {
  const size_t n = p.size(), edges = closed ? n : n - 1;
  for (size_t i = 0; i < edges; ++i) {
    for (size_t j = i + 1; j < edges; ++j) {
      if (j == i + 1 || (closed && i == 0 && j == n - 1)) continue;  // neighbours share a corner
      if (SegmentsCross(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n])) return true;
    }
  }
  return false;
}

// Reports route legs (a straight line between consecutive waypoints, and the closing
// leg of a looped route) that cross or enter a closed object.
void CheckRouteClear(Reader& r, const YAML::Node& node, const std::string& ctx, const std::vector<Waypoint>& route,
                     bool loop, const std::vector<StaticObject>& objects) {
  const size_t legs = loop ? route.size() : route.size() - 1;
  for (size_t k = 0; k < legs && route.size() >= 2; ++k) {
    const Vec2 a = route[k].p, b = route[(k + 1) % route.size()].p;
    for (size_t o = 0; o < objects.size(); ++o) {
      const auto& poly = objects[o].polygon;
      if (!objects[o].closed) continue;
      bool blocked = InsidePolygon(poly, a) || InsidePolygon(poly, b);
      for (size_t i = 0; i < poly.size() && !blocked; ++i)
        blocked = SegmentsCross(a, b, poly[i], poly[(i + 1) % poly.size()]);
      if (blocked) {
        r.Error(node, ctx,
                "leg " + std::to_string(k) + " -> " + std::to_string((k + 1) % route.size()) +
                    " passes through world.objects[" + std::to_string(o) + "]");
        return;
      }
    }
  }
}

std::vector<Waypoint> Route(Reader& r, const YAML::Node& n, const std::string& ctx) {
  std::vector<Waypoint> route;
  if (!n) return route;
  if (!n.IsSequence()) {
    r.Error(n, ctx, "expected a list of waypoints [x, y] or {at: [x, y], stop: true}");
    return route;
  }
  for (size_t i = 0; i < n.size(); ++i) {
    const std::string at = ctx + "[" + std::to_string(i) + "]";
    Vec2 p;
    if (n[i].IsMap()) {
      r.Map(n[i], at, {"at", "stop"});
      if (r.Point(n[i]["at"], at + ".at", p)) route.push_back({p, r.Bool(n[i], at, "stop", false)});
    } else if (r.Point(n[i], at, p)) {
      route.push_back({p, false});
    }
  }
  return route;
}

}  // namespace

Scenario ParseScenario(const std::string& text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(Where(source, e.mark.line + 1) + "YAML syntax error: " + e.msg);
  }
  std::vector<std::string> errors;
  Reader r(source, errors);
  Scenario s;
  s.path = source;
  if (!r.Map(root, "", {"name", "seed", "duration_s", "world", "ego", "agents", "sensors"})) {
    throw InputError(errors.front());
  }
  s.name = r.String(root, "", "name", "unnamed");
  s.seed = static_cast<uint64_t>(r.Number(root, "", "seed", 1, 0, 4e18));
  s.duration_s = r.Number(root, "", "duration_s", 60, 0.1, 86400);

  // world
  if (const YAML::Node w = root["world"]; w && r.Map(w, "world", {"bounds", "objects", "parking_bays"})) {
    std::vector<double> v;
    if (const YAML::Node b = w["bounds"]; b && r.Numbers(b, "world.bounds", 4, "[xmin, ymin, xmax, ymax]", v)) {
      for (int i = 0; i < 4; ++i) s.bounds[i] = v[i];
      if (s.bounds[2] <= s.bounds[0] || s.bounds[3] <= s.bounds[1]) r.Error(b, "world.bounds", "empty area");
    }
    const std::map<std::string, ObjectType> types = {{"wall", ObjectType::kWall},
                                                     {"parked_car", ObjectType::kParkedCar},
                                                     {"cone", ObjectType::kCone},
                                                     {"boundary", ObjectType::kBoundary},
                                                     {"building", ObjectType::kBuilding}};
    if (const YAML::Node objects = w["objects"]; objects && r.List(objects, "world.objects", "objects")) {
      for (size_t i = 0; i < objects.size(); ++i) {
        const YAML::Node o = objects[i];
        const std::string ctx = "world.objects[" + std::to_string(i) + "]";
        if (!r.Map(o, ctx, {"type", "polygon", "polyline", "height_m", "texture"})) continue;
        StaticObject obj;
        obj.type = types.at(r.String(o, ctx, "type", "wall", {"wall", "parked_car", "cone", "boundary", "building"}));
        obj.closed = !o["polyline"];
        const YAML::Node shape = obj.closed ? o["polygon"] : o["polyline"];
        if (!shape) {
          r.Error(o, ctx, "needs a 'polygon' (closed) or a 'polyline' (open)");
          continue;
        }
        obj.polygon = r.Points(shape, ctx + (obj.closed ? ".polygon" : ".polyline"));
        if (obj.polygon.size() < (obj.closed ? 3u : 2u)) {
          r.Error(shape, ctx, obj.closed ? "a polygon needs at least 3 points" : "a polyline needs at least 2 points");
        } else if (SelfIntersects(obj.polygon, obj.closed)) {
          r.Error(shape, ctx + (obj.closed ? ".polygon" : ".polyline"), "self-intersecting");
        }
        obj.height_m = r.Number(o, ctx, "height_m", 1.0, 0.01, 100);
        obj.texture = r.String(o, ctx, "texture", "noise", {"noise", "bricks", "stripes", "checker", "plain"});
        s.objects.push_back(std::move(obj));
      }
    }
    if (const YAML::Node bays = w["parking_bays"]; bays && r.List(bays, "world.parking_bays", "bays")) {
      for (size_t i = 0; i < bays.size(); ++i) {
        const std::string ctx = "world.parking_bays[" + std::to_string(i) + "]";
        if (!r.Map(bays[i], ctx, {"name", "pose", "size_m"})) continue;
        ParkingBay bay;
        bay.name = r.String(bays[i], ctx, "name", "bay" + std::to_string(i));
        bay.pose = r.Pose(bays[i], ctx, "pose", {});
        if (const YAML::Node size = bays[i]["size_m"];
            size && r.Numbers(size, ctx + ".size_m", 2, "[length_m, width_m]", v)) {
          bay.length_m = v[0], bay.width_m = v[1];
        }
        s.bays.push_back(bay);
      }
    }
  }
  auto inside = [&](Vec2 p) {
    return p.x >= s.bounds[0] && p.x <= s.bounds[2] && p.y >= s.bounds[1] && p.y <= s.bounds[3];
  };

  // ego
  if (const YAML::Node e = root["ego"];
      e && r.Map(e, "ego",
                 {"wheelbase_m", "max_steer_deg", "max_speed_mps", "max_accel_mps2", "length_m", "width_m",
                  "rear_overhang_m", "start", "route", "cruise_speed_mps", "loop"})) {
    VehicleModel& m = s.ego.model;
    m.wheelbase_m = r.Number(e, "ego", "wheelbase_m", m.wheelbase_m, 0.2, 10);
    m.max_steer_rad = r.Number(e, "ego", "max_steer_deg", 30, 1, 80) * internal::kDeg;
    m.max_speed_mps = r.Number(e, "ego", "max_speed_mps", m.max_speed_mps, 0, 60);
    m.max_accel_mps2 = r.Number(e, "ego", "max_accel_mps2", m.max_accel_mps2, 0.1, 20);
    m.length_m = r.Number(e, "ego", "length_m", m.length_m, 0.3, 20);
    m.width_m = r.Number(e, "ego", "width_m", m.width_m, 0.2, 5);
    m.rear_overhang_m = r.Number(e, "ego", "rear_overhang_m", m.length_m / 2, 0, 10);
    if (m.rear_overhang_m >= m.length_m)
      r.Error(e["rear_overhang_m"], "ego.rear_overhang_m", "must be shorter than length_m");
    s.ego.start = r.Pose(e, "ego", "start", {});
    s.ego.route = Route(r, e["route"], "ego.route");
    s.ego.cruise_speed_mps = r.Number(e, "ego", "cruise_speed_mps", 3, 0, 60);
    s.ego.loop = r.Bool(e, "ego", "loop", true);
    if (s.ego.cruise_speed_mps > m.max_speed_mps) {
      r.Error(e["cruise_speed_mps"], "ego.cruise_speed_mps", "above max_speed_mps");
    }
    if (!inside({s.ego.start.x, s.ego.start.y})) r.Error(e["start"], "ego.start", "outside the world bounds");
    for (size_t i = 0; i < s.ego.route.size(); ++i) {
      if (!inside(s.ego.route[i].p))
        r.Error(e["route"][i], "ego.route[" + std::to_string(i) + "]", "outside the world bounds");
    }
    std::vector<Waypoint> with_start = s.ego.route;
    with_start.insert(with_start.begin(), Waypoint{{s.ego.start.x, s.ego.start.y}, false});
    if (e["route"]) CheckRouteClear(r, e["route"], "ego.route", with_start, false, s.objects);
  }

  // agents
  if (const YAML::Node agents = root["agents"]; agents && r.List(agents, "agents", "agents")) {
    std::set<int> ids;
    for (size_t i = 0; i < agents.size(); ++i) {
      const YAML::Node a = agents[i];
      const std::string ctx = "agents[" + std::to_string(i) + "]";
      if (!r.Map(a, ctx, {"id", "class", "route", "start_s", "loop", "max_speed_mps", "sprite"})) continue;
      AgentSpec spec;
      spec.id = static_cast<int>(r.Number(a, ctx, "id", static_cast<double>(i + 1), 0, 1e6));
      if (!ids.insert(spec.id).second)
        r.Error(a["id"], ctx + ".id", "id " + std::to_string(spec.id) + " is used twice");
      const std::string cls = r.String(a, ctx, "class", "pedestrian", {"pedestrian", "cyclist", "car"});
      spec.cls = cls == "car" ? AgentClass::kCar : cls == "cyclist" ? AgentClass::kCyclist : AgentClass::kPedestrian;
      spec.route = Route(r, a["route"], ctx + ".route");
      if (spec.route.size() < 2) r.Error(a, ctx + ".route", "needs at least 2 waypoints");
      for (size_t k = 0; k < spec.route.size(); ++k) {
        if (!inside(spec.route[k].p)) {
          r.Error(a["route"][k], ctx + ".route[" + std::to_string(k) + "]", "agent outside the world bounds");
        }
      }
      spec.start_s = r.Number(a, ctx, "start_s", 0, 0, 86400);
      spec.loop = r.Bool(a, ctx, "loop", false);
      spec.max_speed_mps = r.Number(a, ctx, "max_speed_mps", 0, 0, 60);
      spec.sprite = r.String(a, ctx, "sprite", "");
      if (a["route"]) CheckRouteClear(r, a["route"], ctx + ".route", spec.route, spec.loop, s.objects);
      s.agents.push_back(std::move(spec));
    }
  }

  // sensors
  if (const YAML::Node sn = root["sensors"]; sn && r.Map(sn, "sensors", {"lidar", "odometry", "imu", "stereo"})) {
    if (const YAML::Node st = sn["stereo"];
        st &&
        r.Map(st, "sensors.stereo", {"rate_hz", "width", "height", "focal_px", "baseline_m", "mount", "sprites"})) {
      StereoSpec x;
      const std::string ctx = "sensors.stereo";
      x.rate_hz = r.Number(st, ctx, "rate_hz", x.rate_hz, 0.1, 60);
      x.width = static_cast<int>(r.Number(st, ctx, "width", x.width, 16, 4096));
      x.height = static_cast<int>(r.Number(st, ctx, "height", x.height, 16, 4096));
      x.focal_px = r.Number(st, ctx, "focal_px", x.focal_px, 10, 10000);
      x.baseline_m = r.Number(st, ctx, "baseline_m", x.baseline_m, 0.01, 5);
      x.sprites = r.String(st, ctx, "sprites", x.sprites, {"tuning", "held_out", "all"});
      std::vector<double> m;
      if (const YAML::Node n = st["mount"];
          n && r.Numbers(n, ctx + ".mount", 5, "[x_m, y_m, z_m, yaw_deg, pitch_deg]", m)) {
        x.x_m = m[0], x.y_m = m[1], x.z_m = m[2];
        x.yaw_rad = m[3] * internal::kDeg, x.pitch_rad = m[4] * internal::kDeg;
      }
      s.stereo = x;
    }
    if (const YAML::Node l = sn["lidar"];
        l && r.Map(l, "sensors.lidar",
                   {"rate_hz", "beams", "fov_deg", "max_range_m", "range_noise_m", "dropout", "mount"})) {
      LidarSpec& x = s.lidar;
      x.rate_hz = r.Number(l, "sensors.lidar", "rate_hz", x.rate_hz, 0.1, 100);
      x.beams = static_cast<int>(r.Number(l, "sensors.lidar", "beams", x.beams, 2, 10000));
      x.fov_rad = r.Number(l, "sensors.lidar", "fov_deg", 180, 1, 360) * internal::kDeg;
      x.max_range_m = r.Number(l, "sensors.lidar", "max_range_m", x.max_range_m, 0.5, 500);
      x.range_noise_m = r.Number(l, "sensors.lidar", "range_noise_m", x.range_noise_m, 0, 5);
      x.dropout = r.Number(l, "sensors.lidar", "dropout", x.dropout, 0, 1);
      x.mount = r.Pose(l, "sensors.lidar", "mount", {});
    }
    if (const YAML::Node o = sn["odometry"];
        o && r.Map(o, "sensors.odometry", {"rate_hz", "translation_noise", "rotation_noise", "rotation_per_metre"})) {
      OdometrySpec& x = s.odometry;
      x.rate_hz = r.Number(o, "sensors.odometry", "rate_hz", x.rate_hz, 0.1, 100);
      x.translation_noise = r.Number(o, "sensors.odometry", "translation_noise", x.translation_noise, 0, 1);
      x.rotation_noise = r.Number(o, "sensors.odometry", "rotation_noise", x.rotation_noise, 0, 1);
      x.rotation_per_metre = r.Number(o, "sensors.odometry", "rotation_per_metre", x.rotation_per_metre, -1, 1);
    }
    if (const YAML::Node m = sn["imu"];
        m && r.Map(m, "sensors.imu", {"rate_hz", "gyro_noise_rad_s", "gyro_bias_rad_s", "accel_noise_mps2"})) {
      ImuSpec& x = s.imu;
      x.rate_hz = r.Number(m, "sensors.imu", "rate_hz", x.rate_hz, 1, 100);
      x.gyro_noise_rad_s = r.Number(m, "sensors.imu", "gyro_noise_rad_s", x.gyro_noise_rad_s, 0, 1);
      x.gyro_bias_rad_s = r.Number(m, "sensors.imu", "gyro_bias_rad_s", x.gyro_bias_rad_s, -1, 1);
      x.accel_noise_mps2 = r.Number(m, "sensors.imu", "accel_noise_mps2", x.accel_noise_mps2, 0, 10);
    }
  }
  if (!errors.empty()) {
    std::string all;
    for (const auto& e : errors) all += (all.empty() ? "" : "\n") + e;
    throw InputError(all);
  }
  return s;
}

Scenario LoadScenario(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read scenario file");
  std::stringstream text;
  text << in.rdbuf();
  return ParseScenario(text.str(), path);
}

}  // namespace specht::sim
