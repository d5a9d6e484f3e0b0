#include "specht/io/dataset.h"

#include <filesystem>

namespace specht::io {

DatasetError::DatasetError(const std::string& file, int64_t record, int64_t byte_offset, const std::string& why)
    : InputError(file + ": record " + std::to_string(record) + " (byte " + std::to_string(byte_offset) +
                 "): " + why),
      record_(record),
      byte_offset_(byte_offset) {}

std::unique_ptr<DatasetSource> OpenDataset(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path + ": no such dataset file");
  }
  // Rawlogs are the only format so far; the CARMEN and KITTI readers slot in here.
  return OpenRawlog(path);
}

}  // namespace specht::io
