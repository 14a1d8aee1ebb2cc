#pragma once
#include <Eigen/Core>
#include <deque>

#include "mcvio/core/imu_sample.hpp"
#include "mcvio/core/time.hpp"

namespace mcvio::frontend {

/// Buffers gyro readings and integrates the body rotation between two instants
/// (linear interpolation of the rate between samples, midpoint rule per segment).
class GyroIntegrator {
 public:
  /// @param max_gap_ns larger holes between samples (or at the interval ends) make
  ///        rotation() fail rather than guess.
  explicit GyroIntegrator(Timestamp max_gap_ns = 30'000'000) : max_gap_ns_(max_gap_ns) {}

  /// Appends a sample; returns false (and ignores it) if it is not newer than the last one or
  /// holds non-finite values.
  bool add(const ImuSample& sample);

  /// R_{B(t0) B(t1)}: maps vectors in the body frame at t1 into the body frame at t0.
  /// `gyro_bias` is subtracted from every reading. False when the buffer does not cover [t0, t1].
  bool rotation(Timestamp t0, Timestamp t1, const Eigen::Vector3d& gyro_bias,
                Eigen::Matrix3d* R_b0_b1) const;

  /// Forgets samples not needed for intervals starting at or after t.
  void dropBefore(Timestamp t);

  std::size_t size() const { return samples_.size(); }
  void setMaxGap(Timestamp max_gap_ns) { max_gap_ns_ = max_gap_ns; }

 private:
  Eigen::Vector3d rateAt(Timestamp t) const;

  Timestamp max_gap_ns_;
  std::deque<ImuSample> samples_;
};

}  // namespace mcvio::frontend
