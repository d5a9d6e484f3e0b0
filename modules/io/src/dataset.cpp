#include "specht/io/dataset.h"

#include <filesystem>

#include "specht/io/carmen.h"
#include "specht/io/ros_bag.h"

namespace specht::io {

namespace {

std::string Located(const std::string& file, int64_t record, int64_t byte_offset) {
  if (byte_offset < 0) return file + ":" + std::to_string(record) + ": ";
  return file + ": record " + std::to_string(record) + " (byte " + std::to_string(byte_offset) + "): ";
}

}  // namespace

DatasetError::DatasetError(const std::string& file, int64_t record, int64_t byte_offset, const std::string& why)
    : InputError(Located(file, record, byte_offset) + why), record_(record), byte_offset_(byte_offset) {}

std::unique_ptr<DatasetSource> OpenDataset(const std::string& path, OnBadRecord on_bad) {
  std::error_code ec;
  if (IsRos2Bag(path)) return OpenRos2Bag(path, {}, on_bad);
  if (IsMcap(path)) return OpenMcap(path, {}, on_bad);
  if (IsRos1Bag(path)) return OpenRos1Bag(path, {}, on_bad);
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path + ": no such dataset file");
  }
  if (LooksLikeCarmen(path)) return OpenCarmen(path, on_bad);
  return OpenRawlog(path);
}

}  // namespace specht::io
