// specht/core/interrupt.h: stopping long work cleanly on SIGINT and SIGTERM.
//
// `specht` installs the handlers once at start. The first signal only sets a flag;
// every long loop (a dataset replay, a closed-loop drive, a tuning search, a
// training epoch) polls it at its next record or step boundary, stops there and
// writes everything computed so far, as a truncated input does, with the report's
// status "interrupted"; the process then exits with 128 + the signal (130 for
// SIGINT, 143 for SIGTERM). A second signal restores the default action and raises
// it again: the process ends at once, for a user who does not want to wait.
#pragma once

#include <string>

#include "specht/core/error.h"

namespace specht {

// Thrown by work that has no usable result part-way (a cross-validation fold): the
// caller writes what did finish; ExitCodeFor maps it to InterruptExitCode().
class Interrupted : public Error {
 public:
  using Error::Error;
};

// Installs the SIGINT and SIGTERM handlers (idempotent).
void InstallInterruptHandlers();

// True once a signal asked to stop. Cheap (one atomic load): poll it per record.
bool InterruptRequested();

// The signal that asked to stop (SIGINT, SIGTERM), or 0.
int InterruptSignal();

// "SIGINT", "SIGTERM" (or "signal N"); "" when none.
std::string InterruptName();

// The exit code of an interrupted command: 128 + the signal (0 when none).
int InterruptExitCode();

// Throws Interrupted("<what>: interrupted by SIGINT") when a signal asked to stop.
void ThrowIfInterrupted(const std::string& what);

// Sets the flag as a signal would (tests, and a parent stopping in-process work).
void RequestInterrupt(int signal);

// Clears the flag (tests only).
void ClearInterruptForTesting();

}  // namespace specht
