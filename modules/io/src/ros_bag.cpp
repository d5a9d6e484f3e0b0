#include "specht/io/ros_bag.h"

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <sqlite3.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>

#include "specht/io/mcap.h"
#include "specht/io/ros_conversion.h"
#include "specht/io/ros_messages.h"

namespace specht::io {
namespace {

namespace fs = std::filesystem;

// One read-only rosbag2 SQLite file and the statement stepping through it.
class Db3 {
 public:
  explicit Db3(std::string path) : path_(std::move(path)) {
    // A constructor that throws runs no destructor: the handle (allocated even when
    // opening fails) is closed here.
    const auto refuse = [&](const char* why) {
      const std::string message = Message(why);
      sqlite3_close(db_);
      throw InputError(message);
    };
    if (sqlite3_open_v2(path_.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) refuse("cannot open");
    sqlite3_stmt* probe = nullptr;  // a file that is no rosbag2 store fails here, not later
    if (sqlite3_prepare_v2(db_, "SELECT id, name, type FROM topics", -1, &probe, nullptr) != SQLITE_OK)
      refuse("not a rosbag2 SQLite file");
    while (sqlite3_step(probe) == SQLITE_ROW)
      topics_.push_back({sqlite3_column_int64(probe, 0), Text(probe, 1), Text(probe, 2)});
    sqlite3_finalize(probe);
  }
  ~Db3() {
    sqlite3_finalize(stmt_);
    sqlite3_close(db_);
  }
  Db3(const Db3&) = delete;
  Db3& operator=(const Db3&) = delete;

  struct Topic {
    int64_t id;
    std::string name, type;
  };
  const std::vector<Topic>& topics() const { return topics_; }
  const std::string& path() const { return path_; }

  // The messages of `names` in receive order: (id, topic, receive stamp, payload).
  void Select(const std::vector<std::string>& names) {
    std::string in;
    for (size_t i = 0; i < names.size(); ++i) in += i ? ",?" : "?";
    const std::string sql =
        "SELECT m.id, t.name, m.timestamp, m.data FROM messages m JOIN topics t ON m.topic_id = t.id WHERE t.name IN "
        "(" +
        in + ") ORDER BY m.timestamp, m.id";
    sqlite3_finalize(stmt_);
    stmt_ = nullptr;
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &stmt_, nullptr) != SQLITE_OK) Fail("cannot read its messages");
    for (size_t i = 0; i < names.size(); ++i)
      sqlite3_bind_text(stmt_, static_cast<int>(i + 1), names[i].c_str(), -1, SQLITE_TRANSIENT);
  }
  struct Row {
    int64_t id = 0;
    std::string topic;
    int64_t received_ns = 0;
    std::vector<uint8_t> data;
  };
  bool Step(Row& row) {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_DONE) return false;
    if (rc != SQLITE_ROW) Fail("message table unreadable");
    row.id = sqlite3_column_int64(stmt_, 0);
    row.topic = Text(stmt_, 1);
    row.received_ns = sqlite3_column_int64(stmt_, 2);
    const auto* blob = static_cast<const uint8_t*>(sqlite3_column_blob(stmt_, 3));
    row.data.assign(blob, blob + sqlite3_column_bytes(stmt_, 3));
    return true;
  }
  int64_t Count(const std::vector<std::string>& names) {
    int64_t n = 0;
    for (const auto& t : topics_)
      if (std::find(names.begin(), names.end(), t.name) != names.end()) n += Scalar(t.id, "COUNT(*)");
    return n;
  }
  // (messages, first receive ns, last receive ns) of a topic.
  std::array<int64_t, 3> Span(int64_t topic_id) {
    return {Scalar(topic_id, "COUNT(*)"), Scalar(topic_id, "MIN(timestamp)"), Scalar(topic_id, "MAX(timestamp)")};
  }

 private:
  static std::string Text(sqlite3_stmt* s, int col) {
    const auto* t = sqlite3_column_text(s, col);
    return t ? reinterpret_cast<const char*>(t) : "";
  }
  int64_t Scalar(int64_t topic_id, const char* what) {
    sqlite3_stmt* s = nullptr;
    const std::string sql = std::string("SELECT ") + what + " FROM messages WHERE topic_id = ?";
    if (sqlite3_prepare_v2(db_, sql.c_str(), -1, &s, nullptr) != SQLITE_OK) Fail("message table unreadable");
    sqlite3_bind_int64(s, 1, topic_id);
    const int64_t v = sqlite3_step(s) == SQLITE_ROW ? sqlite3_column_int64(s, 0) : 0;
    sqlite3_finalize(s);
    return v;
  }
  std::string Message(const std::string& why) const {
    return path_ + ": " + why + " (SQLite: " + (db_ ? sqlite3_errmsg(db_) : "no handle") + ")";
  }
  [[noreturn]] void Fail(const std::string& why) const { throw InputError(Message(why)); }
  std::string path_;
  sqlite3* db_ = nullptr;
  sqlite3_stmt* stmt_ = nullptr;
  std::vector<Topic> topics_;
};

// The .db3 files of a bag: the folder's metadata.yaml lists them.
// A bag folder's storage ("sqlite3" or "mcap", since ROS 2 Iron) and its files, as
// its metadata.yaml lists them; a lone .db3 is sqlite3.
struct BagFiles {
  std::string storage = "sqlite3";
  std::vector<std::string> files;
};

BagFiles ListedFiles(const std::string& path) {
  if (fs::is_regular_file(path)) return {"sqlite3", {path}};
  const std::string meta = path + "/metadata.yaml";
  if (!fs::is_regular_file(meta)) throw InputError(path + ": not a ROS 2 bag (no metadata.yaml)");
  YAML::Node info;
  try {
    info = YAML::LoadFile(meta)["rosbag2_bagfile_information"];
  } catch (const YAML::Exception& e) {
    throw InputError(meta + ":" + std::to_string(e.mark.line + 1) + ": " + e.msg);
  }
  if (!info || !info.IsMap()) throw InputError(meta + ": no rosbag2_bagfile_information");
  const auto text = [&](const char* key) {
    return info[key] && info[key].IsScalar() ? info[key].as<std::string>() : std::string();
  };
  BagFiles bag;
  if (const std::string storage = text("storage_identifier"); !storage.empty()) bag.storage = storage;
  if (bag.storage != "sqlite3" && bag.storage != "mcap")
    throw InputError(meta + ": storage_identifier '" + bag.storage + "': sqlite3 and mcap bags are read");
  if (const std::string c = text("compression_format"); !c.empty())
    throw InputError(meta + ": compression_format '" + c + "' is not read (decompress with `ros2 bag convert`)");
  if (const auto list = info["relative_file_paths"]; list && list.IsSequence()) {
    for (const auto& f : list) {
      const std::string p = path + "/" + f.as<std::string>();
      if (!fs::is_regular_file(p))
        throw InputError(meta + ": relative_file_paths lists " + f.as<std::string>() + ", which is missing");
      bag.files.push_back(p);
    }
  }
  if (bag.files.empty()) throw InputError(meta + ": relative_file_paths lists no file");
  return bag;
}

std::vector<std::string> Db3Files(const std::string& path) {
  BagFiles bag = ListedFiles(path);
  if (bag.storage != "sqlite3") throw InputError(path + ": a " + bag.storage + " bag, not sqlite3");
  return bag.files;
}

// The first topic of `type`, or `chosen` checked against the bag.
std::string Pick(const std::vector<Db3::Topic>& topics, const std::string& chosen, const char* type,
                 const std::string& bag) {
  for (const auto& t : topics) {
    if (chosen.empty() && t.type == type) return t.name;
    if (t.name == chosen) {
      if (t.type != type) throw InputError(bag + ": topic " + chosen + " is " + t.type + ", not " + type);
      return t.name;
    }
  }
  if (!chosen.empty()) throw InputError(bag + ": no topic " + chosen);
  return "";
}

class Ros2BagSource : public DatasetSource {
 public:
  Ros2BagSource(std::string path, const BagTopicChoice& choice, OnBadRecord on_bad)
      : path_(std::move(path)), files_(Db3Files(path_)), on_bad_(on_bad) {
    Db3 first(files_.front());
    scan_ = Pick(first.topics(), choice.scan, ros::kLaserScanType, path_);
    if (choice.odometry != "none") odometry_ = Pick(first.topics(), choice.odometry, ros::kOdometryType, path_);
    if (scan_.empty()) throw InputError(path_ + ": no " + std::string(ros::kLaserScanType) + " topic to map with");
    for (const auto& t : first.topics())
      if (t.name == "/tf_static")
        notes_.push_back("/tf_static read for the scan's mount");
      else if (t.name != scan_ && t.name != odometry_)
        notes_.push_back(t.name + " (" + t.type + ") not read");
    for (const auto& f : files_) {
      Db3 db(f);
      total_ += db.Count(Selected());
      ReadStaticTransforms(db);
    }
    OpenFile(0);
  }

  std::optional<Observation> Next() override {
    Db3::Row row;
    while (db_) {
      if (!db_->Step(row)) {
        OpenFile(file_ + 1);
        continue;
      }
      ++read_;
      try {
        if (auto obs = Convert(row)) return obs;
      } catch (const InputError& e) {
        ros::OnBadMessage(on_bad_, db_->path(), row.id, row.topic, e.what(), skipped_);
      }
    }
    return std::nullopt;
  }
  std::string Path() const override { return path_; }
  std::string Format() const override { return "ROS 2 bag (sqlite3)"; }
  double FractionRead() const override { return total_ > 0 ? static_cast<double>(read_) / total_ : 1.0; }
  const std::vector<std::string>& SkippedRecords() const override { return skipped_; }
  std::vector<std::string> Notes() const override {
    std::vector<std::string> notes = notes_;
    for (const auto& note : convert_.MountNotes()) notes.push_back(note);
    return notes;
  }

 private:
  std::vector<std::string> Selected() const {
    std::vector<std::string> s{scan_};
    if (!odometry_.empty()) s.push_back(odometry_);
    return s;
  }
  void OpenFile(size_t i) {
    db_.reset();
    file_ = i;
    if (i >= files_.size()) return;
    db_ = std::make_unique<Db3>(files_[i]);
    db_->Select(Selected());
  }
  void ReadStaticTransforms(Db3& db) {
    for (const auto& t : db.topics()) {
      if (t.type != ros::kTfMessageType || t.name != "/tf_static") continue;
      db.Select({t.name});
      Db3::Row row;
      while (db.Step(row)) convert_.AddStatic(ros::DecodeTfMessage(row.data));
    }
  }
  std::optional<Observation> Convert(const Db3::Row& row) {
    if (row.topic == odometry_)
      return convert_.Observe(ros::DecodeOdometry(row.data), row.topic, row.received_ns, row.id);
    return convert_.Observe(ros::DecodeLaserScan(row.data), row.topic, row.received_ns, row.id);
  }

  std::string path_;
  std::vector<std::string> files_;
  OnBadRecord on_bad_;
  std::string scan_, odometry_;
  std::vector<std::string> notes_, skipped_;
  ros::RosObservations convert_;
  std::unique_ptr<Db3> db_;
  size_t file_ = 0;
  int64_t total_ = 0, read_ = 0;
};

// Topics with their message counts and first and last receive times, for --list.
class TopicTally {
 public:
  void Add(const std::string& name, const std::string& type, int64_t count, int64_t first_ns, int64_t last_ns) {
    auto& [topic, span] = by_name_[name];
    topic.name = name, topic.type = type, topic.messages += count;
    if (count > 0)
      span = topic.messages == count ? std::make_pair(first_ns, last_ns)
                                     : std::make_pair(std::min(span.first, first_ns), std::max(span.second, last_ns));
  }
  std::vector<BagTopic> Topics() const {
    std::vector<BagTopic> out;
    for (auto [name, entry] : by_name_) {
      auto& [topic, span] = entry;
      if (topic.messages > 1 && span.second > span.first)
        topic.rate_hz = (topic.messages - 1) / ((span.second - span.first) * 1e-9);
      out.push_back(topic);
    }
    return out;
  }

 private:
  std::map<std::string, std::pair<BagTopic, std::pair<int64_t, int64_t>>> by_name_;
};

// An MCAP file (mcap.h) read linearly: /tf_static for the mounts, the chosen scan and
// odometry topics (the first of each type when not chosen) as observations.
class McapSource : public DatasetSource {
 public:
  McapSource(std::string path, BagTopicChoice choice, OnBadRecord on_bad)
      : path_(std::move(path)), reader_(path_), choice_(std::move(choice)), on_bad_(on_bad) {}

  std::optional<Observation> Next() override {
    while (auto m = reader_.Next()) {
      try {
        if (auto obs = Convert(*m)) return obs;
      } catch (const InputError& e) {
        ros::OnBadMessage(on_bad_, path_, m->index, m->topic, e.what(), skipped_);
      }
    }
    return std::nullopt;
  }
  std::string Path() const override { return path_; }
  std::string Format() const override { return "MCAP (ros2)"; }
  double FractionRead() const override { return reader_.FractionRead(); }
  const std::vector<std::string>& SkippedRecords() const override { return skipped_; }
  std::vector<std::string> Notes() const override {
    std::vector<std::string> notes;
    for (const auto& [topic, n] : not_read_) notes.push_back(topic + ": " + std::to_string(n) + " messages not read");
    for (const auto& note : convert_.MountNotes()) notes.push_back(note);
    return notes;
  }

 private:
  // Takes `topic` as the one of its kind when none was chosen and none is yet.
  static bool Claims(std::string& chosen, const std::string& topic) {
    if (chosen.empty()) chosen = topic;
    return chosen == topic;
  }
  std::optional<Observation> Convert(const McapMessage& m) {
    if (m.message_encoding != "cdr") throw InputError("message encoding '" + m.message_encoding + "', not cdr");
    if (m.schema_name == ros::kTfMessageType && m.topic == "/tf_static") {
      convert_.AddStatic(ros::DecodeTfMessage(m.data));
    } else if (m.schema_name == ros::kLaserScanType && Claims(choice_.scan, m.topic)) {
      return convert_.Observe(ros::DecodeLaserScan(m.data), m.topic, static_cast<int64_t>(m.log_time_ns), m.index);
    } else if (m.schema_name == ros::kOdometryType && choice_.odometry != "none" && Claims(choice_.odometry, m.topic)) {
      return convert_.Observe(ros::DecodeOdometry(m.data), m.topic, static_cast<int64_t>(m.log_time_ns), m.index);
    } else {
      ++not_read_[m.topic];
    }
    return std::nullopt;
  }
  std::string path_;
  McapReader reader_;
  BagTopicChoice choice_;
  OnBadRecord on_bad_;
  ros::RosObservations convert_;
  std::map<std::string, long> not_read_;
  std::vector<std::string> skipped_;
};

}  // namespace

bool IsMcap(const std::string& path) { return fs::path(path).extension() == ".mcap"; }

std::unique_ptr<DatasetSource> OpenMcap(const std::string& path, const BagTopicChoice& topics, OnBadRecord on_bad) {
  return std::make_unique<McapSource>(path, topics, on_bad);
}

bool IsRos2Bag(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return fs::is_regular_file(path + "/metadata.yaml", ec);
  return fs::path(path).extension() == ".db3";
}

std::vector<BagTopic> ListRosBag(const std::string& path) {
  if (IsRos2Bag(path) && ListedFiles(path).storage == "mcap") return ListRosBag(ListedFiles(path).files.front());
  if (IsRos2Bag(path)) return ListRos2Bag(path);
  if (IsRos1Bag(path)) return ListRos1Bag(path);
  if (!IsMcap(path)) throw InputError(path + ": not a ROS bag or MCAP file");
  TopicTally tally;
  McapReader reader(path);
  while (auto m = reader.Next()) {
    const auto t = static_cast<int64_t>(m->log_time_ns);
    tally.Add(m->topic, m->schema_name, 1, t, t);
  }
  return tally.Topics();
}

std::vector<BagTopic> ListRos2Bag(const std::string& path) {
  TopicTally tally;
  for (const auto& f : Db3Files(path)) {
    Db3 db(f);
    for (const auto& t : db.topics()) {
      const auto [count, first, last] = db.Span(t.id);
      tally.Add(t.name, t.type, count, first, last);
    }
  }
  return tally.Topics();
}

std::unique_ptr<DatasetSource> OpenRos2Bag(const std::string& path, const BagTopicChoice& topics, OnBadRecord on_bad) {
  const BagFiles bag = ListedFiles(path);
  if (bag.storage == "mcap") {  // ROS 2 Iron's default storage: one MCAP file a bag split
    if (bag.files.size() > 1)
      throw InputError(path + ": an MCAP bag split into " + std::to_string(bag.files.size()) +
                       " files; give one .mcap file at a time");
    return OpenMcap(bag.files.front(), topics, on_bad);
  }
  return std::make_unique<Ros2BagSource>(path, topics, on_bad);
}

}  // namespace specht::io
