// specht/io/ros_bag.h: ROS 2 bags (rosbag2's sqlite3 storage: a folder with
// metadata.yaml and its .db3 files, or one .db3) as a dataset source. SQLite reads
// the tables, Fast CDR the payloads (ros_messages.h).
//
// What becomes an observation (in the order of the messages' header stamps):
//   sensor_msgs/msg/LaserScan  a CObservation2DRangeScan, mounted where /tf_static puts
//                              its frame on the base frame (odometry's child frame,
//                              else base_link); beams outside [range_min, range_max]
//                              invalid; a scan not centred on its x axis is rotated
//                              by its mid angle (MRPT's scans are symmetric)
//   nav_msgs/msg/Odometry      a CObservationOdometry (x, y, yaw; the twist as its
//                              local velocity)
// Other types are counted and skipped (Notes()); /tf_static is read for the mounts.
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

// A folder holding metadata.yaml, or a file ending in .db3.
bool IsRos2Bag(const std::string& path);

// Every topic of the bag, by name.
std::vector<BagTopic> ListRos2Bag(const std::string& path);

// Throws InputError naming the bag: a listed .db3 missing, not an SQLite bag, a chosen
// topic absent or of another type.
std::unique_ptr<DatasetSource> OpenRos2Bag(const std::string& path, const BagTopicChoice& topics = {},
                                           OnBadRecord on_bad = OnBadRecord::kStop);

}  // namespace specht::io
