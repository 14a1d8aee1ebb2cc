#pragma once
#include <cstdint>

namespace mcvio {

/// Time inside mcvio: int64 nanoseconds, as EuRoC stores it. Seconds only at the edges.
using Timestamp = std::int64_t;

constexpr double toSeconds(Timestamp t) { return static_cast<double>(t) * 1e-9; }
constexpr Timestamp fromSeconds(double s) { return static_cast<Timestamp>(s * 1e9 + (s >= 0 ? 0.5 : -0.5)); }

}  // namespace mcvio
