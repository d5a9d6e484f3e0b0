#include "specht/core/error.h"

#include "specht/core/interrupt.h"

namespace specht {

std::string Where(const std::string& file, int line) {
  if (line > 0) return file + ":" + std::to_string(line) + ": ";
  return file + ": ";
}

int ExitCodeFor(const std::exception& e) {
  if (dynamic_cast<const Interrupted*>(&e) != nullptr) return InterruptExitCode();
  return dynamic_cast<const InputError*>(&e) != nullptr ? 2 : 1;
}

}  // namespace specht
