// Rawlog reading: both formats, and what happens when the file is cut or corrupted.
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPosePDFGaussian.h>
#include <mrpt/serialization/CArchive.h>

#include <random>

#include "specht/io/dataset.h"
#include "test_support.h"

namespace specht::io {
namespace {

struct ReadResult {
  long scans = 0, odometry = 0;
  std::vector<Stamp> stamps;
  std::string error;
  int64_t error_record = -1, error_offset = -1;
};

ReadResult ReadAll(const std::string& path) {
  ReadResult r;
  auto source = OpenDataset(path);
  try {
    while (auto obs = source->Next()) {
      r.stamps.push_back(obs->stamp);
      if (std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs->data)) ++r.scans;
      if (std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs->data)) ++r.odometry;
    }
  } catch (const DatasetError& e) {
    r.error = e.what();
    r.error_record = e.record();
    r.error_offset = e.byte_offset();
  }
  return r;
}

// A gzip rawlog of the given objects, in order, as MRPT writes them.
template <class... Objects>
void WriteRawlog(const std::string& path, const Objects&... objects) {
  mrpt::io::CFileGZOutputStream out(path);
  auto archive = mrpt::serialization::archiveFrom(out);
  (archive << ... << objects);
}

mrpt::obs::CObservationOdometry::Ptr OdometryAt(double seconds) {
  auto odometry = mrpt::obs::CObservationOdometry::Create();
  odometry->timestamp = mrpt::Clock::fromDouble(seconds);
  return odometry;
}

TEST(RawlogTest, ReadsTheBuiltInActionSensoryFrameRawlog) {
  const std::string rawlog = testing::BuiltInRawlog();
  SPECHT_REQUIRE_FILE(rawlog);
  const ReadResult r = ReadAll(rawlog);
  EXPECT_EQ(r.error, "");
  EXPECT_EQ(r.scans, 225);     // rawlog-edit --info: 449 objects, 224 sensory frames
  EXPECT_EQ(r.odometry, 224);  // one chained odometry reading per action
  EXPECT_TRUE(std::is_sorted(r.stamps.begin(), r.stamps.end()));
  EXPECT_NEAR(SecondsBetween(r.stamps.front(), r.stamps.back()), 58.8, 0.5);
}

TEST(RawlogTest, MissingFileIsAnInputError) { EXPECT_THROW(OpenDataset("/nonexistent.rawlog"), InputError); }

TEST(RawlogTest, TruncatedFileStopsAtTheBrokenRecordWithItsOffset) {
  const std::string rawlog = testing::BuiltInRawlog();
  SPECHT_REQUIRE_FILE(rawlog);
  const std::string bytes = testing::ReadDecompressed(rawlog);
  const std::string cut = testing::TempDir() + "/cut.rawlog";
  testing::WriteFile(cut, bytes.substr(0, bytes.size() / 2));
  const ReadResult r = ReadAll(cut);
  EXPECT_THAT(r.error, ::testing::HasSubstr("cut.rawlog: record "));
  EXPECT_THAT(r.error, ::testing::HasSubstr("truncated rawlog"));
  EXPECT_GT(r.error_record, 100);
  EXPECT_LT(r.error_offset, static_cast<int64_t>(bytes.size() / 2));
  EXPECT_GT(r.scans, 100);  // everything before the cut was delivered
}

TEST(RawlogTest, TruncatedGzipStopsCleanly) {
  const std::string rawlog = testing::BuiltInRawlog();
  SPECHT_REQUIRE_FILE(rawlog);
  const std::string gz = testing::ReadFile(rawlog);
  const std::string cut = testing::TempDir() + "/cut.rawlog.gz";
  testing::WriteFile(cut, gz.substr(0, gz.size() * 2 / 3));
  const ReadResult r = ReadAll(cut);
  EXPECT_THAT(r.error, ::testing::HasSubstr("record"));
  EXPECT_GT(r.scans, 50);
}

// Fuzz-style: flip random bytes in random places; the reader must either read on or
// stop with a DatasetError that names a record, never crash or hang.
TEST(RawlogTest, RandomCorruptionIsReportedNeverFatal) {
  const std::string rawlog = testing::BuiltInRawlog();
  SPECHT_REQUIRE_FILE(rawlog);
  const std::string bytes = testing::ReadDecompressed(rawlog);
  std::mt19937 rng(42);
  const std::string path = testing::TempDir() + "/fuzz.rawlog";
  int reported = 0;
  for (int trial = 0; trial < 40; ++trial) {
    std::string corrupt = bytes;
    const int flips = 1 + trial % 8;
    for (int k = 0; k < flips; ++k) {
      corrupt[std::uniform_int_distribution<size_t>(0, corrupt.size() - 1)(rng)] ^= static_cast<char>(1 + rng() % 255);
    }
    testing::WriteFile(path, corrupt);
    const ReadResult r = ReadAll(path);
    if (!r.error.empty()) {
      ++reported;
      EXPECT_THAT(r.error, ::testing::MatchesRegex(".*fuzz.rawlog: record [0-9]+ \\(byte [0-9]+\\): .+"));
    }
  }
  // Most flips land in range data and read on; some hit structure and are reported.
  EXPECT_GT(reported, 0);
}

TEST(RawlogTest, GarbageIsNotARawlog) {
  const std::string path = testing::TempDir() + "/garbage.rawlog";
  testing::WriteFile(path, std::string(1000, 'x'));
  const ReadResult r = ReadAll(path);
  EXPECT_THAT(r.error, ::testing::HasSubstr("record 0 (byte 0)"));
}

// fuzz_rawlog's finding: MRPT 2.5 fills freed memory when it reads a GPS record of
// serialization versions 5–9 that carries TopCon data. Such a record is refused at its
// header, before MRPT reads the body; the records before it are delivered, and a GPS
// record of today's format still reads.
TEST(RawlogTest, LegacyGpsRecordIsRefusedBeforeMrptReadsIt) {
  const std::string path = testing::TempDir() + "/gps.rawlog";
  auto gps = mrpt::obs::CObservationGPS::Create();
  gps->timestamp = mrpt::Clock::fromDouble(100.5);
  WriteRawlog(path, *OdometryAt(100.0), *gps);
  ReadResult r = ReadAll(path);
  EXPECT_EQ(r.error, "");
  EXPECT_EQ(r.stamps.size(), 2u);

  // The legacy header: length byte, class name, version 8 (the body does not matter:
  // it is never read).
  const std::string bytes = testing::ReadDecompressed(path);
  const size_t at = bytes.find("mrpt::obs::CObservationGPS") - 1;
  const std::string header = std::string(1, '\x8f') + "CObservationGPS" + std::string(1, '\x08');
  const std::string legacy = bytes.substr(0, at) + header + std::string(64, '\x01');
  testing::WriteFile(path, legacy);
  r = ReadAll(path);
  EXPECT_EQ(r.odometry, 1);
  EXPECT_EQ(r.error_record, 1);
  EXPECT_EQ(r.error_offset, static_cast<int64_t>(at));
  EXPECT_THAT(r.error, ::testing::HasSubstr("GPS observation in MRPT's pre-1.4 format (version 8)"));
}

// fuzz_rawlog: a stamp beyond the years a Stamp holds overflowed its conversion.
TEST(RawlogTest, StampOutOfRangeIsNamed) {
  const std::string path = testing::TempDir() + "/far.rawlog";
  auto odometry = OdometryAt(0.0);
  odometry->sensorLabel = "ODO";
  odometry->timestamp = mrpt::Clock::time_point(mrpt::Clock::duration(-6315051035256397823LL));
  WriteRawlog(path, *odometry);
  const ReadResult r = ReadAll(path);
  EXPECT_THAT(r.error,
              ::testing::HasSubstr("far.rawlog: record 0 (byte 0): observation 'ODO' has a time stamp out of range"));
  EXPECT_TRUE(RepresentableAsStamp(mrpt::Clock::fromDouble(1.7e9)));
}

// fuzz_rawlog: a movement action whose pose PDF was another class made MRPT 2.5 clone a
// null pointer inside CActionRobotMovement2D::serializeFrom.
TEST(RawlogTest, MovementActionWithoutAPosePdfIsRefusedBeforeMrptReadsIt) {
  const std::string path = testing::TempDir() + "/movement.rawlog";
  mrpt::obs::CActionRobotMovement2D move;
  move.estimationMethod = mrpt::obs::CActionRobotMovement2D::emScan2DMatching;
  move.poseChange = mrpt::poses::CPosePDFGaussian::Create(mrpt::poses::CPose2D(1.0, 0.5, 0.1));
  move.timestamp = mrpt::Clock::fromDouble(100.0);
  mrpt::obs::CActionCollection actions;
  actions.insert(move);
  WriteRawlog(path, actions);
  ReadResult r = ReadAll(path);
  EXPECT_EQ(r.error, "");  // a scan-matching estimate with its PDF is read
  ASSERT_EQ(r.odometry, 1);

  // The PDF's header swapped for another class (the body never gets read).
  const std::string bytes = testing::ReadDecompressed(path);
  const std::string name = "mrpt::poses::CPosePDFGaussian";
  const size_t at = bytes.find(name) - 1;
  testing::WriteFile(path, bytes.substr(0, at) + "\x94mrpt::poses::CPose2D" + bytes.substr(at + 1 + name.size()));
  r = ReadAll(path);
  EXPECT_EQ(r.error_record, 0);
  EXPECT_THAT(r.error,
              ::testing::HasSubstr("movement action whose pose PDF is a 'mrpt::poses::CPose2D', not a CPosePDF"));
}

// A sensory frame or action collection holding another class reads as a null entry.
TEST(RawlogTest, ContainerHoldingTheWrongClassIsNamed) {
  const std::string path = testing::TempDir() + "/frame.rawlog";
  mrpt::obs::CSensoryFrame frame;
  frame.insert(OdometryAt(100.0));
  WriteRawlog(path, frame);
  ASSERT_EQ(ReadAll(path).odometry, 1);
  // An odometry observation's body starts with its pose: a CPose2D written in full.
  const std::string bytes = testing::ReadDecompressed(path);
  const size_t at = bytes.find("CObservationOdometry") - 1;
  WriteRawlog(path, mrpt::poses::CPose2D(1, 2, 3));
  const std::string pose = testing::ReadDecompressed(path);
  testing::WriteFile(path, bytes.substr(0, at) + pose + bytes.back());  // the frame's end marker
  const ReadResult r = ReadAll(path);
  EXPECT_THAT(r.error, ::testing::HasSubstr("sensory frame holds an object that is not an observation"));
}

// MRPT would build any registered class a record names and run its deserializer; a
// rawlog holds observations and actions, so a map in it is refused unread.
TEST(RawlogTest, ClassARawlogDoesNotHoldIsRefusedUnread) {
  const std::string path = testing::TempDir() + "/map.rawlog";
  WriteRawlog(path, *OdometryAt(100.0), mrpt::maps::COccupancyGridMap2D(-1.0f, 1.0f, -1.0f, 1.0f, 0.5f));
  const ReadResult r = ReadAll(path);
  EXPECT_EQ(r.odometry, 1);
  EXPECT_EQ(r.error_record, 1);
  EXPECT_THAT(r.error,
              ::testing::HasSubstr("object of class 'mrpt::maps::COccupancyGridMap2D', which a rawlog does not hold"));
}

}  // namespace
}  // namespace specht::io
