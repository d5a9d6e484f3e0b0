#include "specht/io/data_dir.h"

#include <cstdlib>
#include <filesystem>

#include "specht/core/error.h"

namespace specht::io {

std::optional<std::string> ResolveDataDir(const std::string& cli_value) {
  std::string dir = cli_value;
  std::string from = "--data-dir";
  if (dir.empty()) {
    const char* env = std::getenv("SPECHT_DATA_DIR");
    if (env == nullptr || *env == '\0') return std::nullopt;
    dir = env;
    from = "SPECHT_DATA_DIR";
  }
  if (!std::filesystem::is_directory(dir)) throw InputError(from + ": '" + dir + "' is not a directory");
  return dir;
}

std::string DefaultRawlog() {
  return "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
}

}  // namespace specht::io
