#pragma once
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mcvio/core/imu_noise.hpp"
#include "mcvio/core/imu_sample.hpp"
#include "mcvio/estimator/imu_bias.hpp"

namespace mcvio::estimator {

/// On-manifold IMU preintegration between two frames (Forster et al., T-RO 2017) with midpoint
/// integration.
///
/// Error-state and residual order everywhere: [dtheta (0..2), dv (3..5), dp (6..8), dbg (9..11),
/// dba (12..14)]. Rotation errors are right perturbations: R = R_hat Exp(dtheta).
/// The deltas are expressed in the body frame at the first sample:
///   dR = R_i^T R_j,  dv = R_i^T (v_j - v_i - g dt),  dp = R_i^T (p_j - p_i - v_i dt - g dt^2 / 2).
/// Bias Jacobians are the exact first-order derivatives of the discrete midpoint scheme, so they
/// agree with numerical differentiation of integrate().
class ImuPreintegrator {
 public:
  using Matrix15 = Eigen::Matrix<double, 15, 15>;
  using Vector15 = Eigen::Matrix<double, 15, 1>;

  /// @param bias_lin bias the samples are integrated with (the linearisation point).
  /// @param noise continuous-time densities (already inflated if the caller wants that);
  ///              discretised per step as sigma/sqrt(dt) (white) and sigma*sqrt(dt) (random walk).
  ImuPreintegrator(const ImuBias& bias_lin, const ImuNoiseParams& noise);

  /// Appends a sample. The first sample only sets the start; each further one integrates the
  /// interval from the previous sample with the midpoint rule. Samples whose time does not
  /// increase are ignored and counted (see rejectedSamples()).
  void integrate(const ImuSample& sample);

  /// Integrates all samples again from scratch with a new linearisation bias.
  void repropagate(const ImuBias& bias_lin);

  /// True when the bias moved so far from the linearisation point that first-order correction is
  /// no longer good enough.
  bool needsRepropagation(const ImuBias& bias, double gyro_threshold, double accel_threshold) const;

  double deltaTime() const { return sum_dt_; }
  Timestamp startTime() const { return samples_.empty() ? 0 : samples_.front().t; }
  Timestamp endTime() const { return samples_.empty() ? 0 : samples_.back().t; }
  std::size_t sampleCount() const { return samples_.size(); }
  std::size_t rejectedSamples() const { return rejected_; }
  const std::vector<ImuSample>& samples() const { return samples_; }
  const ImuBias& linearizationBias() const { return bias_lin_; }
  const ImuNoiseParams& noise() const { return noise_; }

  const Eigen::Quaterniond& deltaQ() const { return delta_q_; }
  const Eigen::Vector3d& deltaV() const { return delta_v_; }
  const Eigen::Vector3d& deltaP() const { return delta_p_; }

  /// d(dtheta)/d(bg), d(dv)/d(bg), d(dv)/d(ba), d(dp)/d(bg), d(dp)/d(ba).
  Eigen::Matrix3d dR_dbg() const { return jac_bias_.block<3, 3>(0, 0); }
  Eigen::Matrix3d dV_dbg() const { return jac_bias_.block<3, 3>(3, 0); }
  Eigen::Matrix3d dV_dba() const { return jac_bias_.block<3, 3>(3, 3); }
  Eigen::Matrix3d dP_dbg() const { return jac_bias_.block<3, 3>(6, 0); }
  Eigen::Matrix3d dP_dba() const { return jac_bias_.block<3, 3>(6, 3); }

  /// Covariance of [dtheta, dv, dp, bg_j - bg_i, ba_j - ba_i].
  const Matrix15& covariance() const { return covariance_; }
  /// Upper-triangular S with S^T S = covariance^-1 (whitens the residual).
  Matrix15 sqrtInformation() const;

  /// Deltas corrected to first order for a bias different from the linearisation point.
  Eigen::Quaterniond correctedDeltaQ(const ImuBias& bias) const;
  Eigen::Vector3d correctedDeltaV(const ImuBias& bias) const;
  Eigen::Vector3d correctedDeltaP(const ImuBias& bias) const;

  /// Unwhitened 15-dim residual between two states (used by tests and diagnostics; the Ceres
  /// factor evaluates the same expression).
  Vector15 residual(const Eigen::Vector3d& p_i, const Eigen::Quaterniond& q_i, const Eigen::Vector3d& v_i,
                    const ImuBias& b_i, const Eigen::Vector3d& p_j, const Eigen::Quaterniond& q_j,
                    const Eigen::Vector3d& v_j, const ImuBias& b_j, const Eigen::Vector3d& gravity) const;

  /// State j predicted from state i with the corrected deltas.
  void predict(const Eigen::Vector3d& p_i, const Eigen::Quaterniond& q_i, const Eigen::Vector3d& v_i,
               const ImuBias& b_i, const Eigen::Vector3d& gravity, Eigen::Vector3d* p_j,
               Eigen::Quaterniond* q_j, Eigen::Vector3d* v_j) const;

 private:
  void reset();
  void step(const ImuSample& a, const ImuSample& b);

  ImuBias bias_lin_;
  ImuNoiseParams noise_;
  std::vector<ImuSample> samples_;
  std::size_t rejected_ = 0;
  double sum_dt_ = 0;
  Eigen::Quaterniond delta_q_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d delta_v_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d delta_p_ = Eigen::Vector3d::Zero();
  Eigen::Matrix<double, 9, 6> jac_bias_ = Eigen::Matrix<double, 9, 6>::Zero();
  Matrix15 covariance_ = Matrix15::Zero();
};

}  // namespace mcvio::estimator
