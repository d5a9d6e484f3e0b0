#include "specht/io/rawlog_writer.h"

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <unistd.h>

#include <filesystem>

#include "specht/core/error.h"

namespace specht::io {

struct RawlogWriter::Impl {
  mrpt::io::CFileGZOutputStream out;
};

RawlogWriter::RawlogWriter(std::string path) : impl_(std::make_unique<Impl>()), path_(std::move(path)) {
  const std::filesystem::path p(path_);
  tmp_path_ = (p.parent_path() / ("." + p.filename().string() + ".tmp" + std::to_string(getpid()))).string();
  if (!impl_->out.open(tmp_path_)) throw RuntimeError(path_ + ": cannot write rawlog");
}

RawlogWriter::~RawlogWriter() {
  if (impl_) {
    impl_->out.close();
    std::error_code ec;
    std::filesystem::remove(tmp_path_, ec);
  }
}

void RawlogWriter::Write(const mrpt::obs::CObservation& observation) {
  auto archive = mrpt::serialization::archiveFrom(impl_->out);
  archive << observation;
  ++count_;
}

void RawlogWriter::WriteFrame(const mrpt::poses::CPose2D& odometry_increment,
                              const mrpt::obs::CObservation::Ptr& observation) {
  mrpt::obs::CActionRobotMovement2D move;
  mrpt::obs::CActionRobotMovement2D::TMotionModelOptions model;  // MRPT's default Gaussian model
  move.computeFromOdometry(odometry_increment, model);
  move.timestamp = observation->timestamp;
  mrpt::obs::CActionCollection actions;
  actions.insert(move);
  mrpt::obs::CSensoryFrame frame;
  frame.insert(observation);
  auto archive = mrpt::serialization::archiveFrom(impl_->out);
  archive << actions << frame;
  ++count_;
}

void RawlogWriter::Close() {
  impl_->out.close();
  impl_.reset();
  std::error_code ec;
  std::filesystem::rename(tmp_path_, path_, ec);
  if (ec) throw RuntimeError(path_ + ": cannot write rawlog: " + ec.message());
}

}  // namespace specht::io
