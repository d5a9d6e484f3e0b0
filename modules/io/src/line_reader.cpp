#include "specht/io/line_reader.h"

#include <bzlib.h>
#include <zlib.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "specht/core/error.h"
#include "specht/io/dataset.h"

namespace specht::io {

static gzFile Gz(void* f) { return static_cast<gzFile>(f); }

// A bzip2 file (the Freiburg benchmark's .clf.bz2) decoded with libbz2, in blocks.
// A file may hold several streams one after another (pbzip2 writes them): at each
// stream's end the next one starts from the bytes the decoder read past it.
class LineReader::Bz2 {
 public:
  explicit Bz2(const std::string& path) : file_(std::fopen(path.c_str(), "rb")) {
    if (file_ == nullptr) throw InputError(path + ": cannot open");
    Open(nullptr, 0);
  }
  ~Bz2() {
    int error = BZ_OK;
    if (bz_ != nullptr) BZ2_bzReadClose(&error, bz_);
    std::fclose(file_);
  }
  Bz2(const Bz2&) = delete;
  Bz2& operator=(const Bz2&) = delete;

  // Up to `n` decoded bytes into `out`; 0 at the end. "" in `error` unless broken.
  size_t Read(char* out, size_t n, std::string& error) {
    while (bz_ != nullptr) {
      int status = BZ_OK;
      const int got = BZ2_bzRead(&status, bz_, out, static_cast<int>(n));
      if (status == BZ_OK) return static_cast<size_t>(got);
      if (status != BZ_STREAM_END) {
        error = "bzip2 error " + std::to_string(status);
        return 0;
      }
      NextStream();
      if (got > 0) return static_cast<size_t>(got);
    }
    return 0;
  }
  long Offset() const { return std::ftell(file_); }

 private:
  void Open(void* unused, int n) {
    int error = BZ_OK;
    bz_ = BZ2_bzReadOpen(&error, file_, 0, 0, unused, n);
    if (error != BZ_OK) bz_ = nullptr;
  }
  void NextStream() {
    int error = BZ_OK;
    void* unused = nullptr;
    int n = 0;
    BZ2_bzReadGetUnused(&error, bz_, &unused, &n);
    char rest[BZ_MAX_UNUSED];
    std::memcpy(rest, unused, static_cast<size_t>(n));
    BZ2_bzReadClose(&error, bz_);
    bz_ = nullptr;
    const int next = std::fgetc(file_);
    if (n == 0 && next == EOF) return;
    if (next != EOF) std::ungetc(next, file_);
    Open(rest, n);
  }

  FILE* file_;
  BZFILE* bz_ = nullptr;
};

namespace {

bool IsBzip2(const std::string& path) {
  char magic[3] = {};
  FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return false;
  const size_t n = std::fread(magic, 1, 3, f);
  std::fclose(f);
  return n == 3 && magic[0] == 'B' && magic[1] == 'Z' && magic[2] == 'h';
}

}  // namespace

LineReader::LineReader(const std::string& path) : path_(path), file_(nullptr) {
  if (IsBzip2(path)) {
    bz2_ = std::make_unique<Bz2>(path);
    return;
  }
  file_ = gzopen(path.c_str(), "rb");
  if (file_ == nullptr) throw InputError(path + ": cannot open");
  // A large buffer speeds up reading a long log; a short file (a relations file, a
  // fuzzer's input) needs none, and zlib allocates three times the size on every open.
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  gzbuffer(Gz(file_), static_cast<unsigned>(std::clamp<uintmax_t>(ec ? 0 : size, 1 << 13, 1 << 17)));
}

LineReader::~LineReader() {
  if (file_ != nullptr) gzclose(Gz(file_));
}

bool LineReader::ReadRaw(std::string& line) {
  if (!bz2_) {
    char buf[8192];
    while (gzgets(Gz(file_), buf, sizeof(buf)) != nullptr) {
      line += buf;
      if (!line.empty() && line.back() == '\n') break;
    }
    int error = Z_OK;
    const char* message = gzerror(Gz(file_), &error);
    if (error != Z_OK)
      throw DatasetError(
          path_, number_ + 1, -1,
          std::string("compressed data ends or breaks here (") + message + "): truncated or corrupt gzip file");
    return !line.empty();
  }
  for (;;) {
    const size_t eol = buffer_.find('\n', buffer_pos_);
    if (eol != std::string::npos) {
      line.append(buffer_, buffer_pos_, eol + 1 - buffer_pos_);
      buffer_pos_ = eol + 1;
      return true;
    }
    line.append(buffer_, buffer_pos_, std::string::npos);
    buffer_.resize(1 << 17);
    buffer_pos_ = 0;
    std::string error;
    buffer_.resize(bz2_->Read(buffer_.data(), buffer_.size(), error));
    if (!error.empty())
      throw DatasetError(path_, number_ + 1, -1,
                         "compressed data ends or breaks here (" + error + "): truncated or corrupt bzip2 file");
    if (buffer_.empty()) return !line.empty();
  }
}

bool LineReader::Next(std::string& line) {
  line.clear();
  if (!ReadRaw(line)) return false;
  ++number_;
  while (!line.empty() && (line.back() == '\n' || line.back() == '\r')) line.pop_back();
  return true;
}

double LineReader::Fraction(uint64_t file_size) const {
  if (file_size == 0) return -1.0;
  const double read = bz2_ ? static_cast<double>(bz2_->Offset()) : static_cast<double>(gzoffset(Gz(file_)));
  return std::min(1.0, read / static_cast<double>(file_size));
}

}  // namespace specht::io
