#include "specht/io/rawlog_writer.h"

#include <unistd.h>

#include <filesystem>

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>

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

void RawlogWriter::Close() {
  impl_->out.close();
  impl_.reset();
  std::error_code ec;
  std::filesystem::rename(tmp_path_, path_, ec);
  if (ec) throw RuntimeError(path_ + ": cannot write rawlog: " + ec.message());
}

}  // namespace specht::io
