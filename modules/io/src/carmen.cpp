#include "specht/io/carmen.h"

#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <optional>
#include <sstream>
#include <utility>

#include "specht/io/line_reader.h"

namespace specht::io {
namespace {

using mrpt::poses::CPose2D;

// A corrected log's first NEFF line follows its first laser message closely (line 4
// to 194 on the Radish logs); this many lines are looked at.
constexpr int kCorrectedProbeLines = 20000;
constexpr double kMaxStampS = 4e9;  // ±126 years about the epoch (nanoseconds in 64 bits reach ±292)

struct LaserMessage {
  std::vector<float> ranges;
  double start_angle = -M_PI / 2;
  double increment = 0;
  double max_range = 0;
  CPose2D pose;      // the laser's pose in a FLASER line, the robot's in ROBOTLASER1 (corrected logs: the reference)
  CPose2D odometry;  // the robot's odometry at this scan (FLASER odom_*, ROBOTLASER1 robot_*)
  CPose2D laser_offset;  // laser on the robot (ROBOTLASER1), else from PARAM
  bool has_offset = false;
  double stamp = 0;
};

// Parses one line into tokens and checks numbers, naming the field on error.
class LineFields {
 public:
  explicit LineFields(const std::string& line) {
    std::istringstream s(line);
    for (std::string t; s >> t;) tokens_.push_back(std::move(t));
  }
  size_t size() const { return tokens_.size(); }
  const std::string& operator[](size_t i) const { return tokens_[i]; }
  // The i-th token as a number; `what` names it in the error.
  double Number(size_t i, const char* what) const {
    if (i >= tokens_.size()) throw Bad(std::string("missing field '") + what + "'");
    const char* s = tokens_[i].c_str();
    char* end = nullptr;
    const double v = std::strtod(s, &end);
    if (end == s || *end != '\0') throw Bad(std::string("field '") + what + "' is not a number: '" + tokens_[i] + "'");
    if (!std::isfinite(v)) throw Bad(std::string("field '") + what + "' is " + tokens_[i]);
    return v;
  }
  // A stamp in seconds, within ±kMaxStampS (so it converts to nanoseconds exactly).
  double Seconds(size_t i, const char* what) const {
    const double v = Number(i, what);
    if (std::abs(v) > kMaxStampS) throw Bad(std::string("'") + what + "' is out of range: " + tokens_[i]);
    return v;
  }
  int Count(size_t i, const char* what) const {
    const double v = Number(i, what);
    if (v < 1 || v > 100000 || v != std::floor(v)) throw Bad(std::string("'") + what + "' must be a positive count");
    return static_cast<int>(v);
  }
  struct Bad : std::runtime_error {
    using std::runtime_error::runtime_error;
  };

 private:
  std::vector<std::string> tokens_;
};

std::vector<float> Ranges(const LineFields& f, size_t first, int n) {
  std::vector<float> r(n);
  for (int i = 0; i < n; ++i) {
    const std::string name = "range " + std::to_string(i + 1);
    const double v = f.Number(first + i, name.c_str());
    if (v < 0) throw LineFields::Bad("'" + name + "' is negative");
    r[i] = static_cast<float>(v);
  }
  return r;
}

// Angle between FLASER beams, as CARMEN reads a SICK (carmen_laser_get_angle_increment):
// 180/181 beams at 1°, 360/361 at 0.5°, the first beam at −90°; the even counts drop
// the last beam, so 180 beams span −90°..+89°, not 180° in 179 steps. On the Radish
// logs, against the corrected poses, this spacing and −90° rather than a centred
// start give both the lower relation error and the sharper reference map
// (docs/slam-experiments.md).
// Other counts spread over 180°.
double FlaserIncrement(int n) {
  if (n == 180 || n == 181) return M_PI / 180;
  if (n == 360 || n == 361) return M_PI / 360;
  return n > 1 ? M_PI / (n - 1) : 0;
}

// FLASER n r_1..r_n x y θ odom_x odom_y odom_θ ipc_t [host logger_t]
LaserMessage ParseFlaser(const LineFields& f) {
  const int n = f.Count(1, "num_readings");
  if (f.size() < static_cast<size_t>(2 + n + 7)) {
    throw LineFields::Bad("FLASER with " + std::to_string(n) + " beams needs at least " + std::to_string(2 + n + 7) +
                          " fields, got " + std::to_string(f.size()) + " (beam count mismatch or truncated line)");
  }
  LaserMessage m;
  m.ranges = Ranges(f, 2, n);
  m.increment = FlaserIncrement(n);
  m.pose = CPose2D(f.Number(2 + n, "x"), f.Number(3 + n, "y"), f.Number(4 + n, "theta"));
  m.odometry = CPose2D(f.Number(5 + n, "odom_x"), f.Number(6 + n, "odom_y"), f.Number(7 + n, "odom_theta"));
  m.stamp = f.Seconds(8 + n, "ipc_timestamp");
  return m;
}

// ROBOTLASER1 type start fov res max acc mode n r.. m e.. lx ly lθ rx ry rθ tv rv fs ss ta ipc_t ...
LaserMessage ParseRobotLaser(const LineFields& f) {
  LaserMessage m;
  m.start_angle = f.Number(2, "start_angle");
  m.increment = f.Number(4, "angular_resolution");
  m.max_range = f.Number(5, "maximum_range");
  const int n = f.Count(8, "num_readings");
  m.ranges = Ranges(f, 9, n);
  const size_t rem = 9 + n;
  const double remissions = f.Number(rem, "num_remissions");
  if (remissions < 0 || remissions != std::floor(remissions) || remissions > static_cast<double>(f.size()))
    throw LineFields::Bad("'num_remissions' must be a count no larger than the line");
  const size_t p = rem + 1 + static_cast<size_t>(remissions);
  if (f.size() < p + 12) {
    throw LineFields::Bad("ROBOTLASER1 with " + std::to_string(n) + " beams needs at least " + std::to_string(p + 12) +
                          " fields, got " + std::to_string(f.size()));
  }
  const CPose2D laser(f.Number(p, "laser_pose_x"), f.Number(p + 1, "laser_pose_y"),
                      f.Number(p + 2, "laser_pose_theta"));
  m.pose =
      CPose2D(f.Number(p + 3, "robot_pose_x"), f.Number(p + 4, "robot_pose_y"), f.Number(p + 5, "robot_pose_theta"));
  m.odometry = m.pose;
  m.laser_offset = laser - m.pose;
  m.has_offset = true;
  m.stamp = f.Seconds(p + 11, "ipc_timestamp");
  return m;
}

// One sensor's stamps, as logged. A stamp equal to the previous one's (logs without
// stamps write 0 throughout) is moved 1 ms after the previous stamp given out, so scans
// stay apart; a stamp that goes backwards is kept as logged and counted.
class StampStream {
 public:
  explicit StampStream(std::string sensor) : sensor_(std::move(sensor)) {}
  Stamp Take(double t) {
    const Stamp logged = Stamp::FromSeconds(t);
    Stamp s = logged;
    if (last_logged_ && logged == *last_logged_) {
      ++repeated_;
      s = Stamp{last_given_->ns + 1'000'000};
    } else if (last_logged_ && logged < *last_logged_) {
      ++backwards_;
      max_back_s_ = std::max(max_back_s_, last_logged_->Seconds() - logged.Seconds());
    }
    last_logged_ = logged;
    last_given_ = s;
    return s;
  }
  // What happened to this sensor's stamps, for the report; empty when nothing did.
  std::optional<std::string> Note() const {
    std::string note;
    if (backwards_ > 0) {
      char back[64];
      std::snprintf(back, sizeof back, "%.3f", max_back_s_);
      note = std::to_string(backwards_) + " stamps go backwards (by up to " + back +
             " s): kept as logged, taken in file order";
    }
    if (repeated_ > 0) {
      note += (note.empty() ? "" : "; ") + std::to_string(repeated_) +
              " stamps repeat the previous one: moved 1 ms after it";
    }
    if (note.empty()) return std::nullopt;
    return sensor_ + ": " + note;
  }

 private:
  std::string sensor_;
  std::optional<Stamp> last_logged_, last_given_;
  long repeated_ = 0, backwards_ = 0;
  double max_back_s_ = 0;
};

// The event stream of a CARMEN log, shared by the dataset source and the reference
// reader so both stamp scans identically.
class CarmenReader {
 public:
  struct Event {
    enum Kind { kOdometry, kLaser } kind;
    Stamp stamp;
    CPose2D odometry;    // the robot's raw odometry (at the scan, for kLaser)
    LaserMessage laser;  // kLaser
    int64_t line = 0;
  };

  CarmenReader(std::string path, OnBadRecord on_bad)
      : path_(std::move(path)), corrected_(IsCorrectedCarmenLog(path_)), lines_(path_), on_bad_(on_bad) {
    std::error_code ec;
    file_size_ = std::filesystem::file_size(path_, ec);
  }

  std::optional<Event> Next() {
    std::string line;
    while (lines_.Next(line)) {
      try {
        if (auto e = Parse(line)) return e;
      } catch (const LineFields::Bad& bad) {
        if (on_bad_ == OnBadRecord::kStop) throw DatasetError(path_, lines_.number(), -1, bad.what());
        skipped_.push_back(path_ + ":" + std::to_string(lines_.number()) + ": " + bad.what());
      }
    }
    return std::nullopt;
  }
  double Fraction() const { return lines_.Fraction(file_size_); }
  const std::vector<std::string>& skipped() const { return skipped_; }
  double front_laser_offset() const { return front_laser_offset_; }
  bool corrected() const { return corrected_; }
  std::vector<std::string> Notes() const {
    std::vector<std::string> notes{corrected_ ? kCorrectedNote : kRawNote};
    for (const StampStream* s : {&laser_stamps_, &odometry_stamps_}) {
      if (auto note = s->Note()) notes.push_back(*note);
    }
    return notes;
  }

 private:
  static constexpr const char* kCorrectedNote =
      "a corrected log (it holds NEFF lines): laser poses are the reference; odometry is the chain of ODOM "
      "increments, re-anchored at each laser message";
  static constexpr const char* kRawNote =
      "a raw log (no NEFF lines): laser poses are the robot's odometry, not a reference; each scan's odometry is "
      "its own line's";

  std::optional<Event> Parse(const std::string& line) {
    const LineFields f(line);
    if (f.size() == 0 || f[0][0] == '#') return std::nullopt;
    const std::string& kind = f[0];
    if (kind == "PARAM") {
      if (f.size() >= 3 && f[1] == "robot_frontlaser_offset") front_laser_offset_ = f.Number(2, "value");
      if (f.size() >= 3 && f[1] == "robot_front_laser_max") front_laser_max_ = f.Number(2, "value");
      return std::nullopt;
    }
    if (kind == "ODOM") {
      if (f.size() < 8) throw LineFields::Bad("ODOM needs at least 8 fields, got " + std::to_string(f.size()));
      const CPose2D odom(f.Number(1, "x"), f.Number(2, "y"), f.Number(3, "theta"));
      const double t = f.Seconds(7, "ipc_timestamp");
      if (!corrected_) {
        raw_ = odom;
      } else {
        if (anchor_) raw_ = raw_ + (odom - *anchor_);
        anchor_ = odom;
      }
      return Event{Event::kOdometry, odometry_stamps_.Take(t), raw_, {}, lines_.number()};
    }
    if (kind == "FLASER" || kind == "ROBOTLASER1") {
      LaserMessage m = kind == "FLASER" ? ParseFlaser(f) : ParseRobotLaser(f);
      if (m.max_range <= 0) m.max_range = front_laser_max_;
      if (corrected_) {
        anchor_ = m.pose;  // following ODOM lines are relative to the logged pose
      } else {
        raw_ = m.odometry;  // the logger's odometry at this scan
      }
      // CARMEN logs a FLASER's pose as the laser's (its logger writes laser_pose there),
      // and the corrected logs correct that pose: the robot sits the PARAM offset behind.
      if (!m.has_offset) m.pose = m.pose + CPose2D(-front_laser_offset_, 0, 0);
      const Stamp stamp = laser_stamps_.Take(m.stamp);
      return Event{Event::kLaser, stamp, raw_, std::move(m), lines_.number()};
    }
    return std::nullopt;  // NEFF, SYNC, TRUEPOS, RLASER, ...
  }

  std::string path_;
  bool corrected_;
  LineReader lines_;
  OnBadRecord on_bad_;
  uint64_t file_size_ = 0;
  std::vector<std::string> skipped_;
  CPose2D raw_;
  std::optional<CPose2D> anchor_;
  StampStream laser_stamps_{"laser"}, odometry_stamps_{"odometry"};
  double front_laser_offset_ = 0;
  double front_laser_max_ = 81.9;
};

mrpt::obs::CObservation2DRangeScan::Ptr ToScan(const LaserMessage& m, double front_laser_offset, Stamp stamp) {
  auto scan = mrpt::obs::CObservation2DRangeScan::Create();
  const size_t n = m.ranges.size();
  const double aperture = m.increment * static_cast<double>(n - 1);
  scan->aperture = static_cast<float>(aperture);
  scan->rightToLeft = true;
  scan->maxRange = static_cast<float>(m.max_range);
  scan->resizeScan(n);
  for (size_t i = 0; i < n; ++i) {
    scan->setScanRange(i, m.ranges[i]);
    scan->setScanRangeValidity(i, m.ranges[i] > 0.0f && m.ranges[i] < m.max_range);
  }
  // MRPT scans are centred on the sensor's x axis: turn the sensor to the scan centre.
  const double centre = m.start_angle + aperture / 2;
  const CPose2D mount = m.has_offset ? m.laser_offset : CPose2D(front_laser_offset, 0, 0);
  scan->sensorPose = mrpt::poses::CPose3D(mount + CPose2D(0, 0, centre));
  scan->sensorLabel = "LASER";
  scan->timestamp = ToMrpt(stamp);
  return scan;
}

class CarmenSource final : public DatasetSource {
 public:
  CarmenSource(std::string path, OnBadRecord on_bad) : path_(std::move(path)), reader_(path_, on_bad) {}

  // A raw log's scan comes after an odometry reading at its own stamp (its line's), so
  // the odometry a scan is paired with is the one at that scan, not the latest ODOM
  // line, whose stamp may be later.
  std::optional<Observation> Next() override {
    if (pending_scan_) return std::exchange(pending_scan_, std::nullopt);
    auto e = reader_.Next();
    if (!e) return std::nullopt;
    if (e->kind == CarmenReader::Event::kOdometry) return Odometry(e->stamp, e->odometry, e->line);
    Observation scan{e->stamp, ToScan(e->laser, reader_.front_laser_offset(), e->stamp), e->line};
    if (reader_.corrected()) return scan;
    pending_scan_ = std::move(scan);
    return Odometry(e->stamp, e->odometry, e->line);
  }
  std::string Path() const override { return path_; }
  std::string Format() const override { return "carmen"; }
  double FractionRead() const override { return reader_.Fraction(); }
  const std::vector<std::string>& SkippedRecords() const override { return reader_.skipped(); }
  std::vector<std::string> Notes() const override { return reader_.Notes(); }

 private:
  static Observation Odometry(Stamp stamp, const CPose2D& pose, int64_t line) {
    auto odo = mrpt::obs::CObservationOdometry::Create();
    odo->odometry = pose;
    odo->timestamp = ToMrpt(stamp);
    odo->sensorLabel = "ODOMETRY";
    return Observation{stamp, odo, line};
  }

  std::string path_;
  CarmenReader reader_;
  std::optional<Observation> pending_scan_;
};

}  // namespace

bool LooksLikeCarmen(const std::string& path) {
  LineReader lines(path);
  std::string line;
  for (int i = 0; i < 50 && lines.Next(line); ++i) {
    if (line.empty() || line[0] == '#') continue;
    const std::string word = line.substr(0, line.find(' '));
    for (const char* k : {"PARAM", "ODOM", "FLASER", "RLASER", "ROBOTLASER1", "SYNC", "NEFF", "TRUEPOS"}) {
      if (word == k) return true;
    }
    return false;
  }
  return false;
}

std::unique_ptr<DatasetSource> OpenCarmen(const std::string& path, OnBadRecord on_bad) {
  return std::make_unique<CarmenSource>(path, on_bad);
}

bool IsCorrectedCarmenLog(const std::string& path) {
  LineReader lines(path);
  std::string line;
  for (int i = 0; i < kCorrectedProbeLines && lines.Next(line); ++i) {
    if (line.rfind("NEFF", 0) == 0) return true;
  }
  return false;
}

Trajectory ReadCarmenReference(const std::string& path) {
  CarmenReader reader(path, OnBadRecord::kSkip);
  if (!reader.corrected()) {
    throw InputError(path +
                     ": a raw CARMEN log (no NEFF lines), not a corrected one: its laser poses are the "
                     "robot's odometry, not a reference (score it with --relations, or give --reference)");
  }
  Trajectory t;
  while (auto e = reader.Next()) {
    if (e->kind == CarmenReader::Event::kLaser) t.push_back({e->stamp, mrpt::poses::CPose3D(e->laser.pose)});
  }
  return t;
}

}  // namespace specht::io
