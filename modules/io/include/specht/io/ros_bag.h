// specht/io/ros_bag.h: ROS 2 recordings as dataset sources — rosbag2's sqlite3
// storage (a folder with metadata.yaml and its .db3 files, or one .db3; SQLite reads
// the tables) and MCAP files (mcap.h, read linearly); Fast CDR decodes the payloads
// (ros_messages.h).
//
// sensor_msgs/msg/LaserScan and nav_msgs/msg/Odometry become observations
// (ros_conversion.h: scans mounted where /tf_static puts their frame), in the order
// the recording holds them (rosbag2: receive time), stamped by their headers. Other
// topics are listed in Notes(), not read.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "specht/io/dataset.h"

namespace specht::io {

// Which topics a bag source reads; "" takes the bag's first topic of that type.
struct BagTopicChoice {
  std::string scan;      // sensor_msgs/msg/LaserScan
  std::string odometry;  // nav_msgs/msg/Odometry; "none" reads no odometry
};

struct BagTopic {
  std::string name, type;
  int64_t messages = 0;
  double rate_hz = 0;  // messages over the topic's first-to-last span
};

// A folder holding metadata.yaml (its storage sqlite3, or mcap as ROS 2 Iron records
// by default), or a file ending in .db3.
bool IsRos2Bag(const std::string& path);

// A ROS 1 bag (format 2.0), read through Debian's rosbag_storage; an unindexed bag
// (a recording cut short) is an input error naming `rosbag reindex`.
bool IsRos1Bag(const std::string& path);
std::unique_ptr<DatasetSource> OpenRos1Bag(const std::string& path, const BagTopicChoice& topics = {},
                                           OnBadRecord on_bad = OnBadRecord::kStop);

// A file ending in .mcap.
bool IsMcap(const std::string& path);
std::unique_ptr<DatasetSource> OpenMcap(const std::string& path, const BagTopicChoice& topics = {},
                                        OnBadRecord on_bad = OnBadRecord::kStop);

// Every topic of a ROS 2 bag, a ROS 1 bag or an MCAP file, by name (an MCAP file is
// read through).
std::vector<BagTopic> ListRosBag(const std::string& path);
std::vector<BagTopic> ListRos1Bag(const std::string& path);
// Every topic of the bag, by name.
std::vector<BagTopic> ListRos2Bag(const std::string& path);

// Throws InputError naming the bag: a listed .db3 missing, not an SQLite bag, a chosen
// topic absent or of another type.
std::unique_ptr<DatasetSource> OpenRos2Bag(const std::string& path, const BagTopicChoice& topics = {},
                                           OnBadRecord on_bad = OnBadRecord::kStop);

}  // namespace specht::io
