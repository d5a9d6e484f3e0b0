// tests/fuzz/fuzz_support.h: what every libFuzzer target here shares.
//
// A parser may reject its input only with specht's own errors (core/error.h:
// InputError, DatasetError, RuntimeError), whose message names the file and the
// reason; anything else — a crash, a sanitizer report, another exception escaping —
// is a finding. Parsers that read a path get the bytes through a file of this
// process's own (in $TMPDIR, /tmp by default).
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <string>

#include "specht/core/error.h"

namespace specht::fuzz {

// Writes the input to this process's scratch file named `name` and returns its path;
// the file goes when the process ends normally (one killed on a finding keeps it).
inline std::string InputFile(const uint8_t* data, size_t size, const std::string& name) {
  struct Scratch {
    std::string path;
    ~Scratch() { std::remove(path.c_str()); }
  };
  const char* tmp = std::getenv("TMPDIR");
  static std::map<std::string, Scratch> files;
  Scratch& file = files[name];
  if (file.path.empty())
    file.path = std::string(tmp != nullptr ? tmp : "/tmp") + "/specht-fuzz-" + std::to_string(getpid()) + "-" + name;
  std::ofstream(file.path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return file.path;
}

inline std::string Text(const uint8_t* data, size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// Runs `parse`; specht's errors are the expected way to reject input.
template <class F>
void Expect(F&& parse) {
  try {
    parse();
  } catch (const Error&) {
  }
}

}  // namespace specht::fuzz
