// specht/io/line_reader.h: text lines from a gzip or plain file (zlib reads both),
// with the line number and the fraction of the file read (for progress lines).
#pragma once

#include <cstdint>
#include <string>

namespace specht::io {

class LineReader {
 public:
  // InputError naming the file when it cannot be opened.
  explicit LineReader(const std::string& path);
  ~LineReader();
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;

  // The next line without its end-of-line characters; false at the end. A broken
  // gzip stream throws DatasetError naming the file and the line.
  bool Next(std::string& line);
  int64_t number() const { return number_; }
  // Compressed bytes consumed over the file size (-1 when the size is unknown).
  double Fraction(uint64_t file_size) const;

 private:
  std::string path_;
  void* file_;  // gzFile
  int64_t number_ = 0;
};

}  // namespace specht::io
