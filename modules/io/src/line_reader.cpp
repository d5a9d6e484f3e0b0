#include "specht/io/line_reader.h"

#include <zlib.h>

#include <algorithm>

#include "specht/core/error.h"
#include "specht/io/dataset.h"

namespace specht::io {

static gzFile Gz(void* f) { return static_cast<gzFile>(f); }

LineReader::LineReader(const std::string& path) : path_(path), file_(gzopen(path.c_str(), "rb")) {
  if (file_ == nullptr) throw InputError(path + ": cannot open");
  gzbuffer(Gz(file_), 1 << 17);
}

LineReader::~LineReader() {
  if (file_ != nullptr) gzclose(Gz(file_));
}

bool LineReader::Next(std::string& line) {
  line.clear();
  char buf[8192];
  while (gzgets(Gz(file_), buf, sizeof(buf)) != nullptr) {
    line += buf;
    if (!line.empty() && line.back() == '\n') break;
  }
  int error = Z_OK;
  const char* message = gzerror(Gz(file_), &error);
  if (error != Z_OK) {
    throw DatasetError(path_, number_ + 1, -1,
                       std::string("compressed data ends or breaks here (") + message + "): truncated or corrupt gzip file");
  }
  if (line.empty()) return false;
  ++number_;
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
  return true;
}

double LineReader::Fraction(uint64_t file_size) const {
  return file_size > 0 ? std::min(1.0, static_cast<double>(gzoffset(Gz(file_))) / file_size) : -1.0;
}

}  // namespace specht::io
