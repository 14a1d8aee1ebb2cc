#include "synthetic_trajectory.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

namespace mcvio::evaluation::test {

Trajectory lissajous(double duration_s, double rate_hz, Timestamp t0) {
  Trajectory t;
  const int n = static_cast<int>(std::lround(duration_s * rate_hz)) + 1;
  for (int i = 0; i < n; ++i) {
    const double s = i / rate_hz;
    StampedPose p;
    p.t = t0 + static_cast<Timestamp>(std::llround(s * 1e9));
    p.p = {2.0 * std::sin(0.5 * s), 1.5 * std::sin(0.8 * s + 0.3), 0.4 * std::cos(0.3 * s)};
    p.q = Eigen::AngleAxisd(0.3 * s, Eigen::Vector3d::UnitZ()) *
          Eigen::AngleAxisd(0.2 * std::sin(s), Eigen::Vector3d::UnitX()) *
          Eigen::AngleAxisd(0.1 * std::cos(0.7 * s), Eigen::Vector3d::UnitY());
    t.append(p);
  }
  return t;
}

Trajectory straightLine(double duration_s, double rate_hz, double speed, Timestamp t0) {
  Trajectory t;
  const int n = static_cast<int>(std::lround(duration_s * rate_hz)) + 1;
  for (int i = 0; i < n; ++i) {
    StampedPose p;
    const Timestamp dt = static_cast<Timestamp>(std::llround(i * 1e9 / rate_hz));
    p.t = t0 + dt;
    p.p = {speed * toSeconds(dt), 0, 0};
    t.append(p);
  }
  return t;
}

std::string freshDir(const std::string& name) {
  const auto dir = std::filesystem::path(::testing::TempDir()) / ("mcvio_evaluation_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

}  // namespace mcvio::evaluation::test
