// Output formats: ROS map_server, MRPT gridmap, TUM, PNG, reports, videos; all atomic.
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "specht/core/error.h"
#include "specht/io/atomic_file.h"
#include "specht/io/map_io.h"
#include "specht/io/report.h"
#include "specht/io/trajectory_io.h"
#include "specht/io/video.h"
#include "test_support.h"

namespace specht::io {
namespace {

namespace fs = std::filesystem;
using mrpt::maps::COccupancyGridMap2D;

// A 4 m x 3 m room at 0.1 m: free inside, walls on the border, unknown outside.
COccupancyGridMap2D Room() {
  COccupancyGridMap2D grid(-1.0f, 5.0f, -1.0f, 4.0f, 0.1f);
  for (unsigned y = 0; y < grid.getSizeY(); ++y) {
    for (unsigned x = 0; x < grid.getSizeX(); ++x) {
      const double wx = grid.idx2x(x), wy = grid.idx2y(y);
      const bool inside = wx > 0 && wx < 4 && wy > 0 && wy < 3;
      const bool wall = inside && (wx < 0.1 || wx > 3.9 || wy < 0.1 || wy > 2.9);
      if (wall)
        grid.setCell(x, y, 0.05f);
      else if (inside)
        grid.setCell(x, y, 0.95f);
    }
  }
  return grid;
}

TEST(MapIoTest, RosMapRoundTripKeepsEveryCellClassAndTheOrigin) {
  const std::string dir = testing::TempDir();
  const COccupancyGridMap2D room = Room();
  WriteRosMap(room, dir + "/room.yaml");
  EXPECT_THAT(testing::ReadFile(dir + "/room.yaml"), ::testing::HasSubstr("image: room.pgm"));
  const COccupancyGridMap2D back = ReadRosMap(dir + "/room.yaml");
  ASSERT_EQ(back.getSizeX(), room.getSizeX());
  ASSERT_EQ(back.getSizeY(), room.getSizeY());
  EXPECT_NEAR(back.getXMin(), room.getXMin(), 1e-6);
  EXPECT_NEAR(back.getYMin(), room.getYMin(), 1e-6);
  auto cls = [](float p_free) { return p_free < 0.35f ? 0 : p_free > 0.804f ? 2 : 1; };
  for (unsigned y = 0; y < room.getSizeY(); ++y) {
    for (unsigned x = 0; x < room.getSizeX(); ++x) {
      ASSERT_EQ(cls(back.getCell(x, y)), cls(room.getCell(x, y))) << x << "," << y;
    }
  }
  // The PGM's first row is the top (largest y) of the map.
  const std::string pgm = testing::ReadFile(dir + "/room.pgm");
  EXPECT_EQ(pgm.substr(0, 2), "P5");
}

TEST(MapIoTest, RosMapErrorsNameTheFileAndField) {
  const std::string dir = testing::TempDir();
  testing::WriteFile(dir + "/m.yaml", "image: m.pgm\norigin: [0, 0, 0]\n");
  try {
    ReadRosMap(dir + "/m.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir + "/m.yaml: missing field 'resolution'");
  }
  testing::WriteFile(dir + "/m.yaml", "image: none.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n");
  EXPECT_THROW(ReadRosMap(dir + "/m.yaml"), InputError);
}

TEST(MapIoTest, MrptGridmapRoundTrip) {
  const std::string dir = testing::TempDir();
  const COccupancyGridMap2D room = Room();
  WriteMrptGridmap(room, dir + "/room.gridmap");
  const COccupancyGridMap2D back = ReadMrptGridmap(dir + "/room.gridmap");
  ASSERT_EQ(back.getSizeX(), room.getSizeX());
  for (unsigned y = 0; y < room.getSizeY(); ++y) {
    for (unsigned x = 0; x < room.getSizeX(); ++x) ASSERT_NEAR(back.getCell(x, y), room.getCell(x, y), 0.01);
  }
  testing::WriteFile(dir + "/bad.gridmap", "not a map");
  EXPECT_THROW(ReadMrptGridmap(dir + "/bad.gridmap"), InputError);
}

TEST(MapIoTest, PngShowsTheMapWithPaths) {
  const std::string dir = testing::TempDir();
  Trajectory t = {{Stamp{0}, mrpt::poses::CPose3D(1, 1, 0, 0, 0, 0)},
                  {Stamp{1}, mrpt::poses::CPose3D(3, 2, 0, 0, 0, 0)}};
  WriteMapPng(Room(), {{&t, {255, 0, 0}, "path"}}, dir + "/room.png", 400);
  EXPECT_GT(fs::file_size(dir + "/room.png"), 1000u);
}

TEST(TrajectoryIoTest, TumRoundTripKeepsNanosecondStampsAndPoses) {
  const std::string dir = testing::TempDir();
  Trajectory t = {{Stamp{1137834225973759900}, mrpt::poses::CPose3D(1.5, -2.25, 0, 0.3, 0, 0)},
                  {Stamp{1137834226000000001}, mrpt::poses::CPose3D(2, 0, 0.1, -3.0, 0.1, 0.2)}};
  WriteTum(t, dir + "/t.tum");
  const Trajectory back = ReadTum(dir + "/t.tum");
  ASSERT_EQ(back.size(), 2u);
  EXPECT_THAT(testing::ReadFile(dir + "/t.tum"), ::testing::HasSubstr("1137834225.973759900 1.500000 -2.250000"));
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_NEAR(back[i].stamp.Seconds(), t[i].stamp.Seconds(), 1e-6);
    EXPECT_NEAR(back[i].pose.distanceTo(t[i].pose), 0, 1e-6);
    EXPECT_NEAR(back[i].pose.yaw(), t[i].pose.yaw(), 1e-6);
    EXPECT_NEAR(back[i].pose.roll(), t[i].pose.roll(), 1e-6);
  }
}

TEST(TrajectoryIoTest, MalformedLinesNameFileAndLine) {
  const std::string dir = testing::TempDir();
  testing::WriteFile(dir + "/t.tum", "# header\n1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n");
  try {
    ReadTum(dir + "/t.tum");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir + "/t.tum:3: expected 8 numbers (t x y z qx qy qz qw), got 7");
  }
  testing::WriteFile(dir + "/gt.txt", "1 0 0 0\n2 nan 0 0\n");
  try {
    ReadPose2DText(dir + "/gt.txt");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_THAT(std::string(e.what()), ::testing::HasSubstr("gt.txt:2: 'nan' is not a finite number"));
  }
  // Found by fuzz_trajectory: a quaternion of no length escaped as MRPT's exception.
  testing::WriteFile(dir + "/q.tum", "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 0\n3 0 0 0 0 0 0 2\n");
  try {
    ReadTum(dir + "/q.tum");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir + "/q.tum:2: the quaternion (qx qy qz qw) has no length");
  }
  testing::WriteFile(dir + "/q2.tum", "1 0 0 0 0 0 0 1\n3 0 0 0 0 0 0 2\n");  // not unit length: normalised
  EXPECT_EQ(ReadTum(dir + "/q2.tum").size(), 2u);
}

TEST(TrajectoryIoTest, RelationsFilesAreReadWithTheirLinesAndFoundBesideTheLog) {
  const std::string dir = testing::TempDir();
  testing::WriteFile(dir + "/log.relations", "976052905.167303 976052911.885496 -0.05699 -0.12843 0 0 0 -1.68221\n");
  const RelationsFile file = ReadRelations(dir + "/log.relations");
  ASSERT_EQ(file.relations.size(), 1u);
  EXPECT_EQ(file.relations[0].line, 1);
  EXPECT_EQ(file.relations[0].t1.ns, Stamp::FromSeconds(976052905.167303).ns);
  EXPECT_NEAR(file.relations[0].delta.phi(), -1.68221, 1e-12);
  testing::WriteFile(dir + "/log.clf.bz2", "");
  EXPECT_EQ(DefaultRelationsPath(dir + "/log.clf.bz2"), dir + "/log.relations");
  EXPECT_EQ(DefaultRelationsPath(dir + "/other.clf"), "");
  testing::WriteFile(dir + "/bad.relations", "1 2 0 0 0 0 0 0\n1 2 0 0 0 0 0\n");
  try {
    ReadRelations(dir + "/bad.relations");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), dir + "/bad.relations:2: expected 8 numbers (t1 t2 x y z roll pitch yaw), got 7");
  }
  testing::WriteFile(dir + "/empty.relations", "# nothing\n");
  EXPECT_THROW(ReadRelations(dir + "/empty.relations"), InputError);
}

TEST(AtomicFileTest, AFailedWriteLeavesTheOldFileAndNoTemporary) {
  const std::string dir = testing::TempDir();
  WriteTextAtomically(dir + "/a.txt", "old");
  EXPECT_THROW(WriteAtomically(dir + "/a.txt",
                               [](const std::string& tmp) {
                                 testing::WriteFile(tmp, "half");
                                 throw RuntimeError("disk full");
                               }),
               RuntimeError);
  EXPECT_EQ(testing::ReadFile(dir + "/a.txt"), "old");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);
}

TEST(ReportTest, WritesJsonAndMarkdownWithStatus) {
  const std::string dir = testing::TempDir();
  RunReport report("replay");
  report.json()["counts"]["scans"] = 10;
  report.SetIncomplete("x.rawlog: record 7 (byte 100): truncated");
  report.AddOutput("map.png");
  report.Write(dir);
  const auto j = nlohmann::json::parse(testing::ReadFile(dir + "/report.json"));
  EXPECT_EQ(j["status"], "incomplete");
  EXPECT_EQ(j["counts"]["scans"], 10);
  const std::string md = testing::ReadFile(dir + "/report.md");
  EXPECT_THAT(md, ::testing::HasSubstr("Status: **incomplete** — x.rawlog: record 7"));
  EXPECT_THAT(md, ::testing::HasSubstr("![map.png](map.png)"));
}

cv::Mat Frame(int i) {
  cv::Mat m(120, 161, CV_8UC3, cv::Scalar(0, 0, 0));  // an odd width: encoders want even sizes
  cv::rectangle(m, cv::Rect(5 * i, 20, 30, 30), cv::Scalar(0, 0, 255), cv::FILLED);
  return m;
}

// The MP4 reads back with OpenCV's own decoder: every frame, at the first frame's
// (even) size, the moving square where it was drawn; only the final name is left.
TEST(VideoSinkTest, Mp4HoldsEveryFrameAndIsRenamedWhenClosed) {
  const std::string dir = testing::TempDir("video");
  io::VideoSink video(dir + "/run.mp4", 10);
  EXPECT_EQ(video.Close(), "");  // nothing yet: nothing written
  io::VideoSink sink(dir + "/run.mp4", 10);
  for (int i = 0; i < 12; ++i) sink.Write(Frame(i));
  EXPECT_FALSE(std::filesystem::exists(dir + "/run.mp4"));
  ASSERT_EQ(sink.Close(), "run.mp4");
  EXPECT_EQ(sink.Close(), "run.mp4");
  EXPECT_FALSE(std::filesystem::exists(dir + "/run.tmp.mp4"));
  cv::VideoCapture capture(dir + "/run.mp4");
  ASSERT_TRUE(capture.isOpened());
  int frames = 0;
  for (cv::Mat f; capture.read(f); ++frames) {
    ASSERT_EQ(f.size(), cv::Size(160, 120));
    const cv::Vec3b inside = f.at<cv::Vec3b>(35, 5 * frames + 15), outside = f.at<cv::Vec3b>(100, 80);
    EXPECT_GT(inside[2], 180) << "frame " << frames;
    EXPECT_LT(outside[2], 60) << "frame " << frames;
  }
  EXPECT_EQ(frames, 12);
  EXPECT_THROW(sink.Write(Frame(0)), RuntimeError);
}

TEST(VideoSinkTest, PngFramesAreNumberedBesideTheVideosName) {
  const std::string dir = testing::TempDir("video_png");
  io::VideoSink sink(dir + "/birds_eye.mp4", 10, io::VideoSink::Format::kPng);
  for (int i = 0; i < 3; ++i) sink.Write(Frame(i));
  EXPECT_EQ(sink.Close(), "birds_eye_frames/");
  for (const char* f : {"000000.png", "000001.png", "000002.png"})
    EXPECT_EQ(cv::imread(dir + "/birds_eye_frames/" + f).size(), cv::Size(160, 120)) << f;
  EXPECT_FALSE(std::filesystem::exists(dir + "/birds_eye_frames/000003.png"));
}

}  // namespace
}  // namespace specht::io
