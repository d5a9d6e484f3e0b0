// The DDS transport (net/dds.h) on this machine's loopback: ROS 2's names, messages
// that arrive as they were sent (the same CDR bytes io/ros_messages encodes for bags
// and MCAP), the latched map a late joiner still gets, a payload that is not its type
// refused, and a configuration that sends nothing beyond this machine. Every test
// uses its own domain and topics (the process id), so parallel test processes never
// see each other.
#include "specht/net/dds.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>

#include "specht/core/error.h"
#include "specht/io/ros_messages.h"
#include "test_support.h"

namespace specht {
namespace {

using std::chrono::milliseconds;

net::Options LoopbackOptions() {
  net::Options o;
  o.domain = 1 + static_cast<int>(getpid() % 200);
  return o;
}

std::string Unique(const std::string& topic) { return topic + "_" + std::to_string(getpid()); }

io::ros::Header HeaderAt(int64_t ns, const std::string& frame) { return {Stamp{ns}, frame}; }

io::ros::LaserScan Scan() {
  io::ros::LaserScan s;
  s.header = HeaderAt(1700000000123456789LL, "laser");
  s.angle_min = -2.35619f;
  s.angle_max = 2.35619f;
  s.angle_increment = 4.71239f / 1079;
  s.time_increment = 1e-5f;
  s.scan_time = 0.025f;
  s.range_min = 0.1f;
  s.range_max = 30.f;
  for (int i = 0; i < 1080; ++i) {
    s.ranges.push_back(1.f + 0.01f * static_cast<float>(i));
    s.intensities.push_back(static_cast<float>(i % 7));
  }
  return s;
}

io::ros::Odometry Odom() {
  io::ros::Odometry o;
  o.header = HeaderAt(1700000000500000000LL, "odom");
  o.child_frame_id = "base_link";
  o.pose = {1.5, -2.25, 0, 0, 0, std::sin(0.3), std::cos(0.3)};
  for (int i = 0; i < 36; ++i) o.pose_covariance[i] = i % 7 == 0 ? 0.01 * (i + 1) : 0;
  o.vx = 0.8;
  o.wz = -0.1;
  for (int i = 0; i < 36; ++i) o.twist_covariance[i] = i % 7 == 0 ? 0.001 : 0;
  return o;
}

io::ros::OccupancyGrid Grid(int8_t fill, uint32_t width) {
  io::ros::OccupancyGrid g;
  g.header = HeaderAt(1700000001000000000LL, "map");
  g.map_load_time = Stamp{1700000000000000000LL};
  g.resolution = 0.05f;
  g.width = width;
  g.height = 3;  // an odd byte count: the CDR ends off a 4-byte boundary
  g.origin = {-10, -5, 0, 0, 0, 0, 1};
  g.data.assign(width * g.height, fill);
  g.data[0] = -1;
  return g;
}

std::vector<io::ros::TransformStamped> Tf() {
  return {{HeaderAt(1700000000200000000LL, "map"), "odom", {0.5, 0.25, 0, 0, 0, 0.0998, 0.995}},
          {HeaderAt(1700000000200000000LL, "odom"), "base_link", {3, 4, 0, 0, 0, 0, 1}}};
}

io::ros::Path PathOf(int n) {
  io::ros::Path p;
  p.header = HeaderAt(1700000002000000000LL, "map");
  for (int i = 0; i < n; ++i)
    p.poses.push_back({HeaderAt(1700000000000000000LL + i * 100000000LL, "map"), {0.1 * i, 0.05 * i, 0, 0, 0, 0, 1}});
  return p;
}

// What arrives equals what was sent, up to what the CDR encapsulation allows a
// writer to add: the options field and the padding to a 4-byte boundary it counts.
void ExpectSameCdr(const std::vector<uint8_t>& sent, const std::vector<uint8_t>& received, const std::string& what) {
  ASSERT_GE(received.size(), sent.size()) << what;
  EXPECT_EQ(received[0], sent[0]) << what;
  EXPECT_EQ(received[1], sent[1]) << what;
  const size_t padding = received[3] & 3u;
  EXPECT_EQ(received.size() - padding, sent.size()) << what;
  EXPECT_TRUE(std::equal(sent.begin() + 4, sent.end(), received.begin() + 4)) << what;
}

TEST(DdsNamesTest, TopicsAndTypesFollowRos2sDdsMapping) {
  EXPECT_EQ(net::DdsTopicName("/scan"), "rt/scan");
  EXPECT_EQ(net::DdsTopicName("/robot1/map"), "rt/robot1/map");
  EXPECT_EQ(net::DdsTypeName("sensor_msgs/msg/LaserScan"), "sensor_msgs::msg::dds_::LaserScan_");
  EXPECT_EQ(net::DdsTypeName("nav_msgs/msg/Odometry"), "nav_msgs::msg::dds_::Odometry_");
  EXPECT_EQ(net::DdsTypeName("nav_msgs/msg/OccupancyGrid"), "nav_msgs::msg::dds_::OccupancyGrid_");
  EXPECT_EQ(net::DdsTypeName("nav_msgs/msg/Path"), "nav_msgs::msg::dds_::Path_");
  EXPECT_EQ(net::DdsTypeName("tf2_msgs/msg/TFMessage"), "tf2_msgs::msg::dds_::TFMessage_");
  EXPECT_EQ(net::DdsTypeName("rosgraph_msgs/msg/Clock"), "rosgraph_msgs::msg::dds_::Clock_");
  EXPECT_THROW(net::DdsTopicName("scan"), InputError);
  EXPECT_THROW(net::DdsTypeName("sensor_msgs/msg/Image"), InputError);
}

TEST(DdsTest, MessagesArriveAsTheBytesIoEncodes) {
  net::Participant out(LoopbackOptions()), in(LoopbackOptions());
  const std::vector<std::tuple<std::string, std::string, net::Qos, std::vector<uint8_t>>> cases = {
      {"/scan", "sensor_msgs/msg/LaserScan", net::Qos::kSensorData, io::ros::Encode(Scan())},
      {"/odom", "nav_msgs/msg/Odometry", net::Qos::kDefault, io::ros::Encode(Odom())},
      {"/map", "nav_msgs/msg/OccupancyGrid", net::Qos::kLatched, io::ros::Encode(Grid(100, 7))},
      {"/tf", "tf2_msgs/msg/TFMessage", net::Qos::kDefault, io::ros::Encode(Tf())},
      {"/path", "nav_msgs/msg/Path", net::Qos::kDefault, io::ros::Encode(PathOf(25))},
  };
  for (const auto& [topic, type, qos, cdr] : cases) {
    net::Reader reader(in, Unique(topic), type, qos);
    net::Writer writer(out, Unique(topic), type, qos);
    ASSERT_TRUE(writer.WaitForReaders(1, milliseconds(5000))) << topic;
    ASSERT_TRUE(reader.WaitForWriters(1, milliseconds(5000))) << topic;
    writer.Write(cdr, Stamp{1700000003000000000LL});
    ASSERT_TRUE(reader.WaitForData(milliseconds(5000))) << topic;
    const auto samples = reader.Take();
    ASSERT_EQ(samples.size(), 1u) << topic;
    EXPECT_EQ(samples[0].source_time.ns, 1700000003000000000LL) << topic;
    ExpectSameCdr(cdr, samples[0].cdr, topic);
  }
}

TEST(DdsTest, DecodedScanAndOdometryEqualWhatWasSent) {
  net::Participant out(LoopbackOptions()), in(LoopbackOptions());
  net::Reader scans(in, Unique("/scan"), "sensor_msgs/msg/LaserScan", net::Qos::kDefault);
  net::Writer scan_writer(out, Unique("/scan"), "sensor_msgs/msg/LaserScan", net::Qos::kDefault);
  ASSERT_TRUE(scan_writer.WaitForReaders(1, milliseconds(5000)));
  auto sent = Scan();
  sent.ranges[3] = std::numeric_limits<float>::infinity();  // no return, as drivers write it
  for (int i = 0; i < 5; ++i) {
    sent.header.stamp.ns += 25000000;
    scan_writer.Write(io::ros::Encode(sent), sent.header.stamp);
  }
  std::vector<net::Sample> got;
  for (int tries = 0; tries < 50 && got.size() < 5; ++tries) {
    if (!scans.WaitForData(milliseconds(100))) continue;
    for (auto& s : scans.Take()) got.push_back(std::move(s));
  }
  ASSERT_EQ(got.size(), 5u);  // reliable, keep last 10: none lost
  const auto last = io::ros::DecodeLaserScan(got.back().cdr);
  EXPECT_EQ(last.header.stamp.ns, sent.header.stamp.ns);
  EXPECT_EQ(last.header.frame_id, "laser");
  EXPECT_EQ(last.ranges, sent.ranges);
  EXPECT_EQ(last.intensities, sent.intensities);
  EXPECT_FLOAT_EQ(last.angle_increment, sent.angle_increment);

  net::Reader odoms(in, Unique("/odom"), "nav_msgs/msg/Odometry", net::Qos::kDefault);
  net::Writer odom_writer(out, Unique("/odom"), "nav_msgs/msg/Odometry", net::Qos::kDefault);
  ASSERT_TRUE(odom_writer.WaitForReaders(1, milliseconds(5000)));
  odom_writer.Write(io::ros::Encode(Odom()), Odom().header.stamp);
  ASSERT_TRUE(odoms.WaitForData(milliseconds(5000)));
  const auto odom = io::ros::DecodeOdometry(odoms.Take().at(0).cdr);
  EXPECT_EQ(odom.child_frame_id, "base_link");
  EXPECT_DOUBLE_EQ(odom.pose.Yaw(), Odom().pose.Yaw());
  EXPECT_EQ(odom.pose_covariance, Odom().pose_covariance);
  EXPECT_DOUBLE_EQ(odom.wz, -0.1);
}

// Transient-local durability: a reader that joins after the map was published gets
// the latest map (keep last 1), not the history and not nothing.
TEST(DdsTest, LateJoinerGetsTheLatestMap) {
  net::Participant out(LoopbackOptions()), in(LoopbackOptions());
  net::Writer maps(out, Unique("/map"), "nav_msgs/msg/OccupancyGrid", net::Qos::kLatched);
  maps.Write(io::ros::Encode(Grid(0, 5)), Stamp{1});
  const auto latest = io::ros::Encode(Grid(100, 9));
  maps.Write(latest, Stamp{2});
  net::Reader late(in, Unique("/map"), "nav_msgs/msg/OccupancyGrid", net::Qos::kLatched);
  ASSERT_TRUE(late.WaitForData(milliseconds(5000)));
  const auto samples = late.Take();
  ASSERT_EQ(samples.size(), 1u);
  EXPECT_EQ(samples[0].source_time.ns, 2);
  ExpectSameCdr(latest, samples[0].cdr, "latest map");
}

TEST(DdsTest, PayloadThatIsNotItsTypeIsRefusedBeforeItIsSent) {
  net::Participant p(LoopbackOptions());
  net::Writer scans(p, Unique("/scan"), "sensor_msgs/msg/LaserScan", net::Qos::kSensorData);
  auto cdr = io::ros::Encode(Scan());
  cdr.resize(cdr.size() / 2);  // ends inside the ranges
  try {
    scans.Write(cdr, Stamp{0});
    FAIL() << "a truncated scan was sent";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not a valid sensor_msgs/msg/LaserScan"), std::string::npos) << e.what();
  }
  EXPECT_THROW(scans.Write({1, 2}, Stamp{0}), InputError);  // no encapsulation header
}

// The same values as Foxglove's CDR writer sees them (times as {sec, nsec}).
nlohmann::json Json(Stamp t) { return {{"sec", t.ns / 1000000000}, {"nsec", t.ns % 1000000000}}; }
nlohmann::json Json(const io::ros::Header& h) { return {{"stamp", Json(h.stamp)}, {"frame_id", h.frame_id}}; }
nlohmann::json Json(const io::ros::Pose& p) {
  return {{"position", {{"x", p.x}, {"y", p.y}, {"z", p.z}}},
          {"orientation", {{"x", p.qx}, {"y", p.qy}, {"z", p.qz}, {"w", p.qw}}}};
}
nlohmann::json Json(const io::ros::LaserScan& m) {
  return {{"header", Json(m.header)},
          {"angle_min", m.angle_min},
          {"angle_max", m.angle_max},
          {"angle_increment", m.angle_increment},
          {"time_increment", m.time_increment},
          {"scan_time", m.scan_time},
          {"range_min", m.range_min},
          {"range_max", m.range_max},
          {"ranges", m.ranges},
          {"intensities", m.intensities}};
}
nlohmann::json Json(const io::ros::Odometry& m) {
  const nlohmann::json zero = {{"x", 0.0}, {"y", 0.0}, {"z", 0.0}};
  return {
      {"header", Json(m.header)},
      {"child_frame_id", m.child_frame_id},
      {"pose", {{"pose", Json(m.pose)}, {"covariance", m.pose_covariance}}},
      {"twist",
       {{"twist",
         {{"linear", {{"x", m.vx}, {"y", m.vy}, {"z", m.vz}}}, {"angular", {{"x", m.wx}, {"y", m.wy}, {"z", m.wz}}}}},
        {"covariance", m.twist_covariance}}}};
}
nlohmann::json Json(const io::ros::OccupancyGrid& m) {
  return {{"header", Json(m.header)},
          {"info",
           {{"map_load_time", Json(m.map_load_time)},
            {"resolution", m.resolution},
            {"width", m.width},
            {"height", m.height},
            {"origin", Json(m.origin)}}},
          {"data", m.data}};
}
nlohmann::json Json(const std::vector<io::ros::TransformStamped>& tf) {
  nlohmann::json transforms = nlohmann::json::array();
  for (const auto& t : tf) {
    const auto pose = Json(t.transform);
    transforms.push_back({{"header", Json(t.header)},
                          {"child_frame_id", t.child_frame_id},
                          {"transform", {{"translation", pose["position"]}, {"rotation", pose["orientation"]}}}});
  }
  return {{"transforms", transforms}};
}
nlohmann::json Json(const io::ros::Path& m) {
  nlohmann::json poses = nlohmann::json::array();
  for (const auto& [h, p] : m.poses) poses.push_back({{"header", Json(h)}, {"pose", Json(p)}});
  return {{"header", Json(m.header)}, {"poses", poses}};
}

io::ros::AckermannDrive Drive() {
  io::ros::AckermannDrive m;
  m.header = {Stamp{1700000000250000000LL}, "base_link"};
  m.steering_angle = -0.3125f;  // exact in float32 and in JSON
  m.steering_angle_velocity = 0.5f;
  m.speed = 2.25f;
  m.acceleration = 1.5f;
  m.jerk = 0;
  return m;
}
nlohmann::json Json(const io::ros::AckermannDrive& m) {
  return {{"header", Json(m.header)},
          {"drive",
           {{"steering_angle", m.steering_angle},
            {"steering_angle_velocity", m.steering_angle_velocity},
            {"speed", m.speed},
            {"acceleration", m.acceleration},
            {"jerk", m.jerk}}}};
}

io::ros::Imu ImuReading() {
  io::ros::Imu m;
  m.header = {Stamp{1700000000250000000LL}, "base_link"};
  m.orientation_covariance[0] = -1;
  m.angular_velocity_covariance[4] = 0.25;
  m.wz = 0.125, m.ax = -1.5, m.ay = 0.75;
  return m;
}
nlohmann::json Vector(double x, double y, double z) { return {{"x", x}, {"y", y}, {"z", z}}; }
nlohmann::json Json(const io::ros::Imu& m) {
  return {{"header", Json(m.header)},
          {"orientation", Json(m.orientation)["orientation"]},
          {"orientation_covariance", m.orientation_covariance},
          {"angular_velocity", Vector(m.wx, m.wy, m.wz)},
          {"angular_velocity_covariance", m.angular_velocity_covariance},
          {"linear_acceleration", Vector(m.ax, m.ay, m.az)},
          {"linear_acceleration_covariance", m.linear_acceleration_covariance}};
}

// specht_msgs: Foxglove's writer takes any definition, so the custom types are
// checked the same way.
io::ros::Obstacles Detections() {
  io::ros::Obstacles m{{Stamp{1700000000250000000LL}, "base_link"}, {}};
  m.obstacles.push_back({7, "pedestrian", 4.5, -1.25, 0, 0.5, 0.75, 0.5, 0.25, {0.01, 0, 0, 0.01}, 0.875, 4.5});
  m.obstacles.push_back({8, "car", 12, 3, 0.5, 2.25, 4.5, 1.75, -1.5, {0.04, 0.01, 0.01, 0.09}, 0.5, 0});
  return m;
}
nlohmann::json Json(const io::ros::Obstacles& m) {
  nlohmann::json obstacles = nlohmann::json::array();
  for (const auto& o : m.obstacles)
    obstacles.push_back({{"id", o.id},
                         {"cls", o.cls},
                         {"x", o.x},
                         {"y", o.y},
                         {"z", o.z},
                         {"radius", o.radius},
                         {"length", o.length},
                         {"width", o.width},
                         {"yaw", o.yaw},
                         {"covariance_xy", o.covariance_xy},
                         {"score", o.score},
                         {"range", o.range}});
  return {{"header", Json(m.header)}, {"obstacles", obstacles}};
}
io::ros::VehicleState Vehicle() { return {{Stamp{1700000000250000000LL}, "base_link"}, 12.5, 2.25, -0.125, ""}; }
nlohmann::json Json(const io::ros::VehicleState& m) {
  return {{"header", Json(m.header)},
          {"time_s", m.time_s},
          {"speed_mps", m.speed_mps},
          {"steer_rad", m.steer_rad},
          {"stop", m.stop}};
}
io::ros::StackStep Step() {
  return {{Stamp{1700000000250000000LL}, "map"}, 2.25, -0.125, 10.5, 3.25, 1.5, "drive", 3, true, false};
}
nlohmann::json Json(const io::ros::StackStep& m) {
  return {{"header", Json(m.header)},
          {"speed_mps", m.speed_mps},
          {"steer_rad", m.steer_rad},
          {"x", m.x},
          {"y", m.y},
          {"yaw", m.yaw},
          {"state", m.state},
          {"tracks", m.tracks},
          {"on_local_path", m.on_local_path},
          {"finished", m.finished}};
}
io::ros::Tracks TrackCycle() {
  io::ros::Tracks m{{Stamp{1700000000250000000LL}, "map"}, {}};
  io::ros::Track t;
  t.id = 12, t.cls = "pedestrian", t.x = 4.5, t.y = -1.25, t.vx = 0.75, t.vy = -0.5;
  for (int i = 0; i < 16; ++i) t.covariance[i] = i % 5 == 0 ? 0.25 : 0.0625 * i;
  t.length = 0.75, t.width = 0.5, t.yaw = 0.25, t.state = "confirmed", t.motion_model = "ct";
  t.history = {{Stamp{1700000000150000000LL}, 4.25, -1.0}, {Stamp{1700000000250000000LL}, 4.5, -1.25}};
  t.prediction = {{0.5, 4.875, -1.5, {0.25, 0.125, 0.125, 0.5}}};
  t.classes = {"car", "pedestrian"}, t.probabilities = {0.125, 0.875};
  m.tracks.push_back(t);
  io::ros::Track coasting;
  coasting.id = 13, coasting.cls = "car", coasting.state = "coasting", coasting.motion_model = "cv";
  m.tracks.push_back(coasting);
  return m;
}
nlohmann::json Json(const io::ros::Tracks& m) {
  nlohmann::json tracks = nlohmann::json::array();
  for (const auto& t : m.tracks) {
    nlohmann::json history = nlohmann::json::array(), prediction = nlohmann::json::array();
    for (const auto& p : t.history) history.push_back({{"stamp", Json(p.stamp)}, {"x", p.x}, {"y", p.y}});
    for (const auto& p : t.prediction)
      prediction.push_back({{"dt", p.dt}, {"x", p.x}, {"y", p.y}, {"covariance_xy", p.covariance_xy}});
    tracks.push_back({{"id", t.id},
                      {"cls", t.cls},
                      {"x", t.x},
                      {"y", t.y},
                      {"vx", t.vx},
                      {"vy", t.vy},
                      {"covariance", t.covariance},
                      {"length", t.length},
                      {"width", t.width},
                      {"yaw", t.yaw},
                      {"state", t.state},
                      {"motion_model", t.motion_model},
                      {"history", history},
                      {"prediction", prediction},
                      {"classes", t.classes},
                      {"probabilities", t.probabilities}});
  }
  return {{"header", Json(m.header)}, {"tracks", tracks}};
}

std::string Hex(const std::vector<uint8_t>& bytes) {
  static const char* digits = "0123456789abcdef";
  std::string out;
  for (uint8_t b : bytes) out += {digits[b >> 4], digits[b & 15]};
  return out;
}

// Interoperability without ROS 2 installed: the CDR bytes specht sends for each type
// equal those Foxglove's ROS 2 serializer (tests/npm/write_cdr.mjs) writes for the
// same values, and what arrives over DDS equals them too.
TEST(Ros2CdrTest, BytesEqualFoxglovesWriterAndWhatDdsDelivers) {
  const std::string verifier = testing::SourceDir() + "/tests/npm";
  if (std::system("node --version > /dev/null 2>&1") != 0 ||
      !std::filesystem::is_directory(verifier + "/node_modules/@foxglove/rosmsg2-serialization"))
    SPECHT_SKIP() << "node or tests/npm/node_modules missing (scripts/setup.sh installs them)";
  const std::vector<std::tuple<std::string, nlohmann::json, std::vector<uint8_t>>> cases = {
      {"sensor_msgs/msg/LaserScan", Json(Scan()), io::ros::Encode(Scan())},
      {"nav_msgs/msg/Odometry", Json(Odom()), io::ros::Encode(Odom())},
      {"nav_msgs/msg/OccupancyGrid", Json(Grid(100, 7)), io::ros::Encode(Grid(100, 7))},
      {"tf2_msgs/msg/TFMessage", Json(Tf()), io::ros::Encode(Tf())},
      {"nav_msgs/msg/Path", Json(PathOf(25)), io::ros::Encode(PathOf(25))},
      {"rosgraph_msgs/msg/Clock",
       {{"clock", Json(Stamp{1700000000250000000LL})}},
       io::ros::EncodeClock(Stamp{1700000000250000000LL})},
      {"ackermann_msgs/msg/AckermannDriveStamped", Json(Drive()), io::ros::Encode(Drive())},
      {"sensor_msgs/msg/Imu", Json(ImuReading()), io::ros::Encode(ImuReading())},
      {"specht_msgs/msg/Obstacles", Json(Detections()), io::ros::Encode(Detections())},
      {"specht_msgs/msg/VehicleState", Json(Vehicle()), io::ros::Encode(Vehicle())},
      {"specht_msgs/msg/StackStep", Json(Step()), io::ros::Encode(Step())},
      {"specht_msgs/msg/Tracks", Json(TrackCycle()), io::ros::Encode(TrackCycle())},
  };
  nlohmann::json input = nlohmann::json::array();
  for (const auto& [type, value, _] : cases)
    input.push_back({{"type", type}, {"definition", io::ros::Definition(type)}, {"value", value}});
  const std::string dir = testing::TempDir("ros2_cdr");
  testing::WriteFile(dir + "/cases.json", input.dump());
  ASSERT_EQ(
      std::system(("node '" + verifier + "/write_cdr.mjs' '" + dir + "/cases.json' > '" + dir + "/out.json'").c_str()),
      0);
  const auto theirs = nlohmann::json::parse(testing::ReadFile(dir + "/out.json"));
  ASSERT_EQ(theirs.size(), cases.size());

  net::Participant out(LoopbackOptions()), in(LoopbackOptions());
  for (size_t i = 0; i < cases.size(); ++i) {
    const auto& [type, value, ours] = cases[i];
    EXPECT_EQ(Hex(ours), theirs[i]["hex"].get<std::string>()) << type;
    const std::string topic = Unique("/interop" + std::to_string(i));
    net::Reader reader(in, topic, type, net::Qos::kDefault);
    net::Writer writer(out, topic, type, net::Qos::kDefault);
    ASSERT_TRUE(writer.WaitForReaders(1, milliseconds(5000))) << type;
    writer.Write(ours, Stamp{0});
    ASSERT_TRUE(reader.WaitForData(milliseconds(5000))) << type;
    ExpectSameCdr(ours, reader.Take().at(0).cdr, type);
  }
}

TEST(DdsOptionsTest, InvalidFieldsAreNamed) {
  auto expect = [](net::Options o, const std::string& field) {
    try {
      o.Validate();
      FAIL() << field << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(field, 0), 0u) << e.what();
    }
  };
  net::Options o;
  o.domain = 233;
  expect(o, "dds.domain");
  o = {};
  o.interface_address = "lo";
  expect(o, "dds.interface_address");
  o = {};
  o.peers = {};
  expect(o, "dds.peers");
  o.peers = {"localhost; rm"};
  expect(o, "dds.peers");
  o = {};
  o.max_participants = 0;
  expect(o, "dds.max_participants");
}

// What Cyclone really runs with, from its own configuration trace: bound to
// 127.0.0.1 only, multicast off, the peers listed, and the interface it selected the
// loopback one.
TEST(DdsTest, EffectiveConfigurationSendsNothingBeyondThisMachine) {
  auto options = LoopbackOptions();
  options.trace_file = testing::TempDir("dds_config") + "/cyclone.log";
  {
    net::Participant p(options);
    net::Writer w(p, Unique("/chatter"), "rosgraph_msgs/msg/Clock", net::Qos::kClock);
  }
  const std::string trace = testing::ReadFile(options.trace_file);
  auto setting = [&](const std::string& key) {
    const std::regex line("config: Domain/" + key + ": ([^\\n{]*) \\{");
    std::smatch m;
    return std::regex_search(trace, m, line) ? m[1].str() : std::string("(not in the trace)");
  };
  EXPECT_EQ(setting("General/AllowMulticast/#text"), "false");
  EXPECT_EQ(setting("General/Interfaces/NetworkInterface\\[@address\\]"), "127.0.0.1");
  EXPECT_EQ(setting("Discovery/Peers/Peer\\[@Address\\]"), "127.0.0.1");
  EXPECT_EQ(setting("Discovery/ParticipantIndex/#text"), "auto");
  // The interfaces Cyclone chose ("selected interfaces: lo (index 1 priority 2)"),
  // each looked up in the list of all it found ("interfaces: lo udp/127.0.0.1(q1)
  // eth0 udp/192.0.2.2(q9)"): loopback addresses only.
  std::smatch all, chosen;
  ASSERT_TRUE(std::regex_search(trace, all, std::regex("\\binterfaces: ([^\\n]*)"))) << trace;
  ASSERT_TRUE(std::regex_search(trace, chosen, std::regex("selected interfaces: ([^\\n]*)"))) << trace;
  std::map<std::string, std::string> address;
  const std::string found = all[1];
  const std::regex entry("(\\S+) udp/([0-9.]+)"), name("(\\S+) \\(index");
  for (std::sregex_iterator it(found.begin(), found.end(), entry), end; it != end; ++it) address[(*it)[1]] = (*it)[2];
  const std::string selected = chosen[1];
  int count = 0;
  for (std::sregex_iterator it(selected.begin(), selected.end(), name), end; it != end; ++it, ++count)
    EXPECT_EQ(address[(*it)[1]].rfind("127.", 0), 0u) << (*it)[1] << " in " << selected;
  EXPECT_EQ(count, 1) << selected;
}

}  // namespace
}  // namespace specht
