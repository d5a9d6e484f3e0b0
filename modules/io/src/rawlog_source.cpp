// Reads MRPT rawlogs object by object, so that a corrupt or truncated file is
// reported at the record where it breaks (MRPT's own CRawlog helpers treat any
// error as the end of the file, which would silently cut a replay short).
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDF.h>
#include <mrpt/rtti/CObject.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/system/datetime.h>

#include <algorithm>
#include <deque>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "little_endian.h"
#include "specht/io/dataset.h"

namespace specht::io {
namespace {

// MRPT exception texts carry a call stack; keep the reason only.
std::string Reason(const std::exception& e) {
  std::string text = e.what();
  const auto pos = text.find_last_of('\n', text.find_last_not_of("\n "));
  std::string last = pos == std::string::npos ? text : text.substr(pos + 1);
  while (!last.empty() && (last.back() == '\n' || last.back() == ' ')) last.pop_back();
  const auto msg = text.find("Message:");
  if (msg != std::string::npos) {
    last = text.substr(msg + 8);
    last = last.substr(0, last.find('\n'));
    while (!last.empty() && last.front() == ' ') last.erase(0, 1);
  }
  return last.empty() ? "unreadable record" : last;
}

// Size of the decompressed stream: the file size, or for gzip the ISIZE field of
// its trailer (size modulo 2^32; good for progress, which is all it is used for).
uint64_t UncompressedSize(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char magic[2] = {0, 0};
  in.read(reinterpret_cast<char*>(magic), 2);
  in.seekg(0, std::ios::end);
  const auto size = static_cast<uint64_t>(in.tellg());
  if (!(magic[0] == 0x1f && magic[1] == 0x8b) || size < 18) return size;
  unsigned char isize[4];
  in.seekg(-4, std::ios::end);
  in.read(reinterpret_cast<char*>(isize), 4);
  return uint64_t(isize[0]) | uint64_t(isize[1]) << 8 | uint64_t(isize[2]) << 16 | uint64_t(isize[3]) << 24;
}

// MRPT builds whatever registered class a record names and runs its deserializer, and
// several of those in MRPT 2.5 touch invalid memory on a corrupt record (found by
// fuzz_rawlog). Refused before MRPT reads their body:
// - any class a robot log does not carry (maps, graphs, 3D scenes: a record naming one
//   can only be corrupt); what a log carries is listed in IsRawlogClass;
// - a GPS observation of serialization versions 5–9 (rawlogs of MRPT before 1.4):
//   CObservationGPS::serializeFrom hands a new TopCon PZS or satellite message to its
//   map by copy, which deletes it, then fills the deleted one. Which message a record
//   carries is known only by reading it, so every GPS record of those versions goes.
// - a movement action whose pose PDF is not a CPosePDF (version 0–1, or a method other
//   than odometry): ReadObject<CPosePDF> casts the wrong class to null and
//   CActionRobotMovement2D::serializeFrom clones the null pointer.
// The guard sits between the file and MRPT's archive and sees each read as the archive
// makes it: an object header is a length byte, the class name, then the version (one
// byte; four in the pre-0.5.5 format); a movement action's body starts with its method
// (four bytes, 0 = odometry). A body read can look like a header; a class name it
// spells by chance is not registered, and only registered names are judged.
class GuardStream final : public mrpt::io::CStream {
 public:
  bool open(const std::string& path) { return in_.open(path); }
  const std::string& refusal() const { return refusal_; }

  size_t Read(void* buffer, size_t count) override {
    const size_t n = in_.Read(buffer, count);
    Inspect(static_cast<const unsigned char*>(buffer), n);
    return n;
  }
  size_t Write(const void*, size_t) override { throw std::logic_error("rawlog input is read-only"); }
  uint64_t Seek(int64_t offset, TSeekOrigin origin) override { return in_.Seek(offset, origin); }
  uint64_t getTotalBytesCount() const override { return in_.getTotalBytesCount(); }
  uint64_t getPosition() const override { return in_.getPosition(); }

 private:
  enum class Expect { kAnything, kVersion, kMethod };

  void Inspect(const unsigned char* bytes, size_t n) {
    const std::string_view read(reinterpret_cast<const char*>(bytes), n);
    const bool is_name = n > 0 && n == name_length_;
    const Expect expected = std::exchange(expect_, Expect::kAnything);
    if (expected == Expect::kVersion && (n == 1 || n == 4)) CheckVersion(static_cast<uint32_t>(LittleEndian(bytes, n)));
    if (expected == Expect::kMethod && n == 4 && LittleEndian(bytes, n) != 0) pdf_next_ = true;
    if (is_name) OnClassName(read);
    if (n != 3) name_length_ = n == 1 ? (bytes[0] & 0x7F) : 0;  // 3: the old format's zero bytes
  }

  void OnClassName(std::string_view name) {
    const auto* cls = mrpt::rtti::findRegisteredClass(std::string(name));
    if (std::exchange(pdf_next_, false) && (cls == nullptr || !cls->derivedFrom(CLASS_ID(mrpt::poses::CPosePDF))))
      Refuse("movement action whose pose PDF is a '" + std::string(name) + "', not a CPosePDF");
    if (cls != nullptr && !IsRawlogClass(*cls))
      Refuse("object of class '" + std::string(name) + "', which a rawlog does not hold");
    class_ = cls;
    if (class_ == CLASS_ID(mrpt::obs::CObservationGPS) || class_ == CLASS_ID(mrpt::obs::CActionRobotMovement2D))
      expect_ = Expect::kVersion;
  }

  void CheckVersion(uint32_t version) {
    if (class_ == CLASS_ID(mrpt::obs::CObservationGPS) && version >= 5 && version <= 9)
      Refuse("GPS observation in MRPT's pre-1.4 format (version " + std::to_string(version) +
             "), which MRPT 2.5 cannot read safely; convert the rawlog with a newer MRPT");
    if (class_ == CLASS_ID(mrpt::obs::CActionRobotMovement2D)) {
      if (version <= 1)
        pdf_next_ = true;
      else
        expect_ = Expect::kMethod;
    }
  }

  // Observations, actions and what they hold as objects: poses, PDFs, images, camera
  // models, matrices and point clouds. Not maps, graphs or 3D scenes (so not the rare
  // CObservation3DScene, whose OpenGL scene MRPT's deserializers read).
  static bool IsRawlogClass(const mrpt::rtti::TRuntimeClassId& cls) {
    static const auto* points = mrpt::rtti::findRegisteredClass("mrpt::maps::CPointsMap");
    const std::string_view name = cls.className;
    for (std::string_view space : {"mrpt::obs::", "mrpt::poses::", "mrpt::img::", "mrpt::math::"}) {
      if (name.substr(0, space.size()) == space) return name != "mrpt::obs::CObservation3DScene";
    }
    return points != nullptr && cls.derivedFrom(points);
  }

  [[noreturn]] void Refuse(std::string reason) {
    refusal_ = std::move(reason);
    throw std::runtime_error(refusal_);
  }

  mrpt::io::CFileGZInputStream in_;
  size_t name_length_ = 0;
  Expect expect_ = Expect::kAnything;
  bool pdf_next_ = false;
  const mrpt::rtti::TRuntimeClassId* class_ = nullptr;  // of the header being read
  std::string refusal_;
};

class RawlogSource final : public DatasetSource {
 public:
  explicit RawlogSource(std::string path) : path_(std::move(path)) {
    bool opened = false;
    try {
      opened = in_.open(path_);
    } catch (const std::exception&) {
      opened = false;  // MRPT throws on some failures instead of returning false
    }
    if (!opened) throw InputError(path_ + ": cannot open rawlog");
    data_size_ = UncompressedSize(path_);
  }

  std::optional<Observation> Next() override {
    while (pending_.empty()) {
      if (!ReadRecord()) return std::nullopt;
    }
    Observation o = std::move(pending_.front());
    pending_.pop_front();
    return o;
  }

  std::string Path() const override { return path_; }
  std::string Format() const override { return format_.empty() ? "rawlog" : format_; }
  double FractionRead() const override {
    if (data_size_ == 0) return -1.0;
    return std::min(1.0, static_cast<double>(in_.getPosition()) / static_cast<double>(data_size_));
  }

 private:
  bool ReadRecord() {
    const int64_t start = static_cast<int64_t>(in_.getPosition());
    mrpt::serialization::CSerializable::Ptr object;
    try {
      auto archive = mrpt::serialization::archiveFrom(in_);
      archive >> object;
    } catch (const mrpt::serialization::CExceptionEOF&) {
      // MRPT turns any error inside an object, the guard's refusal too, into "EOF".
      if (!in_.refusal().empty()) throw DatasetError(path_, record_, start, in_.refusal());
      if (static_cast<int64_t>(in_.getPosition()) == start) return false;  // clean end
      throw DatasetError(path_, record_, start, "file ends inside this record (truncated rawlog)");
    } catch (const std::bad_alloc&) {
      throw DatasetError(path_, record_, start, "corrupt record (implausible size field)");
    } catch (const std::exception& e) {
      if (!in_.refusal().empty()) throw DatasetError(path_, record_, start, in_.refusal());
      // MRPT wraps an end of file met inside an object into a generic exception.
      if (AtEnd()) throw DatasetError(path_, record_, start, "file ends inside this record (truncated rawlog)");
      throw DatasetError(path_, record_, start, "corrupt record: " + Reason(e));
    }
    if (!object) throw DatasetError(path_, record_, start, "empty object in rawlog");
    Dispatch(object, start);
    ++record_;
    return true;
  }

  bool AtEnd() {
    char byte = 0;
    return in_.Read(&byte, 1) == 0;
  }

  void Dispatch(const mrpt::serialization::CSerializable::Ptr& object, int64_t start) {
    using namespace mrpt::obs;
    if (auto obs = std::dynamic_pointer_cast<CObservation>(object)) {
      SetFormat("rawlog (observations)");
      Push(obs, start);
    } else if (auto actions = std::dynamic_pointer_cast<CActionCollection>(object)) {
      SetFormat("rawlog (actions/sensory frames)");
      AddOdometryIncrement(*actions, start);
    } else if (auto frame = std::dynamic_pointer_cast<CSensoryFrame>(object)) {
      SetFormat("rawlog (actions/sensory frames)");
      for (const auto& obs : *frame) {
        if (!obs) throw DatasetError(path_, record_, start, "sensory frame holds an object that is not an observation");
        if (pending_odometry_stamp_) {
          EmitOdometry(obs->timestamp, start);
        }
        Push(obs, start);
      }
    } else {
      throw DatasetError(path_, record_, start,
                         std::string("unexpected object of class ") + object->GetRuntimeClass()->className);
    }
  }

  void SetFormat(const char* f) {
    if (format_.empty()) format_ = f;
  }

  // Chains CActionRobotMovement2D increments into an absolute odometry reading.
  void AddOdometryIncrement(const mrpt::obs::CActionCollection& actions, int64_t start) {
    for (const auto& action : actions) {
      if (!action) throw DatasetError(path_, record_, start, "action collection holds an object that is not an action");
    }
    auto move = actions.getBestMovementEstimation();
    if (!move) return;
    odometry_ = odometry_ + move->poseChange->getMeanVal();
    pending_odometry_stamp_ = true;
    if (move->timestamp != INVALID_TIMESTAMP) EmitOdometry(move->timestamp, start);
  }

  void EmitOdometry(mrpt::Clock::time_point stamp, int64_t start) {
    auto odo = mrpt::obs::CObservationOdometry::Create();
    odo->odometry = odometry_;
    odo->timestamp = stamp;
    odo->sensorLabel = "ODOMETRY";
    pending_.push_back(Observation{StampOf(stamp, start, "odometry"), odo, record_});
    pending_odometry_stamp_ = false;
  }

  void Push(const mrpt::obs::CObservation::Ptr& obs, int64_t start) {
    if (obs->timestamp == INVALID_TIMESTAMP) {
      throw DatasetError(path_, record_, start, "observation '" + obs->sensorLabel + "' has no time stamp");
    }
    pending_.push_back(
        Observation{StampOf(obs->timestamp, start, "observation '" + obs->sensorLabel + "'"), obs, record_});
  }

  Stamp StampOf(mrpt::Clock::time_point t, int64_t start, const std::string& what) const {
    if (!RepresentableAsStamp(t)) throw DatasetError(path_, record_, start, what + " has a time stamp out of range");
    return FromMrpt(t);
  }

  std::string path_;
  GuardStream in_;
  uint64_t data_size_ = 0;
  std::string format_;
  std::deque<Observation> pending_;
  int64_t record_ = 0;
  mrpt::poses::CPose2D odometry_;
  bool pending_odometry_stamp_ = false;
};

}  // namespace

std::unique_ptr<DatasetSource> OpenRawlog(const std::string& path) {
  // Images stored beside the rawlog (MRPT's convention: <name>_Images/) load from there.
  const std::filesystem::path p(path);
  mrpt::img::CImage::setImagesPathBase((p.parent_path() / (p.stem().string() + "_Images")).string());
  return std::make_unique<RawlogSource>(path);
}

}  // namespace specht::io
