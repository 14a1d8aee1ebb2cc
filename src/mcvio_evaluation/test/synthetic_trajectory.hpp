#pragma once
#include <string>

#include "mcvio/evaluation/trajectory.hpp"

namespace mcvio::evaluation::test {

/// A smooth 3D path (Lissajous in x-y, a slow wave in z) with a turning, tilting body, sampled
/// at `rate_hz` for `duration_s` from t0: enough excitation to make every alignment unique.
Trajectory lissajous(double duration_s, double rate_hz, Timestamp t0 = 1'000'000'000);

/// Straight line along x at `speed` [m/s], identity orientation.
Trajectory straightLine(double duration_s, double rate_hz, double speed, Timestamp t0 = 1'000'000'000);

/// A fresh empty directory under the test temp dir.
std::string freshDir(const std::string& name);

/// Writes `text` to `path`.
void writeText(const std::string& path, const std::string& text);

}  // namespace mcvio::evaluation::test
