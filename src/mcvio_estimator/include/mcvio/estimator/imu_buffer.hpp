#pragma once
#include <deque>
#include <string>
#include <vector>

#include "mcvio/core/imu_sample.hpp"

namespace mcvio::estimator {

/// Time-ordered IMU samples awaiting integration. Rejects samples that would corrupt the
/// integration (non-finite values, time not increasing) and reports gaps.
class ImuBuffer {
 public:
  enum class AddResult { kAccepted, kRejectedNonFinite, kRejectedNotIncreasing };

  /// Adds a sample; `message` (if given) explains a rejection or a gap.
  AddResult add(const ImuSample& sample, double max_gap_s, std::string* message = nullptr);

  bool empty() const { return samples_.empty(); }
  Timestamp firstTime() const { return samples_.front().t; }
  Timestamp lastTime() const { return samples_.back().t; }
  std::size_t size() const { return samples_.size(); }

  /// Samples covering [t0, t1] with end points interpolated linearly at exactly t0 and t1.
  /// False when the buffer does not cover the interval. `max_gap_s` receives the largest spacing
  /// between consecutive samples inside the interval.
  bool extract(Timestamp t0, Timestamp t1, std::vector<ImuSample>* out, double* max_gap_s = nullptr) const;

  /// Samples with t in [t0, t1] (no interpolation), e.g. to test for stillness.
  std::vector<ImuSample> between(Timestamp t0, Timestamp t1) const;

  /// Drops samples older than t, keeping the last one before it for interpolation.
  void dropBefore(Timestamp t);
  void clear() { samples_.clear(); }

 private:
  std::deque<ImuSample> samples_;
};

}  // namespace mcvio::estimator
