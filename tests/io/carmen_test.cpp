// CARMEN logs: the real Radish logs, the odometry chain, and malformed lines.
#include "specht/io/carmen.h"

#include <bzlib.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <set>

#include "specht/io/line_reader.h"
#include "specht/io/trajectory_io.h"
#include "test_support.h"

namespace specht::io {
namespace {

using ::testing::HasSubstr;

struct Counts {
  long scans = 0, odometry = 0;
  mrpt::poses::CPose2D last_odometry;
  std::string error;
  std::vector<std::string> skipped;
};

Counts CountRecords(const std::string& path, OnBadRecord on_bad = OnBadRecord::kStop) {
  Counts c;
  auto source = OpenDataset(path, on_bad);
  try {
    while (auto obs = source->Next()) {
      if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs->data)) {
        ++c.odometry;
        c.last_odometry = odo->odometry;
      }
      if (std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs->data)) ++c.scans;
    }
  } catch (const DatasetError& e) {
    c.error = e.what();
  }
  c.skipped = source->SkippedRecords();
  return c;
}

TEST(CarmenTest, ReadsTheIntelLogAndItsReference) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  const std::string log = data + "/slam/carmen/intel-corrected.log.gz";
  const Counts c = CountRecords(log);
  EXPECT_EQ(c.error, "");
  EXPECT_EQ(c.scans, 910);
  EXPECT_EQ(c.odometry, 14541);
  const Trajectory reference = ReadCarmenReference(log);
  ASSERT_EQ(reference.size(), 910u);
  // The chained raw odometry ends about 60 m from the corrected pose (data README:
  // 40-65 m on these logs): the re-anchoring at each laser message is undone.
  const mrpt::poses::CPose2D first(reference.front().pose), last(reference.back().pose);
  const mrpt::poses::CPose2D odometry_end = first + c.last_odometry;
  EXPECT_GT(odometry_end.distanceTo(last), 40.0);
  EXPECT_LT(odometry_end.distanceTo(last), 65.0);
}

// A corrected log (its NEFF line says so: laser poses are the reference, ODOM is
// re-anchored at each laser message), or a raw one.
std::string Log(const std::string& body, bool corrected = true) {
  const std::string path = testing::TempDir() + "/test.log";
  testing::WriteFile(
      path, "# CARMEN log\nPARAM robot_frontlaser_offset 0.1 host 0\n" + body + (corrected ? "NEFF 10\n" : ""));
  return path;
}

std::string Flaser(int beams, const std::string& first_range = "1.5", double t = 1.0,
                   const std::string& pose = "1 2 0.5 1 2 0.5") {
  std::string line = "FLASER " + std::to_string(beams) + " " + first_range;
  for (int i = 1; i < beams; ++i) line += " 2.0";
  return line + " " + pose + " " + std::to_string(t) + " host " + std::to_string(t) + "\n";
}

// Every observation in order: kind ('O' odometry, 'S' scan), stamp, odometry x.
struct Record {
  char kind;
  double t, x;
};
// The source's notes once it has read everything go to `notes`.
std::vector<Record> Records(const std::string& path, std::vector<std::string>* notes = nullptr) {
  std::vector<Record> out;
  auto source = OpenDataset(path);
  while (auto obs = source->Next()) {
    auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(obs->data);
    out.push_back({odo ? 'O' : 'S', obs->stamp.Seconds(), odo ? odo->odometry.x() : 0.0});
  }
  if (notes) *notes = source->Notes();
  return out;
}

TEST(CarmenTest, ParsesFlaserAndOdometryWithTheLaserOffset) {
  const std::string path = Log("ODOM 0 0 0 0 0 0 0.5 host 0.5\n" + Flaser(181) + "ODOM 1 2 0.5 0 0 0 1.1 host 1.1\n" +
                               "ODOM 2 2 0.5 0 0 0 1.2 host 1.2\n");
  auto source = OpenDataset(path);
  EXPECT_EQ(source->Format(), "carmen");
  std::optional<Observation> obs;
  while ((obs = source->Next()) && !std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs->data)) {
  }
  ASSERT_TRUE(obs.has_value());
  auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs->data);
  EXPECT_EQ(scan->getScanSize(), 181u);
  EXPECT_NEAR(scan->aperture, M_PI, 1e-6);
  EXPECT_NEAR(scan->sensorPose.x(), 0.1, 1e-9);
  EXPECT_NEAR(obs->stamp.Seconds(), 1.0, 1e-9);
  const Counts c = CountRecords(path);
  // After the laser message the chain continues from its pose: 1 m forward in the
  // laser's heading frame (0.5 rad), from the origin.
  EXPECT_NEAR(c.last_odometry.norm(), 1.0, 1e-6);
}

// CARMEN's own beam spacing (carmen_laser_get_angle_increment): even counts are a
// SICK with its last beam dropped, so 180 beams span 179° at 1°, not 180° at 180/179°.
TEST(CarmenTest, FlaserBeamSpacingIsCarmens) {
  struct Case {
    int beams;
    double aperture_deg, centre_deg;
  };
  for (const Case& c : {Case{180, 179.0, -0.5}, Case{181, 180.0, 0.0}, Case{360, 179.5, -0.25}, Case{361, 180.0, 0.0},
                        Case{100, 180.0, 0.0}}) {
    auto source = OpenDataset(Log(Flaser(c.beams)));
    std::optional<Observation> obs;
    while ((obs = source->Next()) && !std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs->data)) {
    }
    ASSERT_TRUE(obs.has_value()) << c.beams;
    auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs->data);
    EXPECT_NEAR(mrpt::RAD2DEG(scan->aperture), c.aperture_deg, 1e-4) << c.beams << " beams";
    // MRPT centres the scan on the sensor's x axis: the mount turns it to the scan centre.
    EXPECT_NEAR(mrpt::RAD2DEG(scan->sensorPose.yaw()), c.centre_deg, 1e-4) << c.beams << " beams";
  }
}

// A FLASER line's pose is the laser's; the reference is the robot's, the PARAM offset
// behind it (0.1 m here, heading 0.5 rad), as the scans' sensor pose puts the laser.
TEST(CarmenTest, FlaserReferenceIsTheRobotBehindTheLaser) {
  const Trajectory reference = ReadCarmenReference(Log(Flaser(181)));
  ASSERT_EQ(reference.size(), 1u);
  const mrpt::poses::CPose2D robot(reference.front().pose);
  EXPECT_NEAR(robot.x(), 1 - 0.1 * std::cos(0.5), 1e-9);
  EXPECT_NEAR(robot.y(), 2 - 0.1 * std::sin(0.5), 1e-9);
  EXPECT_NEAR(robot.phi(), 0.5, 1e-9);
}

TEST(CarmenTest, MalformedLinesAreNamedByLine) {
  EXPECT_THAT(CountRecords(Log(Flaser(181).substr(0, 300) + "\n")).error,
              HasSubstr("test.log:3: FLASER with 181 beams needs at least 190 fields"));
  EXPECT_THAT(CountRecords(Log(Flaser(10, "nan"))).error, HasSubstr("test.log:3: field 'range 1' is nan"));
  EXPECT_THAT(CountRecords(Log(Flaser(10, "-1"))).error, HasSubstr("test.log:3: 'range 1' is negative"));
  EXPECT_THAT(CountRecords(Log("ODOM 1 2\n")).error, HasSubstr("test.log:3: ODOM needs at least 8 fields, got 3"));
  EXPECT_THAT(CountRecords(Log("ODOM 1 x 0 0 0 0 1 host 1\n")).error,
              HasSubstr("test.log:3: field 'y' is not a number: 'x'"));
  EXPECT_THAT(CountRecords(Log("FLASER 0\n")).error, HasSubstr("test.log:3: 'num_readings' must be a positive count"));
  // Found by fuzz_carmen: a stamp no clock holds overflowed the stamp arithmetic.
  EXPECT_THAT(CountRecords(Log("ODOM 1 2 0 0 0 0 1 host 1\nODOM 1 2 0 0 0 0 -9.7e17 host 1\n")).error,
              HasSubstr("test.log:4: 'ipc_timestamp' is out of range: -9.7e17"));
  // fr-clinic's ROBOTLASER1, cut short after its remissions: the fields it lacks.
  EXPECT_THAT(CountRecords(Log("ROBOTLASER1 0 -0.2 0.4 0.1 30 0.01 0 5 1 1 1 1 1 0 1.3 0 0 1 0\n")).error,
              HasSubstr("test.log:3: ROBOTLASER1 with 5 beams needs at least 27 fields, got 20"));
  // Found by fuzz_trajectory: a remission count no integer holds overflowed its conversion.
  EXPECT_THAT(CountRecords(Log("ROBOTLASER1 0 -0.2 0.4 0.1 30 0.01 0 5 1 1 1 1 1 3.2e45 1.3 0 0 1 0\n")).error,
              HasSubstr("test.log:3: 'num_remissions' must be a count no larger than the line"));
}

TEST(CarmenTest, SkipModeGoesOnAndListsWhatItSkipped) {
  const Counts c = CountRecords(
      Log(Flaser(10, "nan", 1.0) + Flaser(10, "1.5", 2.0) + "ODOM 1 2\n" + Flaser(10, "1.5", 3.0)), OnBadRecord::kSkip);
  EXPECT_EQ(c.error, "");
  EXPECT_EQ(c.scans, 2);
  ASSERT_EQ(c.skipped.size(), 2u);
  EXPECT_THAT(c.skipped[0], HasSubstr("test.log:3: "));
  EXPECT_THAT(c.skipped[1], HasSubstr("test.log:5: "));
}

TEST(CarmenTest, ParsesRobotLaser1WithItsMount) {
  // 5 beams from -0.2 rad in steps of 0.1 rad, laser 0.3 m ahead of the robot.
  const std::string line = "ROBOTLASER1 0 -0.2 0.4 0.1 30 0.01 0 5 1 1 1 1 1 0 1.3 0 0 1 0 0 0 0 0 0 0 7.5 host 7.5\n";
  auto source = OpenDataset(Log(line));
  const auto obs = source->Next();
  ASSERT_TRUE(obs.has_value());
  auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs->data);
  ASSERT_TRUE(scan);
  EXPECT_NEAR(scan->aperture, 0.4, 1e-6);
  EXPECT_NEAR(scan->sensorPose.x(), 0.3, 1e-9);
  EXPECT_NEAR(scan->sensorPose.yaw(), 0.0, 1e-9);  // centred: -0.2 + 0.4 / 2
  EXPECT_NEAR(obs->stamp.Seconds(), 7.5, 1e-9);
}

TEST(CarmenTest, LogsWithoutTimeStampsAreStampedInOrder) {
  const std::string path = Log(Flaser(10, "1.5", 0.0) + Flaser(10, "1.5", 0.0) + Flaser(10, "1.5", 0.0));
  const Trajectory t = ReadCarmenReference(path);
  ASSERT_EQ(t.size(), 3u);
  EXPECT_LT(t[0].stamp, t[1].stamp);
  EXPECT_LT(t[1].stamp, t[2].stamp);
  const auto notes = OpenDataset(path)->Notes();
  ASSERT_FALSE(notes.empty());
  EXPECT_THAT(notes.front(), HasSubstr("a corrected log"));
}

// A raw log: a scan's odometry is its own line's (the logger's odometry at the scan),
// delivered at the scan's stamp just before it, not the ODOM line stamped after the
// scan that precedes it in the file; stamps that go backwards are kept and counted.
TEST(CarmenTest, RawLogPairsEachScanWithItsOwnOdometryAndKeepsItsStamps) {
  const std::string path =
      Log("ODOM 1.0 0 0 0 0 0 1.0 host 1.0\n"
          "ODOM 2.0 0 0 0 0 0 1.2 host 1.2\n" +
              Flaser(10, "1.5", 1.1, "1.5 0 0 1.5 0 0") + Flaser(10, "1.5", 1.05, "1.7 0 0 1.7 0 0") +
              "ODOM 2.5 0 0 0 0 0 1.3 host 1.3\n",
          /*corrected=*/false);
  std::vector<std::string> notes;
  const auto r = Records(path, &notes);
  ASSERT_EQ(r.size(), 7u);
  const std::string kinds{r[0].kind, r[1].kind, r[2].kind, r[3].kind, r[4].kind, r[5].kind, r[6].kind};
  EXPECT_EQ(kinds, "OOOSOSO");
  EXPECT_DOUBLE_EQ(r[2].t, 1.1);  // the scan's own odometry, at its stamp
  EXPECT_DOUBLE_EQ(r[2].x, 1.5);
  EXPECT_DOUBLE_EQ(r[3].t, 1.1);
  EXPECT_DOUBLE_EQ(r[5].t, 1.05);  // backwards, kept as logged
  EXPECT_DOUBLE_EQ(r[6].x, 2.5);   // ODOM lines are absolute odometry in a raw log
  ASSERT_EQ(notes.size(), 2u);
  EXPECT_THAT(notes[0], HasSubstr("a raw log"));
  EXPECT_THAT(notes[1], HasSubstr("laser: 1 stamps go backwards (by up to 0.050 s): kept as logged"));
  try {
    ReadCarmenReference(path);
    FAIL() << "a raw log's odometry taken as a reference";
  } catch (const InputError& e) {
    EXPECT_THAT(e.what(), HasSubstr("test.log: a raw CARMEN log"));
  }
}

// The Freiburg benchmark's raw logs: the scans carry the log's own stamps, so every
// published relation of Intel (whose laser stamps go backwards 631 times) and FR079
// (whose ODOM lines run ahead of the scans after them) finds its two scans.
TEST(CarmenTest, RawFreiburgScansCarryTheStampsThePublishedRelationsName) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  for (const char* name : {"intel", "fr079"}) {
    const std::string log = data + "/slam/freiburg/" + std::string(name) + ".clf.bz2";
    SPECHT_REQUIRE_FILE(log);
    auto source = OpenDataset(log);
    Trajectory scans;
    while (auto obs = source->Next()) {
      if (std::dynamic_pointer_cast<mrpt::obs::CObservation2DRangeScan>(obs->data)) scans.push_back({obs->stamp, {}});
    }
    const auto relations = ReadRelations(DefaultRelationsPath(log));
    std::set<int64_t> stamps;
    for (const auto& s : scans) stamps.insert(s.stamp.ns);
    size_t matched = 0;
    for (const auto& r : relations.relations) {
      matched += stamps.count(r.t1.ns) && stamps.count(r.t2.ns);
    }
    EXPECT_EQ(matched, relations.relations.size()) << name;
    if (std::string(name) == "intel") {
      EXPECT_EQ(scans.size(), 13631u);
      EXPECT_THAT(source->Notes().at(1), HasSubstr("laser: 631 stamps go backwards"));
    }
  }
}

TEST(CarmenTest, TruncatedGzipStopsWithTheLineWhereItBreaks) {
  const std::string data = testing::DataDir();
  SPECHT_REQUIRE_FILE(data);
  const std::string gz = testing::ReadFile(data + "/slam/carmen/freiburg-101-corrected.log.gz");
  const std::string cut = testing::TempDir() + "/cut.log.gz";
  testing::WriteFile(cut, gz.substr(0, gz.size() / 2));
  const Counts c = CountRecords(cut);
  EXPECT_THAT(c.error, HasSubstr("truncated or corrupt gzip file"));
  EXPECT_THAT(c.error, ::testing::MatchesRegex(".*cut.log.gz:[0-9]+: .*"));
  EXPECT_GT(c.scans, 50);  // what came before the break was delivered
  EXPECT_LT(c.scans, 292);
}

// bzip2, as the Freiburg benchmark ships its logs, in one stream or several one after
// another (pbzip2): the same lines as the plain file; cut short, an error naming the
// line it broke at.
std::string Bzip2(const std::string& text) {
  std::vector<char> out(text.size() + text.size() / 100 + 600);
  unsigned n = static_cast<unsigned>(out.size());
  EXPECT_EQ(BZ2_bzBuffToBuffCompress(out.data(), &n, const_cast<char*>(text.data()), static_cast<unsigned>(text.size()),
                                     9, 0, 0),
            BZ_OK);
  return std::string(out.data(), n);
}

std::vector<std::string> Lines(const std::string& path) {
  LineReader reader(path);
  std::vector<std::string> lines;
  for (std::string line; reader.Next(line);) lines.push_back(line);
  return lines;
}

TEST(CarmenTest, ReadsBzip2InOneStreamOrSeveral) {
  std::string text;
  for (int i = 0; i < 5000; ++i)
    text += "ODOM " + std::to_string(i * 0.01) + " 0 0 0 0 0 " + std::to_string(i) + " h 0\n";
  const std::string dir = testing::TempDir(), plain = dir + "/odom.log";
  testing::WriteFile(plain, text);
  testing::WriteFile(dir + "/one.log.bz2", Bzip2(text));
  const size_t half = text.find('\n', text.size() / 2) + 1;
  testing::WriteFile(dir + "/two.log.bz2", Bzip2(text.substr(0, half)) + Bzip2(text.substr(half)));
  const auto expected = Lines(plain);
  ASSERT_EQ(expected.size(), 5000u);
  EXPECT_EQ(Lines(dir + "/one.log.bz2"), expected);
  EXPECT_EQ(Lines(dir + "/two.log.bz2"), expected);
  EXPECT_EQ(CountRecords(dir + "/two.log.bz2").odometry, 5000);

  const std::string whole = Bzip2(text);
  testing::WriteFile(dir + "/cut.log.bz2", whole.substr(0, whole.size() / 2));
  try {
    Lines(dir + "/cut.log.bz2");
    FAIL() << "a truncated bzip2 file read to its end";
  } catch (const DatasetError& e) {
    EXPECT_THAT(e.what(), HasSubstr("cut.log.bz2"));
    EXPECT_THAT(e.what(), HasSubstr("truncated or corrupt bzip2 file"));
  }
}

}  // namespace
}  // namespace specht::io
