#include "specht/core/time.h"

#include <cmath>

namespace specht {
namespace {
// 100 ns ticks between 1601-01-01 (MRPT's epoch) and 1970-01-01 (UNIX epoch).
constexpr int64_t kMrptTicksToUnixEpoch = 116444736000000000LL;
}  // namespace

Stamp Stamp::FromSeconds(double s) { return Stamp{static_cast<int64_t>(std::llround(s * 1e9))}; }

Stamp FromMrpt(mrpt::Clock::time_point t) {
  return Stamp{(t.time_since_epoch().count() - kMrptTicksToUnixEpoch) * 100};
}

bool RepresentableAsStamp(mrpt::Clock::time_point t) {
  int64_t ticks = 0, ns = 0;
  return !__builtin_sub_overflow(t.time_since_epoch().count(), kMrptTicksToUnixEpoch, &ticks) &&
         !__builtin_mul_overflow(ticks, int64_t{100}, &ns);
}

mrpt::Clock::time_point ToMrpt(Stamp s) {
  return mrpt::Clock::time_point(mrpt::Clock::duration(s.ns / 100 + kMrptTicksToUnixEpoch));
}

// Days from 1970-01-01 to a civil date (Howard Hinnant's days_from_civil).
int64_t UnixSecondsFromUtc(int64_t y, int64_t m, int64_t d, int64_t hour, int64_t minute, int64_t second) {
  y -= m <= 2;
  const int64_t era = (y >= 0 ? y : y - 399) / 400;
  const int64_t yoe = y - era * 400;
  const int64_t doy = (153 * (m + (m > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const int64_t doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  const int64_t days = era * 146097 + doe - 719468;
  return days * 86400 + hour * 3600 + minute * 60 + second;
}

}  // namespace specht
