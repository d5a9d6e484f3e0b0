// specht/io/dataset.h: dataset sources. A source yields MRPT observations in file
// order, each with its stamp and the index of the record it came from, so that an
// error can name where it happened. Sources never consult the wall clock.
//
// Formats:
//   MRPT rawlogs (observation-only and action/sensory-frame; plain or gzip).
//     Action/sensory-frame rawlogs carry odometry as increments
//     (CActionRobotMovement2D); the source chains them into CObservationOdometry
//     readings so that every consumer sees one kind of odometry.
//   CARMEN logs (FLASER, ROBOTLASER1, ODOM, PARAM; plain or gzip): see carmen.h.
#pragma once

#include <mrpt/obs/CObservation.h>

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "specht/core/error.h"
#include "specht/core/time.h"

namespace specht::io {

struct Observation {
  Stamp stamp;
  mrpt::obs::CObservation::Ptr data;
  int64_t record = 0;  // index of the record in the file (0-based)
};

// Bad or truncated input met while reading a dataset. What was read before stays valid.
class DatasetError : public InputError {
 public:
  // byte_offset < 0: the record is a text line and `record` its 1-based number.
  DatasetError(const std::string& file, int64_t record, int64_t byte_offset, const std::string& why);
  int64_t record() const { return record_; }
  int64_t byte_offset() const { return byte_offset_; }

 private:
  int64_t record_;
  int64_t byte_offset_;
};

class DatasetSource {
 public:
  virtual ~DatasetSource() = default;
  // The next observation, or nullopt at the clean end of the data. Throws
  // DatasetError on corrupt or truncated input.
  virtual std::optional<Observation> Next() = 0;
  virtual std::string Path() const = 0;
  virtual std::string Format() const = 0;
  // Fraction of the data read so far, in [0, 1] (for progress); negative if unknown.
  virtual double FractionRead() const = 0;
  // Bad records skipped so far, with the reason for each (OnBadRecord::kSkip).
  virtual const std::vector<std::string>& SkippedRecords() const { return no_skips_; }
  // What the reader decided about the data, for the report (e.g. how stamps that go
  // backwards were handled); empty when there is nothing to say.
  virtual std::vector<std::string> Notes() const { return {}; }
  // Figures about the reading itself, for the report (a live source: how long its
  // messages waited before they were used); empty for a file.
  virtual std::map<std::string, double> Figures() const { return {}; }

 private:
  std::vector<std::string> no_skips_;
};

// What a source does with a bad record: stop (throw DatasetError) or skip it (count
// it in SkippedRecords and go on). Sources that cannot resynchronise (rawlogs) stop.
enum class OnBadRecord { kStop, kSkip };

// Opens a dataset by looking at its contents (gzip or not): a CARMEN log when its
// first non-comment line starts with a CARMEN message name, else an MRPT rawlog.
// Throws InputError if the file is missing.
std::unique_ptr<DatasetSource> OpenDataset(const std::string& path, OnBadRecord on_bad = OnBadRecord::kStop);

// The MRPT rawlog reader (both formats, plain or gzip).
std::unique_ptr<DatasetSource> OpenRawlog(const std::string& path);

}  // namespace specht::io
