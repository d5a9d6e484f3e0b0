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

mrpt::Clock::time_point ToMrpt(Stamp s) {
  return mrpt::Clock::time_point(mrpt::Clock::duration(s.ns / 100 + kMrptTicksToUnixEpoch));
}

}  // namespace specht
