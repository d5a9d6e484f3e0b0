// specht/io/line_reader.h: text lines from a gzip, bzip2 or plain file (zlib reads
// gzip and plain, libbz2 bzip2, told apart by the file's first bytes),
// with the line number and the fraction of the file read (for progress lines).
#pragma once

#include <cstdint>
#include <memory>
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
  // compressed stream throws DatasetError naming the file and the line.
  bool Next(std::string& line);
  int64_t number() const { return number_; }
  // Compressed bytes consumed over the file size (-1 when the size is unknown).
  double Fraction(uint64_t file_size) const;

 private:
  class Bz2;
  bool ReadRaw(std::string& line);  // appends the next line with its end of line; false at the end

  std::string path_;
  void* file_;  // gzFile, unless bzip2
  std::unique_ptr<Bz2> bz2_;
  std::string buffer_;  // bzip2: decoded bytes not yet returned, from buffer_pos_
  size_t buffer_pos_ = 0;
  int64_t number_ = 0;
};

}  // namespace specht::io
