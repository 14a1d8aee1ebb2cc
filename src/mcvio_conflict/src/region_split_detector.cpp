#include "mcvio/conflict/region_split_detector.hpp"

#include <algorithm>

namespace mcvio::conflict {

RegionSplitDetector::Result RegionSplitDetector::test(const std::vector<TrackedPoint>& points,
                                                      const RelativeMotion& imu) const {
  Result res;
  if (points.size() < 16) return res;
  std::vector<TrackedPoint> low, high;
  std::vector<double> coordinate(points.size());
  for (int axis = 0; axis < 2; ++axis) {
    for (std::size_t i = 0; i < points.size(); ++i) coordinate[i] = points[i].n0_k[axis];
    std::vector<double> sorted = coordinate;
    std::sort(sorted.begin(), sorted.end());
    // Quartiles and median: an object covering a quarter to three quarters of the view on one
    // side finds a cut with mostly static points on the other.
    for (const double q : {0.25, 0.5, 0.75}) {
      const double cut = sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size()))];
      low.clear();
      high.clear();
      for (std::size_t i = 0; i < points.size(); ++i) (coordinate[i] < cut ? low : high).push_back(points[i]);
      const auto a = solver_.solve(low, imu), b = solver_.solve(high, imu);
      if (!a.valid || !b.valid) continue;
      const double chi2 = compare_.test(b.motion, a.motion).chi2;
      if (res.axis >= 0 && chi2 <= res.chi2) continue;
      const double a_imu = compare_.test(imu, a.motion).chi2, b_imu = compare_.test(imu, b.motion).chi2;
      const bool a_static = a_imu <= b_imu;
      res.chi2 = chi2;
      res.axis = axis;
      res.cut = cut;
      res.static_motion = a_static ? a.motion : b.motion;
      res.moving_motion = a_static ? b.motion : a.motion;
      res.static_chi2_imu = a_static ? a_imu : b_imu;
      res.moving_chi2_imu = a_static ? b_imu : a_imu;
      res.static_points = static_cast<int>(a_static ? low.size() : high.size());
      res.moving_points = static_cast<int>(a_static ? high.size() : low.size());
    }
  }
  res.fired = res.axis >= 0 && res.chi2 > compare_.threshold();
  return res;
}

}  // namespace mcvio::conflict
