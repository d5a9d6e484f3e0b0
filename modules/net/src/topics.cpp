#include "specht/net/topics.h"

#include <algorithm>
#include <chrono>
#include <deque>

#include "specht/core/interrupt.h"
#include "specht/io/ros_conversion.h"
#include "specht/io/ros_messages.h"

namespace specht::net {
namespace {

using std::chrono::milliseconds;
using Clock = std::chrono::steady_clock;

constexpr const char* kLaserScan = "sensor_msgs/msg/LaserScan";
constexpr const char* kOdometry = "nav_msgs/msg/Odometry";
constexpr const char* kTfMessage = "tf2_msgs/msg/TFMessage";

// One subscribed topic and what it delivered that is not yet released.
struct Stream {
  std::string topic, type;
  bool periodic = true;  // a topic that keeps coming (scans, odometry) rather than once (/tf_static)
  std::unique_ptr<Reader> reader;
  struct Queued {
    Sample sample;
    Clock::time_point arrived;
  };
  std::deque<Queued> queue;
  bool delivered = false;  // anything ever
};

class TopicSource : public io::DatasetSource {
 public:
  TopicSource(std::shared_ptr<Participant> participant, TopicSourceOptions options)
      : participant_(std::move(participant)), options_(std::move(options)), waitset_(*participant_) {
    Add("/tf_static", kTfMessage, false);
    Add(options_.scan_topic, kLaserScan, true);
    if (options_.odometry_topic != "none") Add(options_.odometry_topic, kOdometry, true);
    for (const auto& s : streams_) waitset_.Attach(*s.reader);
  }

  std::optional<io::Observation> Next() override {
    for (;;) {
      Pull();
      Stream* head = Head();
      const bool idle = options_.idle_end_s > 0 && last_arrival_ &&
                        Clock::now() - *last_arrival_ > std::chrono::duration<double>(options_.idle_end_s);
      if (head && (Releasable(*head) || idle)) {
        auto queued = std::move(head->queue.front());
        head->queue.pop_front();
        waited_ms_.push_back(std::chrono::duration<double, std::milli>(Clock::now() - queued.arrived).count());
        try {
          if (auto obs = Convert(*head, queued.sample)) return obs;
        } catch (const InputError& e) {  // a message that does not decode: stop or skip (replay.on_bad_record)
          io::ros::OnBadMessage(options_.on_bad, Path(), index_ - 1, head->topic, e.what(), skipped_);
        }
        continue;
      }
      if (idle || InterruptRequested()) return std::nullopt;
      waitset_.Wait(milliseconds(head ? 5 : 50));  // a queued message may become releasable by waiting
    }
  }
  std::string Path() const override { return "DDS domain " + std::to_string(participant_->options().domain); }
  std::string Format() const override { return "ROS 2 topics (DDS)"; }
  double FractionRead() const override { return -1; }
  std::vector<std::string> Notes() const override { return convert_.MountNotes(); }
  const std::vector<std::string>& SkippedRecords() const override { return skipped_; }
  // How long messages waited between their arrival and their use: the merge's wait
  // for the other topics, and the queue that builds up when the consumer is slower
  // than the stream.
  std::map<std::string, double> Figures() const override {
    if (waited_ms_.empty()) return {};
    std::vector<double> w = waited_ms_;
    std::sort(w.begin(), w.end());
    const auto at = [&](double q) { return w[static_cast<size_t>(q * static_cast<double>(w.size() - 1))]; };
    return {{"messages", static_cast<double>(w.size())},
            {"waited_ms_p50", at(0.5)},
            {"waited_ms_p99", at(0.99)},
            {"waited_ms_max", w.back()}};
  }

 private:
  void Add(const std::string& topic, const std::string& type, bool periodic) {
    Stream s{topic, type, periodic, nullptr, {}, false};
    s.reader = std::make_unique<Reader>(*participant_, topic, type, QosForTopic(topic, Qos::kKeepAll));
    streams_.push_back(std::move(s));
  }

  void Pull() {
    for (auto& s : streams_)
      for (auto& sample : s.reader->Take()) {
        s.queue.push_back({std::move(sample), Clock::now()});
        s.delivered = true;
        last_arrival_ = Clock::now();
      }
  }

  // The stream whose first queued message has the earliest source time.
  Stream* Head() {
    Stream* head = nullptr;
    for (auto& s : streams_)
      if (!s.queue.empty() && (!head || s.queue.front().sample.source_time < head->queue.front().sample.source_time))
        head = &s;
    return head;
  }

  // Every other stream has a later message queued, or cannot hold this one back: it
  // has waited settle_s, or the empty stream is one that came once and did.
  bool Releasable(const Stream& head) const {
    if (Clock::now() - head.queue.front().arrived >= std::chrono::duration<double>(options_.settle_s)) return true;
    for (const auto& s : streams_)
      if (&s != &head && s.queue.empty() && (s.periodic || !s.delivered)) return false;
    return true;
  }

  std::optional<io::Observation> Convert(const Stream& s, const Sample& sample) {
    const int64_t index = index_++;
    if (s.type == kTfMessage) {
      convert_.AddStatic(io::ros::DecodeTfMessage(sample.cdr));
      return std::nullopt;
    }
    if (s.type == kLaserScan)
      return convert_.Observe(io::ros::DecodeLaserScan(sample.cdr), s.topic, sample.source_time.ns, index);
    return convert_.Observe(io::ros::DecodeOdometry(sample.cdr), s.topic, sample.source_time.ns, index);
  }

  std::shared_ptr<Participant> participant_;
  TopicSourceOptions options_;
  WaitSet waitset_;
  std::vector<Stream> streams_;
  io::ros::RosObservations convert_;
  std::optional<Clock::time_point> last_arrival_;
  int64_t index_ = 0;
  std::vector<std::string> skipped_;
  std::vector<double> waited_ms_;
};

}  // namespace

TopicPublisher::TopicPublisher(std::shared_ptr<Participant> participant, Qos stream)
    : participant_(std::move(participant)), stream_(stream) {}

Writer& TopicPublisher::WriterFor(const std::string& ros_topic, const std::string& ros_type) {
  auto& writer = writers_[ros_topic];
  if (!writer) writer = std::make_unique<Writer>(*participant_, ros_topic, ros_type, QosForTopic(ros_topic, stream_));
  return *writer;
}

void TopicPublisher::Publish(const std::string& ros_topic, const std::string& ros_type, Stamp stamp,
                             const std::vector<uint8_t>& cdr) {
  last_ns_ = std::max(stamp.ns, last_ns_ + 1);
  WriterFor(ros_topic, ros_type).Write(cdr, Stamp{last_ns_});
  ++counts_[ros_topic];
}

bool TopicPublisher::WaitForReaders(const std::string& ros_topic, const std::string& ros_type, int n,
                                    std::chrono::milliseconds timeout) {
  return WriterFor(ros_topic, ros_type).WaitForReaders(n, timeout);
}

bool TopicPublisher::WaitForAcks(std::chrono::milliseconds timeout) {
  bool all = true;
  for (auto& [topic, writer] : writers_) all &= writer->WaitForAcks(timeout);
  return all;
}

std::unique_ptr<io::DatasetSource> SubscribeTopics(std::shared_ptr<Participant> participant,
                                                   const TopicSourceOptions& options) {
  return std::make_unique<TopicSource>(std::move(participant), options);
}

}  // namespace specht::net
