// specht/core/error.h: the two kinds of failure every app maps to an exit code.
//
//   InputError   the user's input is wrong: a parameter, a file, a record, the
//                command line. Apps exit with code 2.
//   RuntimeError something failed while running on good input. Apps exit with 1.
//
// Messages carry their context at the edge where the input was read:
// "params/x.yaml:12: key 'grid.resolution': value -1 is outside [0.01, 2]".
#pragma once

#include <stdexcept>
#include <string>

namespace specht {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class InputError : public Error {
 public:
  using Error::Error;
};

class RuntimeError : public Error {
 public:
  using Error::Error;
};

// "file:line: " (line omitted when < 1), the prefix of every located message.
std::string Where(const std::string& file, int line = 0);

// Exit code for an exception caught at the top of an app: 2 for InputError, 128 +
// the signal for Interrupted (core/interrupt.h), 1 else.
int ExitCodeFor(const std::exception& e);

}  // namespace specht
