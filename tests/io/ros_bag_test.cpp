// ROS 2 messages and bags: CDR payloads written here with Fast CDR's serializer
// (the writer side, independent of the decoders under test) decode to the values
// written; short payloads and broken bags are input errors naming what broke.
#include "specht/io/ros_bag.h"

#include <fastcdr/Cdr.h>
#include <fastcdr/FastBuffer.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <sqlite3.h>

#include <cmath>
#include <filesystem>
#include <functional>

#include "specht/core/error.h"
#include "specht/io/ros_messages.h"
#include "test_support.h"

namespace specht::io {
namespace {

using eprosima::fastcdr::Cdr;
using ::testing::HasSubstr;

// Serialises with `write` after a little-endian CDR encapsulation header.
template <class Write>
std::vector<uint8_t> Cdr(Write write) {
  std::vector<char> bytes(64 * 1024);
  eprosima::fastcdr::FastBuffer buffer(bytes.data(), bytes.size());
  eprosima::fastcdr::Cdr cdr(buffer, eprosima::fastcdr::Cdr::LITTLE_ENDIANNESS, eprosima::fastcdr::Cdr::DDS_CDR);
  cdr.serialize_encapsulation();
  write(cdr);
  return {bytes.begin(), bytes.begin() + static_cast<long>(cdr.getSerializedDataLength())};
}

void Header(eprosima::fastcdr::Cdr& cdr, int32_t sec, uint32_t nsec, const std::string& frame) {
  cdr << sec << nsec << frame;
}

std::vector<uint8_t> Scan() {
  return Cdr([](eprosima::fastcdr::Cdr& cdr) {
    Header(cdr, 1663967375, 500000000u, "rplidar_link");
    cdr << -3.1f << -2.8f << 0.1f << 0.0f << 0.1f << 0.15f << 12.0f;  // 4 beams, 0.1 rad apart
    cdr << std::vector<float>{1.5f, 2.0f, INFINITY, 0.1f} << std::vector<float>{};
  });
}

TEST(RosMessagesTest, ALaserScanDecodesToTheValuesWritten) {
  const ros::LaserScan m = ros::DecodeLaserScan(Scan());
  EXPECT_EQ(m.header.stamp.ns, 1663967375500000000LL);
  EXPECT_EQ(m.header.frame_id, "rplidar_link");
  EXPECT_FLOAT_EQ(m.angle_min, -3.1f);
  EXPECT_FLOAT_EQ(m.range_max, 12.0f);
  ASSERT_EQ(m.ranges.size(), 4u);
  EXPECT_FLOAT_EQ(m.ranges[1], 2.0f);
  EXPECT_TRUE(std::isinf(m.ranges[2]));
}

TEST(RosMessagesTest, OdometryAndTfDecodeToTheValuesWritten) {
  const double yaw = 0.7;
  const auto odom = Cdr([&](eprosima::fastcdr::Cdr& cdr) {
    Header(cdr, 10, 250u, "odom");
    cdr << std::string("base_link");
    cdr << 1.0 << 2.0 << 0.0 << 0.0 << 0.0 << std::sin(yaw / 2) << std::cos(yaw / 2);
    cdr << std::array<double, 36>{};
    cdr << 0.5 << 0.0 << 0.0 << 0.0 << 0.0 << 0.2;
    cdr << std::array<double, 36>{};
  });
  const ros::Odometry o = ros::DecodeOdometry(odom);
  EXPECT_EQ(o.child_frame_id, "base_link");
  EXPECT_DOUBLE_EQ(o.pose.x, 1.0);
  EXPECT_NEAR(o.pose.Yaw(), yaw, 1e-12);
  EXPECT_DOUBLE_EQ(o.vx, 0.5);
  EXPECT_DOUBLE_EQ(o.wz, 0.2);

  const auto tf = Cdr([](eprosima::fastcdr::Cdr& cdr) {
    cdr << static_cast<uint32_t>(2);
    for (const char* child : {"base_link", "rplidar_link"}) {
      Header(cdr, 1, 0, child == std::string("base_link") ? "odom" : "base_link");
      cdr << std::string(child) << 0.1 << 0.0 << 0.2 << 0.0 << 0.0 << 0.0 << 1.0;
    }
  });
  const auto transforms = ros::DecodeTfMessage(tf);
  ASSERT_EQ(transforms.size(), 2u);
  EXPECT_EQ(transforms[1].header.frame_id, "base_link");
  EXPECT_EQ(transforms[1].child_frame_id, "rplidar_link");
  EXPECT_DOUBLE_EQ(transforms[1].transform.z, 0.2);
}

TEST(RosMessagesTest, APayloadShorterThanItsTypeIsAnInputError) {
  std::vector<uint8_t> cut = Scan();
  cut.resize(cut.size() - 12);  // inside the ranges
  try {
    ros::DecodeLaserScan(cut);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("sensor_msgs/msg/LaserScan: CDR payload of"));
    EXPECT_THAT(e.what(), HasSubstr("ends inside the message"));
  }
  EXPECT_THROW(ros::DecodeOdometry({0, 1}), InputError);
  EXPECT_THROW(ros::DecodeOdometry({0, 2, 0, 0, 1, 2, 3, 4}), InputError);  // PL_CDR: not this encapsulation
}

// specht's own messages between the nodes (Imu, Obstacles, VehicleState, StackStep,
// Tracks): written and read back equal, and every payload cut short anywhere is an
// input error naming the type — never a crash or a message made up of what is missing.
ros::Tracks SomeTracks() {
  ros::Tracks m{{Stamp{1700000000250000000LL}, "map"}, {}};
  ros::Track t;
  t.id = 4, t.cls = "car", t.x = 3, t.y = -2, t.vx = 1.5, t.vy = 0.25, t.length = 4.5, t.width = 1.8, t.yaw = 0.1;
  t.covariance[0] = 0.5, t.covariance[15] = 2;
  t.state = "confirmed", t.motion_model = "ct";
  t.history = {{Stamp{1700000000150000000LL}, 2.9, -2.0}};
  t.prediction = {{0.5, 3.75, -1.9, {0.1, 0, 0, 0.2}}};
  t.classes = {"car", "pedestrian"}, t.probabilities = {0.75, 0.25};
  m.tracks = {t, t};
  m.tracks[1].id = 5;
  return m;
}

TEST(RosMessagesTest, TracksDecodeToTheValuesWritten) {
  const ros::Tracks in = SomeTracks();
  const ros::Tracks out = ros::DecodeTracks(ros::Encode(in));
  ASSERT_EQ(out.tracks.size(), 2u);
  EXPECT_EQ(out.header.stamp, in.header.stamp);
  const ros::Track& t = out.tracks[0];
  EXPECT_EQ(t.cls, "car");
  EXPECT_EQ(t.motion_model, "ct");
  EXPECT_DOUBLE_EQ(t.covariance[15], 2);
  ASSERT_EQ(t.history.size(), 1u);
  EXPECT_EQ(t.history[0].stamp, in.tracks[0].history[0].stamp);
  ASSERT_EQ(t.prediction.size(), 1u);
  EXPECT_DOUBLE_EQ(t.prediction[0].covariance_xy[3], 0.2);
  EXPECT_EQ(t.classes, in.tracks[0].classes);
  EXPECT_EQ(t.probabilities, in.tracks[0].probabilities);
  EXPECT_EQ(out.tracks[1].id, 5);
}

TEST(RosMessagesTest, EveryNodeMessageCutShortIsAnInputErrorNamingItsType) {
  ros::Imu imu;
  imu.header = {Stamp{1700000000000000000LL}, "imu_link"}, imu.wz = 0.5;
  ros::Obstacles obstacles{{Stamp{1700000000000000000LL}, "base_link"}, {}};
  obstacles.obstacles.push_back({7, "pedestrian", 4.5, -1.25, 0, 0.5, 0.75, 0.5, 0.25, {0.01, 0, 0, 0.01}, 0.9, 4.5});
  const ros::VehicleState state{{Stamp{1700000000000000000LL}, "base_link"}, 1.5, 2.0, 0.1, "time limit"};
  const ros::StackStep step{{Stamp{1700000000000000000LL}, "map"}, 2, 0.1, 1, 2, 3, "drive", 2, true, false};
  const std::vector<std::pair<std::string, std::function<void(const std::vector<uint8_t>&)>>> decoders = {
      {ros::kImuType, [](const auto& b) { ros::DecodeImu(b); }},
      {ros::kObstaclesType, [](const auto& b) { ros::DecodeObstacles(b); }},
      {ros::kVehicleStateType, [](const auto& b) { ros::DecodeVehicleState(b); }},
      {ros::kStackStepType, [](const auto& b) { ros::DecodeStackStep(b); }},
      {ros::kTracksType, [](const auto& b) { ros::DecodeTracks(b); }}};
  const std::vector<std::vector<uint8_t>> payloads = {ros::Encode(imu), ros::Encode(obstacles), ros::Encode(state),
                                                      ros::Encode(step), ros::Encode(SomeTracks())};
  for (size_t k = 0; k < decoders.size(); ++k) {
    const auto& [type, decode] = decoders[k];
    EXPECT_NO_THROW(decode(payloads[k])) << type;
    // CDR pads the end to 4 bytes: cutting those off only removes padding.
    for (size_t size = 0; size + 4 <= payloads[k].size() - 4; ++size) {
      const std::vector<uint8_t> cut(payloads[k].begin(), payloads[k].begin() + static_cast<long>(size));
      try {
        decode(cut);
        ADD_FAILURE() << type << " cut to " << size << " bytes decoded";
      } catch (const InputError& e) {
        EXPECT_THAT(e.what(), HasSubstr(type)) << size;
      }
    }
  }
}

// A bag written here with SQLite in rosbag2's schema: one scan, one odometry, a
// mount on /tf_static; and the same bag with a payload cut short.
void WriteBag(const std::string& db3, bool cut_scan) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(db3.c_str(), &db), SQLITE_OK);
  sqlite3_exec(db,
               "CREATE TABLE topics(id INTEGER PRIMARY KEY,name TEXT NOT NULL,type TEXT NOT NULL,serialization_format "
               "TEXT NOT NULL,offered_qos_profiles TEXT NOT NULL);"
               "CREATE TABLE messages(id INTEGER PRIMARY KEY,topic_id INTEGER NOT NULL,timestamp INTEGER NOT NULL, "
               "data BLOB NOT NULL);"
               "INSERT INTO topics VALUES (1,'/scan','sensor_msgs/msg/LaserScan','cdr','');"
               "INSERT INTO topics VALUES (2,'/tf_static','tf2_msgs/msg/TFMessage','cdr','');"
               "INSERT INTO topics VALUES (3,'/cmd_vel','geometry_msgs/msg/Twist','cdr','');",
               nullptr, nullptr, nullptr);
  const auto insert = [&](int id, int topic, int64_t t, const std::vector<uint8_t>& data) {
    sqlite3_stmt* s = nullptr;
    sqlite3_prepare_v2(db, "INSERT INTO messages VALUES (?,?,?,?)", -1, &s, nullptr);
    sqlite3_bind_int(s, 1, id), sqlite3_bind_int(s, 2, topic), sqlite3_bind_int64(s, 3, t);
    sqlite3_bind_blob(s, 4, data.data(), static_cast<int>(data.size()), SQLITE_TRANSIENT);
    sqlite3_step(s);
    sqlite3_finalize(s);
  };
  insert(1, 2, 1, Cdr([](eprosima::fastcdr::Cdr& cdr) {
           cdr << static_cast<uint32_t>(1);
           Header(cdr, 1, 0, "base_link");
           cdr << std::string("rplidar_link") << 0.3 << 0.0 << 0.2 << 0.0 << 0.0 << 0.0 << 1.0;
         }));
  std::vector<uint8_t> scan = Scan();
  if (cut_scan) scan.resize(20);
  insert(2, 1, 2, scan);
  sqlite3_close(db);
}

TEST(Ros2BagTest, ReadsTheScanMountedWhereTfStaticPutsIt) {
  const std::string dir = testing::TempDir("ros2_bag");
  WriteBag(dir + "/bag.db3", false);
  auto source = OpenRos2Bag(dir + "/bag.db3");
  const auto obs = source->Next();
  ASSERT_TRUE(obs);
  const auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs->data);
  ASSERT_TRUE(scan);
  EXPECT_EQ(scan->getScanSize(), 4u);
  EXPECT_TRUE(scan->getScanRangeValidity(0));
  EXPECT_FALSE(scan->getScanRangeValidity(2));  // inf
  EXPECT_FALSE(scan->getScanRangeValidity(3));  // below range_min
  EXPECT_NEAR(scan->sensorPose.x(), 0.3, 1e-9);
  EXPECT_NEAR(scan->sensorPose.z(), 0.2, 1e-9);
  // -3.1 + 0.1 · 3 / 2 = -2.95 rad: the beams' middle, where MRPT puts the sensor's x axis.
  EXPECT_NEAR(scan->sensorPose.yaw(), -2.95, 1e-6);
  EXPECT_FALSE(source->Next());
  EXPECT_THAT(source->Notes(), ::testing::Contains(HasSubstr("/cmd_vel (geometry_msgs/msg/Twist) not read")));
}

TEST(Ros2BagTest, BrokenBagsNameWhatBroke) {
  const std::string dir = testing::TempDir("ros2_bag_bad");
  WriteBag(dir + "/cut.db3", true);
  auto source = OpenRos2Bag(dir + "/cut.db3");
  try {
    source->Next();
    FAIL() << "no error";
  } catch (const DatasetError& e) {
    EXPECT_THAT(e.what(), HasSubstr("cut.db3:2: /scan: sensor_msgs/msg/LaserScan: CDR payload of 20 bytes"));
  }
  auto skipping = OpenRos2Bag(dir + "/cut.db3", {}, OnBadRecord::kSkip);
  EXPECT_FALSE(skipping->Next());
  EXPECT_EQ(skipping->SkippedRecords().size(), 1u);

  std::filesystem::create_directories(dir + "/bag");
  testing::WriteFile(dir + "/bag/metadata.yaml",
                     "rosbag2_bagfile_information:\n  storage_identifier: sqlite3\n  relative_file_paths:\n"
                     "    - bag_0.db3\n");
  EXPECT_TRUE(IsRos2Bag(dir + "/bag"));
  try {
    OpenRos2Bag(dir + "/bag");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("metadata.yaml: relative_file_paths lists bag_0.db3, which is missing"));
  }
  testing::WriteFile(dir + "/not.db3", "hello");
  EXPECT_THROW(OpenRos2Bag(dir + "/not.db3"), InputError);
}

// A ROS 1 bag (CCNY's scan_tools demo) whose records run past the end of the file: a
// corrupt bag-header length, an index record claiming more data than is left, and a
// bag cut short (its index gone) are named before rosbag_storage allocates what they
// claim.
TEST(Ros1BagTest, RecordsPastTheEndOfTheFileAreNamedByByte) {
  const std::string bag = testing::DataDir() + "/ros/ccny-scan-tools/demo.bag";
  if (testing::DataDir().empty() || !std::filesystem::exists(bag)) SPECHT_SKIP() << bag;
  const std::string bytes = testing::ReadFile(bag);
  EXPECT_TRUE(OpenRos1Bag(bag)->Next());

  const std::string dir = testing::TempDir("ros1_bag_bad");
  std::string corrupt = bytes;
  corrupt.replace(13, 4, "\xf0\xff\xff\xff");  // the bag header's header length
  testing::WriteFile(dir + "/header.bag", corrupt);
  try {
    OpenRos1Bag(dir + "/header.bag");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("header.bag: the record at byte 13 has a header of 4294967280 bytes past the end "
                                    "of the file (" +
                                    std::to_string(bytes.size()) + " bytes)"));
  }
  EXPECT_THROW(ListRos1Bag(dir + "/header.bag"), InputError);

  // The last chunk info record, at the end of the index, claiming more data than is left.
  corrupt = bytes;
  corrupt.replace(corrupt.size() - 4 - 8, 4, std::string("\xff\xff\x00\x00", 4));
  testing::WriteFile(dir + "/index.bag", corrupt);
  try {
    OpenRos1Bag(dir + "/index.bag");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(),
                ::testing::ContainsRegex("index.bag: the record at byte [0-9]+ has data of 65535 bytes past"));
  }

  testing::WriteFile(dir + "/cut.bag", bytes.substr(0, 500000));
  try {
    OpenRos1Bag(dir + "/cut.bag");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), ::testing::ContainsRegex("cut.bag: the bag header's index_pos \\([0-9]+\\) does not point "
                                                   "into the file \\(500000 bytes\\).*rosbag reindex"));
  }
}

}  // namespace
}  // namespace specht::io
