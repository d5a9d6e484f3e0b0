// specht/net/topics.h: ROS 2 topics in and out of specht's dataset model.
//
// TopicPublisher publishes CDR messages by topic name, a writer per topic made on
// first use with ROS 2's QoS convention (QosForTopic). Its samples' source times
// increase strictly in publication order (a message's own stamp, or 1 ns past the
// previous one's): a subscriber that merges the topics by source time (below) gets
// them in the order they were published even where a log's stamps go backwards. The
// headers keep the stamps the messages carry.
//
// SubscribeTopics is a dataset source (io/dataset.h) on live topics — what `specht
// node slam` maps from: sensor_msgs/msg/LaserScan and nav_msgs/msg/Odometry become
// observations (io/ros_conversion.h, the same conversion as for bags and MCAP, scans
// mounted where /tf_static puts their frame), merged by source time. A message is
// released once every other topic has a message queued, or once it has waited
// `settle_s` (a topic may pause or stop: odometry may be absent, /tf_static comes
// once); /tf_static holds the first scans back until it came (or `settle_s` passed).
// The stream ends `idle_end_s` after the last message (0: only a signal ends it,
// core/interrupt.h); Next() returns at the latest every 50 ms to look for a signal.
// Figures() reports how long messages waited between arrival and use (p50, p99,
// max): a consumer slower than the stream shows as a growing wait, not as loss.
// A message that does not decode is a DatasetError naming the topic and its index
// (or, with OnBadRecord::kSkip, a skipped record), as in a bag.
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "specht/io/dataset.h"
#include "specht/net/dds.h"

namespace specht::net {

class TopicPublisher {
 public:
  TopicPublisher(std::shared_ptr<Participant> participant, Qos stream);
  void Publish(const std::string& ros_topic, const std::string& ros_type, Stamp stamp, const std::vector<uint8_t>& cdr);
  // Makes the topic's writer now rather than at its first sample, so that readers
  // match it before that sample is written (a volatile topic's sample reaches only
  // the readers matched when it is written).
  void Advertise(const std::string& ros_topic, const std::string& ros_type) { WriterFor(ros_topic, ros_type); }
  // Waits until `ros_topic` (published with `ros_type`) has `n` readers; false after `timeout`.
  bool WaitForReaders(const std::string& ros_topic, const std::string& ros_type, int n,
                      std::chrono::milliseconds timeout);
  // Waits until every reader has acknowledged every sample (reliable topics); false after `timeout`.
  bool WaitForAcks(std::chrono::milliseconds timeout);
  std::map<std::string, uint64_t> Counts() const { return counts_; }

 private:
  Writer& WriterFor(const std::string& ros_topic, const std::string& ros_type);
  std::shared_ptr<Participant> participant_;
  Qos stream_;
  std::map<std::string, std::unique_ptr<Writer>> writers_;
  std::map<std::string, uint64_t> counts_;
  int64_t last_ns_ = 0;
};

// A topic to merge: `periodic` topics keep coming (scans, odometry) and hold an
// earlier message of another topic back until they deliver one; the others
// (/tf_static, the map) hold back only until their first message.
struct TopicSpec {
  std::string topic, type;
  bool periodic = true;
};

// Subscribed topics merged into one stream by source time (the rule above), reliable
// and keep-all: what the SLAM node and the recorder read.
class TopicMerger {
 public:
  TopicMerger(std::shared_ptr<Participant> participant, const std::vector<TopicSpec>& topics, double settle_s,
              double idle_end_s);
  ~TopicMerger();
  TopicMerger(const TopicMerger&) = delete;
  TopicMerger& operator=(const TopicMerger&) = delete;

  struct Message {
    std::string topic, type;
    Sample sample;
  };
  // The next message; nullopt once the input was idle idle_end_s (> 0) or a signal came.
  std::optional<Message> Next();
  // How long messages waited between arrival and release: messages, waited_ms_p50/p99/max.
  std::map<std::string, double> Figures() const;

 private:
  struct Stream;
  void Pull();
  Stream* Head();
  bool Releasable(const Stream& head) const;
  std::shared_ptr<Participant> participant_;
  double settle_s_, idle_end_s_;
  WaitSet waitset_;
  std::vector<std::unique_ptr<Stream>> streams_;
  std::optional<std::chrono::steady_clock::time_point> last_arrival_;
  std::vector<double> waited_ms_;
};

struct TopicSourceOptions {
  std::string scan_topic = "/scan";
  std::string odometry_topic = "/odom";  // "none": no odometry
  double settle_s = 0.2;
  double idle_end_s = 0;
  io::OnBadRecord on_bad = io::OnBadRecord::kStop;  // a message that does not decode
};

std::unique_ptr<io::DatasetSource> SubscribeTopics(std::shared_ptr<Participant> participant,
                                                   const TopicSourceOptions& options);

}  // namespace specht::net
