// ROS 1 bags through Debian's rosbag_storage (rosbag::Bag, rosbag::View) and the ROS 1
// message headers Debian ships (sensor_msgs, nav_msgs, tf2_msgs): the messages are
// copied into specht's ROS message structs (ros_messages.h) and converted as the
// ROS 2 sources convert theirs (ros_conversion.h).
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <fstream>
#include <map>

#include "little_endian.h"
#include "specht/io/ros_bag.h"
#include "specht/io/ros_conversion.h"

namespace specht::io {
namespace {

ros::Header Copy(const std_msgs::Header& h) {
  return {Stamp{static_cast<int64_t>(h.stamp.sec) * 1000000000LL + h.stamp.nsec}, h.frame_id};
}

ros::LaserScan Copy(const sensor_msgs::LaserScan& m) {
  ros::LaserScan s;
  s.header = Copy(m.header);
  s.angle_min = m.angle_min, s.angle_max = m.angle_max, s.angle_increment = m.angle_increment;
  s.time_increment = m.time_increment, s.scan_time = m.scan_time;
  s.range_min = m.range_min, s.range_max = m.range_max;
  s.ranges = m.ranges, s.intensities = m.intensities;
  return s;
}

ros::Odometry Copy(const nav_msgs::Odometry& m) {
  ros::Odometry o;
  o.header = Copy(m.header);
  o.child_frame_id = m.child_frame_id;
  const auto& p = m.pose.pose;
  o.pose = {p.position.x,    p.position.y,    p.position.z,   p.orientation.x,
            p.orientation.y, p.orientation.z, p.orientation.w};
  o.vx = m.twist.twist.linear.x, o.vy = m.twist.twist.linear.y, o.wz = m.twist.twist.angular.z;
  return o;
}

std::vector<ros::TransformStamped> Copy(const tf2_msgs::TFMessage& m) {
  std::vector<ros::TransformStamped> out;
  for (const auto& t : m.transforms) {
    const auto& tr = t.transform;
    out.push_back({Copy(t.header),
                   t.child_frame_id,
                   {tr.translation.x, tr.translation.y, tr.translation.z, tr.rotation.x, tr.rotation.y, tr.rotation.z,
                    tr.rotation.w}});
  }
  return out;
}

// What a bag that does not open most likely is: a recording cut short, whose index
// (written at its end) is missing.
constexpr const char* kCutBagHint =
    " (its index, written at the end of a bag, is missing or cut: a recording cut short? `rosbag reindex` "
    "rebuilds it)";

// A ROS bag 2.0 after its 13-byte version line is a sequence of records, each a header
// (fields `name=value`, each led by its length) and a data block, each led by its
// length (32 bits, little-endian). rosbag_storage allocates what a length says before
// it reads, so one corrupt length costs up to 4 GB before the read fails (a fuzzed bag
// header took 70 % of fuzz_rawlog's time). What it reads on opening is checked to end
// within the file first: the bag header record, then every record from the bag
// header's `index_pos` to the end (connections and chunk infos, a few per chunk).
// Chunks and their index records are left to rosbag: it reads those by their count,
// and real bags carry index records whose data length disagrees with it.
class BagRecords {
 public:
  explicit BagRecords(const std::string& path) : path_(path), in_(path, std::ios::binary | std::ios::ate) {
    size_ = static_cast<uint64_t>(std::max<std::streamoff>(in_.tellg(), 0));
  }

  void CheckWhatOpeningReads() {
    const std::string header = Header(13);
    End(13, header.size());
    const uint64_t index = IndexPosition(header);
    if (index < 13 || index > size_)
      throw InputError(path_ + ": the bag header's index_pos (" + std::to_string(index) +
                       ") does not point into the file (" + std::to_string(size_) + " bytes)" + kCutBagHint);
    for (uint64_t at = index; at < size_;) at = End(at, Header(at).size());
  }

 private:
  uint64_t Length(uint64_t at) {
    unsigned char b[4] = {};
    in_.seekg(static_cast<std::streamoff>(at));
    in_.read(reinterpret_cast<char*>(b), 4);
    return LittleEndian(b, 4);
  }
  InputError PastTheEnd(uint64_t record, const std::string& what) const {
    return InputError(path_ + ": the record at byte " + std::to_string(record) + " has " + what +
                      " past the end of the file (" + std::to_string(size_) + " bytes)" + kCutBagHint);
  }
  // The header of the record at `at`, once it and its data's length fit the file.
  std::string Header(uint64_t at) {
    if (size_ - at < 4) throw PastTheEnd(at, "its header length");
    const uint64_t length = Length(at);
    if (size_ - at - 4 < length + 4) throw PastTheEnd(at, "a header of " + std::to_string(length) + " bytes");
    std::string header(length, '\0');
    in_.read(header.data(), static_cast<std::streamsize>(length));
    return header;
  }
  // Where the record at `at` ends, once its data fits the file.
  uint64_t End(uint64_t at, uint64_t header) {
    const uint64_t data = Length(at + 4 + header);
    if (size_ - at - 8 - header < data) throw PastTheEnd(at, "data of " + std::to_string(data) + " bytes");
    return at + 8 + header + data;
  }
  // The bag header's `index_pos` field (8 bytes); fields with lengths past the header
  // leave it unset (0, refused by the caller).
  static uint64_t IndexPosition(const std::string& header) {
    const std::string name = "index_pos=";
    const auto* bytes = reinterpret_cast<const unsigned char*>(header.data());
    for (size_t at = 0; header.size() - at >= 4;) {
      const uint64_t length = LittleEndian(bytes + at, 4);
      if (header.size() - at - 4 < length) break;
      if (length == name.size() + 8 && header.compare(at + 4, name.size(), name) == 0)
        return LittleEndian(bytes + at + 4 + name.size(), 8);
      at += 4 + length;
    }
    return 0;
  }

  std::string path_;
  std::ifstream in_;
  uint64_t size_ = 0;
};

class Ros1BagSource : public DatasetSource {
 public:
  Ros1BagSource(std::string path, BagTopicChoice choice, OnBadRecord on_bad)
      : path_(std::move(path)), choice_(std::move(choice)), on_bad_(on_bad) {
    BagRecords(path_).CheckWhatOpeningReads();
    try {
      bag_.open(path_, rosbag::bagmode::Read);
      // The mounts first: /tf_static anywhere in the bag.
      rosbag::View statics(bag_, rosbag::TopicQuery("/tf_static"));
      for (const auto& m : statics)
        if (auto tf = m.instantiate<tf2_msgs::TFMessage>()) convert_.AddStatic(Copy(*tf));
      rosbag::View all(bag_);
      for (const auto* c : all.getConnections()) {
        if (c->datatype == "sensor_msgs/LaserScan" && choice_.scan.empty()) choice_.scan = c->topic;
        if (c->datatype == "nav_msgs/Odometry" && choice_.odometry.empty()) choice_.odometry = c->topic;
      }
      if (choice_.scan.empty()) throw InputError(path_ + ": no sensor_msgs/LaserScan topic to map with");
      std::vector<std::string> topics{choice_.scan};
      if (!choice_.odometry.empty() && choice_.odometry != "none") topics.push_back(choice_.odometry);
      for (const auto* c : all.getConnections())
        if (c->topic != choice_.scan && c->topic != choice_.odometry && c->topic != "/tf_static")
          not_read_[c->topic] = c->datatype;
      view_ = std::make_unique<rosbag::View>(bag_, rosbag::TopicQuery(topics));
      total_ = view_->size();
      it_ = view_->begin();
    } catch (const rosbag::BagException& e) {
      throw InputError(path_ + ": " + e.what() + kCutBagHint);
    }
  }

  std::optional<Observation> Next() override {
    try {
      for (; it_ != view_->end(); ++it_, ++read_) {
        const rosbag::MessageInstance& m = *it_;
        const int64_t index = read_;
        try {
          const auto received = static_cast<int64_t>(m.getTime().toNSec());
          std::optional<Observation> obs;
          if (auto scan = m.instantiate<sensor_msgs::LaserScan>())
            obs = convert_.Observe(Copy(*scan), m.getTopic(), received, index);
          else if (auto odo = m.instantiate<nav_msgs::Odometry>())
            obs = convert_.Observe(Copy(*odo), m.getTopic(), received, index);
          if (obs) {
            ++it_, ++read_;
            return obs;
          }
        } catch (const InputError& e) {
          ros::OnBadMessage(on_bad_, path_, index, m.getTopic(), e.what(), skipped_);
        }
      }
    } catch (const rosbag::BagException& e) {
      throw DatasetError(path_, read_, -1, e.what());
    } catch (const ::ros::Exception& e) {  // a message shorter than its type
      throw DatasetError(path_, read_, -1, std::string("cannot deserialize: ") + e.what());
    }
    return std::nullopt;
  }
  std::string Path() const override { return path_; }
  std::string Format() const override { return "ROS 1 bag"; }
  double FractionRead() const override { return total_ > 0 ? static_cast<double>(read_) / total_ : 1.0; }
  const std::vector<std::string>& SkippedRecords() const override { return skipped_; }
  std::vector<std::string> Notes() const override {
    std::vector<std::string> notes;
    for (const auto& [topic, type] : not_read_) notes.push_back(topic + " (" + type + ") not read");
    for (const auto& note : convert_.MountNotes()) notes.push_back(note);
    return notes;
  }

 private:
  std::string path_;
  BagTopicChoice choice_;
  OnBadRecord on_bad_;
  rosbag::Bag bag_;
  std::unique_ptr<rosbag::View> view_;
  rosbag::View::iterator it_;
  ros::RosObservations convert_;
  std::map<std::string, std::string> not_read_;
  std::vector<std::string> skipped_;
  int64_t total_ = 0, read_ = 0;
};

}  // namespace

std::vector<BagTopic> ListRos1Bag(const std::string& path) {
  std::vector<BagTopic> out;
  BagRecords(path).CheckWhatOpeningReads();
  try {
    rosbag::Bag bag(path, rosbag::bagmode::Read);
    rosbag::View all(bag);
    std::map<std::string, BagTopic> by_name;
    for (const auto* c : all.getConnections()) by_name[c->topic] = {c->topic, c->datatype, 0, 0};
    for (auto& [topic, t] : by_name) {
      rosbag::View one(bag, rosbag::TopicQuery(topic));
      t.messages = one.size();
      const double span = (one.getEndTime() - one.getBeginTime()).toSec();
      if (t.messages > 1 && span > 0) t.rate_hz = (t.messages - 1) / span;
      out.push_back(t);
    }
  } catch (const rosbag::BagException& e) {
    throw InputError(path + ": " + e.what());
  }
  return out;
}

bool IsRos1Bag(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[13] = {};
  in.read(head, 13);
  return in && std::string(head, 13) == "#ROSBAG V2.0\n";
}

std::unique_ptr<DatasetSource> OpenRos1Bag(const std::string& path, const BagTopicChoice& topics, OnBadRecord on_bad) {
  return std::make_unique<Ros1BagSource>(path, topics, on_bad);
}

}  // namespace specht::io
