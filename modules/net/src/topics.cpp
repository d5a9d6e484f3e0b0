#include "specht/net/topics.h"

#include <algorithm>
#include <chrono>
#include <deque>

#include "specht/core/interrupt.h"
#include "specht/core/statistics.h"
#include "specht/io/ros_conversion.h"
#include "specht/io/ros_messages.h"

namespace specht::net {
namespace {

using std::chrono::milliseconds;
using Clock = std::chrono::steady_clock;

constexpr const char* kLaserScan = io::ros::kLaserScanType;
constexpr const char* kOdometry = io::ros::kOdometryType;
constexpr const char* kTfMessage = io::ros::kTfMessageType;

// What a topic's reader delivered that is not yet released.
struct Queued {
  Sample sample;
  Clock::time_point arrived;
};

class TopicSource : public io::DatasetSource {
 public:
  TopicSource(std::shared_ptr<Participant> participant, TopicSourceOptions options)
      : participant_(participant),
        options_(std::move(options)),
        merger_(std::move(participant), Topics(options_), options_.settle_s, options_.idle_end_s) {}

  std::optional<io::Observation> Next() override {
    while (auto m = merger_.Next()) {
      try {
        if (auto obs = Convert(m->topic, m->type, m->sample)) return obs;
      } catch (const InputError& e) {  // a message that does not decode: stop or skip (replay.on_bad_record)
        io::ros::OnBadMessage(options_.on_bad, Path(), index_ - 1, m->topic, e.what(), skipped_);
      }
    }
    return std::nullopt;
  }
  std::string Path() const override { return "DDS domain " + std::to_string(participant_->options().domain); }
  std::string Format() const override { return "ROS 2 topics (DDS)"; }
  double FractionRead() const override { return -1; }
  std::vector<std::string> Notes() const override { return convert_.MountNotes(); }
  const std::vector<std::string>& SkippedRecords() const override { return skipped_; }
  std::map<std::string, double> Figures() const override { return merger_.Figures(); }

 private:
  static std::vector<TopicSpec> Topics(const TopicSourceOptions& o) {
    std::vector<TopicSpec> topics = {{"/tf_static", kTfMessage, false}, {o.scan_topic, kLaserScan, true}};
    if (o.odometry_topic != "none") topics.push_back({o.odometry_topic, kOdometry, true});
    return topics;
  }

  std::optional<io::Observation> Convert(const std::string& topic, const std::string& type, const Sample& sample) {
    const int64_t index = index_++;
    if (type == kTfMessage) {
      convert_.AddStatic(io::ros::DecodeTfMessage(sample.cdr));
      return std::nullopt;
    }
    if (type == kLaserScan)
      return convert_.Observe(io::ros::DecodeLaserScan(sample.cdr), topic, sample.source_time.ns, index);
    return convert_.Observe(io::ros::DecodeOdometry(sample.cdr), topic, sample.source_time.ns, index);
  }

  std::shared_ptr<Participant> participant_;
  TopicSourceOptions options_;
  TopicMerger merger_;
  io::ros::RosObservations convert_;
  int64_t index_ = 0;
  std::vector<std::string> skipped_;
};

}  // namespace

struct TopicMerger::Stream {
  TopicSpec spec;
  std::unique_ptr<Reader> reader;
  std::deque<Queued> queue;
  bool delivered = false;  // anything ever
};

TopicMerger::TopicMerger(std::shared_ptr<Participant> participant, const std::vector<TopicSpec>& topics,
                         double settle_s, double idle_end_s)
    : participant_(std::move(participant)), settle_s_(settle_s), idle_end_s_(idle_end_s), waitset_(*participant_) {
  for (const auto& t : topics) {
    auto s = std::make_unique<Stream>();
    s->spec = t;
    const Qos qos = QosForTopic(t.topic, Qos::kKeepAll);  // every sample; a latched topic's latest on joining
    s->reader =
        std::make_unique<Reader>(*participant_, t.topic, t.type, qos == Qos::kLatched ? Qos::kLatchedKeepAll : qos);
    waitset_.Attach(*s->reader);
    streams_.push_back(std::move(s));
  }
}

TopicMerger::~TopicMerger() = default;

std::optional<TopicMerger::Message> TopicMerger::Next() {
  for (;;) {
    Pull();
    Stream* head = Head();
    const bool idle =
        idle_end_s_ > 0 && last_arrival_ && Clock::now() - *last_arrival_ > std::chrono::duration<double>(idle_end_s_);
    if (head && (Releasable(*head) || idle)) {
      Queued queued = std::move(head->queue.front());
      head->queue.pop_front();
      waited_ms_.push_back(std::chrono::duration<double, std::milli>(Clock::now() - queued.arrived).count());
      return Message{head->spec.topic, head->spec.type, std::move(queued.sample)};
    }
    if (idle || InterruptRequested()) return std::nullopt;
    waitset_.Wait(milliseconds(head ? 5 : 50));  // a queued message may become releasable by waiting
  }
}

void TopicMerger::Pull() {
  for (auto& s : streams_)
    for (auto& sample : s->reader->Take()) {
      s->queue.push_back({std::move(sample), Clock::now()});
      s->delivered = true;
      last_arrival_ = Clock::now();
    }
}

TopicMerger::Stream* TopicMerger::Head() {
  Stream* head = nullptr;
  for (auto& s : streams_)
    if (!s->queue.empty() && (!head || s->queue.front().sample.source_time < head->queue.front().sample.source_time))
      head = s.get();
  return head;
}

// Every other stream has a later message queued, or cannot hold this one back: it
// has waited settle_s, or the empty stream is one that came once and did.
bool TopicMerger::Releasable(const Stream& head) const {
  if (Clock::now() - head.queue.front().arrived >= std::chrono::duration<double>(settle_s_)) return true;
  for (const auto& s : streams_)
    if (s.get() != &head && s->queue.empty() && (s->spec.periodic || !s->delivered)) return false;
  return true;
}

std::map<std::string, double> TopicMerger::Figures() const {
  if (waited_ms_.empty()) return {};
  return {{"messages", static_cast<double>(waited_ms_.size())},
          {"waited_ms_p50", Percentile(waited_ms_, 0.5)},
          {"waited_ms_p99", Percentile(waited_ms_, 0.99)},
          {"waited_ms_max", Percentile(waited_ms_, 1.0)}};
}

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
