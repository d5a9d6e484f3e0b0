// specht/io/rawlog_writer.h: writes MRPT rawlogs (gzip-compressed) that `specht
// replay`, RawLogViewer, rawlog-edit and MRPT's SLAM apps read, in either layout:
//   observations:   one CObservation after another (Write)
//   actions/frames: pairs of CActionCollection (the odometry increment as a
//                   CActionRobotMovement2D) and CSensoryFrame (WriteFrame)
// The file appears under its name only when Close() succeeds.
#pragma once

#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose2D.h>

#include <memory>
#include <string>

namespace specht::io {

class RawlogWriter {
 public:
  explicit RawlogWriter(std::string path);
  ~RawlogWriter();  // without Close(), the temporary file is removed
  RawlogWriter(const RawlogWriter&) = delete;
  RawlogWriter& operator=(const RawlogWriter&) = delete;

  void Write(const mrpt::obs::CObservation& observation);
  // One action/sensory-frame pair: the odometry increment since the last frame, then
  // the frame holding `observation`.
  void WriteFrame(const mrpt::poses::CPose2D& odometry_increment, const mrpt::obs::CObservation::Ptr& observation);
  void Close();
  size_t count() const { return count_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string path_;
  std::string tmp_path_;
  size_t count_ = 0;
};

}  // namespace specht::io
