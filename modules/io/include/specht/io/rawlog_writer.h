// specht/io/rawlog_writer.h: writes observations as an MRPT rawlog in the
// observation-only format (gzip-compressed), which `specht replay`, RawLogViewer and
// rawlog-edit read. The file appears under its name only when Close() succeeds.
#pragma once

#include <memory>
#include <string>

#include <mrpt/obs/CObservation.h>

namespace specht::io {

class RawlogWriter {
 public:
  explicit RawlogWriter(std::string path);
  ~RawlogWriter();  // without Close(), the temporary file is removed
  RawlogWriter(const RawlogWriter&) = delete;
  RawlogWriter& operator=(const RawlogWriter&) = delete;

  void Write(const mrpt::obs::CObservation& observation);
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
