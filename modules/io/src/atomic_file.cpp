#include "specht/io/atomic_file.h"

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "specht/core/error.h"

namespace fs = std::filesystem;

namespace specht::io {

void WriteAtomically(const std::string& path, const std::function<void(const std::string&)>& write) {
  const fs::path target(path);
  const fs::path tmp = target.parent_path() /
                       ("." + target.stem().string() + ".tmp" + std::to_string(getpid()) + target.extension().string());
  try {
    write(tmp.string());
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  std::error_code ec;
  if (!fs::exists(tmp, ec)) throw RuntimeError(path + ": writer produced no file");
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw RuntimeError(path + ": cannot write: " + ec.message());
  }
}

void WriteTextAtomically(const std::string& path, const std::string& text) {
  WriteAtomically(path, [&](const std::string& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.close();
    if (!out) throw RuntimeError(path + ": cannot write");
  });
}

void MakeOutputDir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    throw InputError(dir + ": cannot create output directory" + (ec ? ": " + ec.message() : ""));
  }
}

}  // namespace specht::io
