#include "mcvio/estimator/imu_preintegrator.hpp"

#include <cmath>

#include <Eigen/Cholesky>

#include "mcvio/estimator/so3.hpp"

namespace mcvio::estimator {

ImuPreintegrator::ImuPreintegrator(const ImuBias& bias_lin, const ImuNoiseParams& noise)
    : bias_lin_(bias_lin), noise_(noise) {}

void ImuPreintegrator::reset() {
  sum_dt_ = 0;
  delta_q_.setIdentity();
  delta_v_.setZero();
  delta_p_.setZero();
  jac_bias_.setZero();
  covariance_.setZero();
}

void ImuPreintegrator::integrate(const ImuSample& sample) {
  if (!samples_.empty() && sample.t <= samples_.back().t) {
    ++rejected_;
    return;
  }
  if (!samples_.empty()) step(samples_.back(), sample);
  samples_.push_back(sample);
}

void ImuPreintegrator::repropagate(const ImuBias& bias_lin) {
  bias_lin_ = bias_lin;
  reset();
  for (std::size_t k = 1; k < samples_.size(); ++k) step(samples_[k - 1], samples_[k]);
}

bool ImuPreintegrator::needsRepropagation(const ImuBias& bias, double gyro_threshold,
                                          double accel_threshold) const {
  return (bias.gyro - bias_lin_.gyro).norm() > gyro_threshold ||
         (bias.accel - bias_lin_.accel).norm() > accel_threshold;
}

void ImuPreintegrator::step(const ImuSample& s0, const ImuSample& s1) {
  const double dt = toSeconds(s1.t - s0.t);
  const Eigen::Vector3d w = 0.5 * (s0.gyro + s1.gyro) - bias_lin_.gyro;
  const Eigen::Vector3d a0 = s0.accel - bias_lin_.accel;
  const Eigen::Vector3d a1 = s1.accel - bias_lin_.accel;

  const Eigen::Matrix3d R0 = delta_q_.toRotationMatrix();
  const Eigen::Quaterniond dq = so3::expQuat(w * dt);
  const Eigen::Matrix3d dR = dq.toRotationMatrix();
  const Eigen::Matrix3d R1 = R0 * dR;
  const Eigen::Matrix3d Jr = so3::rightJacobian(w * dt);
  const Eigen::Vector3d acc = 0.5 * (R0 * a0 + R1 * a1);

  // Error-state transition of [dtheta, dv, dp | dbg, dba] for this step: F = [A B; 0 I], A 9x9,
  // B 9x6. The same blocks propagate the bias Jacobians, which makes those exact derivatives of
  // the midpoint scheme. The products below use that structure (the bias rows of F are the
  // identity): about a third of the work of full 15x15 products.
  const Eigen::Matrix3d v_theta = -0.5 * dt * (R0 * so3::hat(a0) + R1 * so3::hat(a1) * dR.transpose());
  const Eigen::Matrix3d v_bg = 0.5 * dt * dt * R1 * so3::hat(a1) * Jr;
  const Eigen::Matrix3d v_ba = -0.5 * dt * (R0 + R1);
  Eigen::Matrix<double, 9, 9> A = Eigen::Matrix<double, 9, 9>::Identity();
  Eigen::Matrix<double, 9, 6> B = Eigen::Matrix<double, 9, 6>::Zero();
  A.block<3, 3>(0, 0) = dR.transpose();
  B.block<3, 3>(0, 0) = -Jr * dt;
  A.block<3, 3>(3, 0) = v_theta;
  B.block<3, 3>(3, 0) = v_bg;
  B.block<3, 3>(3, 3) = v_ba;
  A.block<3, 3>(6, 0) = 0.5 * dt * v_theta;
  A.block<3, 3>(6, 3) = Eigen::Matrix3d::Identity() * dt;
  B.block<3, 3>(6, 0) = 0.5 * dt * v_bg;
  B.block<3, 3>(6, 3) = 0.5 * dt * v_ba;

  // Noise input [n_g, n_a] into the first nine rows (G1), with discrete variances from the
  // continuous densities; the bias random walks add to the bias block directly.
  Eigen::Matrix<double, 9, 6> G1 = Eigen::Matrix<double, 9, 6>::Zero();
  G1.block<3, 3>(0, 0) = Jr * dt;
  G1.block<3, 3>(3, 0) = -v_bg;
  G1.block<3, 3>(3, 3) = -v_ba;
  G1.block<3, 3>(6, 0) = -0.5 * dt * v_bg;
  G1.block<3, 3>(6, 3) = -0.5 * dt * v_ba;
  const double g2 = noise_.gyroscope_noise_density * noise_.gyroscope_noise_density / dt;
  const double a2 = noise_.accelerometer_noise_density * noise_.accelerometer_noise_density / dt;
  const double bg2 = noise_.gyroscope_random_walk * noise_.gyroscope_random_walk * dt;
  const double ba2 = noise_.accelerometer_random_walk * noise_.accelerometer_random_walk * dt;
  Eigen::Matrix<double, 6, 1> q1;
  q1 << g2, g2, g2, a2, a2, a2;

  // [P11 P12; P21 P22] -> [M A^T + N B^T + G1 Q G1^T, N; N^T, P22 + Q_bias], M = A P11 + B P21,
  // N = A P12 + B P22.
  const Eigen::Matrix<double, 9, 9> M =
      A.lazyProduct(covariance_.topLeftCorner<9, 9>()) + B.lazyProduct(covariance_.bottomLeftCorner<6, 9>());
  const Eigen::Matrix<double, 9, 6> N =
      A.lazyProduct(covariance_.topRightCorner<9, 6>()) + B.lazyProduct(covariance_.bottomRightCorner<6, 6>());
  const Eigen::Matrix<double, 9, 9> P11 =
      M.lazyProduct(A.transpose()) + N.lazyProduct(B.transpose()) + (G1 * q1.asDiagonal()).lazyProduct(G1.transpose());
  covariance_.topLeftCorner<9, 9>() = 0.5 * (P11 + P11.transpose());
  covariance_.topRightCorner<9, 6>() = N;
  covariance_.bottomLeftCorner<6, 9>() = N.transpose();
  covariance_.diagonal().tail<6>() += (Eigen::Matrix<double, 6, 1>() << bg2, bg2, bg2, ba2, ba2, ba2).finished();
  const Eigen::Matrix<double, 9, 6> jac = A.lazyProduct(jac_bias_) + B;  // not in place: lazy products alias
  jac_bias_ = jac;

  delta_p_ += delta_v_ * dt + 0.5 * acc * dt * dt;
  delta_v_ += acc * dt;
  delta_q_ = (delta_q_ * dq).normalized();
  sum_dt_ += dt;
}

ImuPreintegrator::Matrix15 ImuPreintegrator::sqrtInformation() const {
  const Matrix15 info = covariance_.ldlt().solve(Matrix15::Identity());
  const Matrix15 sym = 0.5 * (info + info.transpose());
  return sym.llt().matrixU();
}

Eigen::Quaterniond ImuPreintegrator::correctedDeltaQ(const ImuBias& bias) const {
  return (delta_q_ * so3::expQuat(dR_dbg() * (bias.gyro - bias_lin_.gyro))).normalized();
}

Eigen::Vector3d ImuPreintegrator::correctedDeltaV(const ImuBias& bias) const {
  return delta_v_ + dV_dbg() * (bias.gyro - bias_lin_.gyro) + dV_dba() * (bias.accel - bias_lin_.accel);
}

Eigen::Vector3d ImuPreintegrator::correctedDeltaP(const ImuBias& bias) const {
  return delta_p_ + dP_dbg() * (bias.gyro - bias_lin_.gyro) + dP_dba() * (bias.accel - bias_lin_.accel);
}

ImuPreintegrator::Vector15 ImuPreintegrator::residual(const Eigen::Vector3d& p_i, const Eigen::Quaterniond& q_i,
                                                      const Eigen::Vector3d& v_i, const ImuBias& b_i,
                                                      const Eigen::Vector3d& p_j, const Eigen::Quaterniond& q_j,
                                                      const Eigen::Vector3d& v_j, const ImuBias& b_j,
                                                      const Eigen::Vector3d& gravity) const {
  const double dt = sum_dt_;
  const Eigen::Matrix3d Ri_t = q_i.toRotationMatrix().transpose();
  Vector15 r;
  r.segment<3>(0) = so3::logQuat(correctedDeltaQ(b_i).conjugate() * q_i.conjugate() * q_j);
  r.segment<3>(3) = Ri_t * (v_j - v_i - gravity * dt) - correctedDeltaV(b_i);
  r.segment<3>(6) = Ri_t * (p_j - p_i - v_i * dt - 0.5 * gravity * dt * dt) - correctedDeltaP(b_i);
  r.segment<3>(9) = b_j.gyro - b_i.gyro;
  r.segment<3>(12) = b_j.accel - b_i.accel;
  return r;
}

void ImuPreintegrator::predict(const Eigen::Vector3d& p_i, const Eigen::Quaterniond& q_i,
                               const Eigen::Vector3d& v_i, const ImuBias& b_i, const Eigen::Vector3d& gravity,
                               Eigen::Vector3d* p_j, Eigen::Quaterniond* q_j, Eigen::Vector3d* v_j) const {
  const double dt = sum_dt_;
  *q_j = (q_i * correctedDeltaQ(b_i)).normalized();
  *v_j = v_i + gravity * dt + q_i * correctedDeltaV(b_i);
  *p_j = p_i + v_i * dt + 0.5 * gravity * dt * dt + q_i * correctedDeltaP(b_i);
}

}  // namespace mcvio::estimator
