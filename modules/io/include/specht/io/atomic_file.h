// specht/io/atomic_file.h: every output is written to a temporary file beside its
// destination and renamed over it when complete, so a crash or an error never
// leaves a half-written map, trajectory or report behind.
#pragma once

#include <functional>
#include <string>

namespace specht::io {

// Calls write(tmp_path) to fill a temporary file (same directory, same extension,
// so libraries that pick the format from the name still work), then renames it
// onto `path`. Throws RuntimeError naming `path` if writing or renaming fails.
void WriteAtomically(const std::string& path, const std::function<void(const std::string& tmp_path)>& write);

void WriteTextAtomically(const std::string& path, const std::string& text);

// Creates a directory (and parents) for outputs; throws InputError if it cannot.
void MakeOutputDir(const std::string& dir);

}  // namespace specht::io
