// specht/core/time.h: time stamps. Everything in specht runs on observation time
// (the stamps recorded in the dataset), never on the wall clock, so replays are
// deterministic. A Stamp is an integer count of nanoseconds since the UNIX epoch.
#pragma once

#include <mrpt/core/Clock.h>

#include <cstdint>

namespace specht {

struct Stamp {
  int64_t ns = 0;

  static Stamp FromSeconds(double s);
  double Seconds() const { return static_cast<double>(ns) * 1e-9; }

  friend bool operator<(Stamp a, Stamp b) { return a.ns < b.ns; }
  friend bool operator<=(Stamp a, Stamp b) { return a.ns <= b.ns; }
  friend bool operator>(Stamp a, Stamp b) { return a.ns > b.ns; }
  friend bool operator>=(Stamp a, Stamp b) { return a.ns >= b.ns; }
  friend bool operator==(Stamp a, Stamp b) { return a.ns == b.ns; }
  friend bool operator!=(Stamp a, Stamp b) { return a.ns != b.ns; }
};

// Seconds from a to b.
inline double SecondsBetween(Stamp a, Stamp b) { return static_cast<double>(b.ns - a.ns) * 1e-9; }

// Seconds since the UNIX epoch of a UTC calendar time (proleptic Gregorian; no
// range check: the caller validates the fields).
int64_t UnixSecondsFromUtc(int64_t year, int64_t month, int64_t day, int64_t hour, int64_t minute, int64_t second);

// Exact conversions to and from MRPT's clock (100 ns ticks since 1601-01-01).
// FromMrpt needs a time Stamp can hold (years 1678–2262; RepresentableAsStamp):
// a corrupt file's stamp is checked first.
Stamp FromMrpt(mrpt::Clock::time_point t);
bool RepresentableAsStamp(mrpt::Clock::time_point t);
mrpt::Clock::time_point ToMrpt(Stamp s);

}  // namespace specht
