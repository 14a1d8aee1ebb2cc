#include "run_accuracy.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "mcvio/evaluation/ate.hpp"
#include "mcvio/evaluation/rpe.hpp"
#include "mcvio/evaluation/trajectory_io.hpp"

namespace mcvio::pipeline::sequences {

void CovarianceLog::add(const VioFrameResult& r) {
  const auto& e = r.estimate;
  if (!r.estimated || !e.frame_accepted || !e.covariance_valid || e.status != estimator::EstimatorStatus::kTracking) return;
  by_time_[e.t] = e.pose_covariance.topLeftCorner<3, 3>();
}

RunAccuracy evaluateRun(const std::string& tum_path, const std::vector<dataset::GroundTruthState>& ground_truth,
                        const CovarianceLog& covariances) {
  using namespace evaluation;
  std::vector<StampedPose> gt_poses;
  for (const auto& g : ground_truth) gt_poses.push_back({g.t, g.p_WB, g.q_WB});
  const Trajectory gt(gt_poses, "ground truth");
  const Trajectory est = loadTum(tum_path);
  const auto posyaw = computeAte(est, gt, Alignment::kPositionYaw);
  const auto se3 = computeAte(est, gt, Alignment::kSe3);
  const auto rpe = computeRpe(est, gt, RpeOptions::time(1.0));
  RunAccuracy a;
  a.poses = est.size();
  a.ate_pos_yaw_rmse = posyaw.translation.rmse;
  a.ate_pos_yaw_max = posyaw.translation.max;
  a.ate_se3_rmse = se3.translation.rmse;
  a.rpe_1s_translation_rmse = rpe.translation.rmse;
  a.rpe_1s_rotation_rmse_deg = rpe.rotation.rmse;
  // NEES needs the error in the covariance's gauge. The estimator fixes its first pose (position and
  // yaw, init_position_sigma / init_yaw_sigma), so the estimate is moved onto the ground truth at its
  // first pose; a whole-run alignment would instead spread late drift back over the start, where the
  // covariance is millimetres. Roll and pitch stay unaligned: gravity makes them observable.
  if (posyaw.aligned_estimate.empty()) return a;
  const Eigen::Matrix3d R_first_gap =
      posyaw.ground_truth[0].q.toRotationMatrix() * posyaw.aligned_estimate[0].q.toRotationMatrix().transpose();
  const Eigen::Matrix3d Rz(Eigen::AngleAxisd(std::atan2(R_first_gap(1, 0), R_first_gap(0, 0)), Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d t_first = posyaw.ground_truth[0].p - Rz * posyaw.aligned_estimate[0].p;
  const Eigen::Matrix3d R_whole = posyaw.T_gt_est.linear();
  double sum_first = 0, sum_whole = 0;
  for (std::size_t i = 0; i < posyaw.aligned_estimate.size(); ++i) {
    const auto it = covariances.byTime().find(posyaw.aligned_estimate[i].t);
    if (it == covariances.byTime().end()) continue;
    const Eigen::Vector3d& p_gt = posyaw.ground_truth[i].p;
    const Eigen::Vector3d& p_aligned = posyaw.aligned_estimate[i].p;
    const Eigen::Matrix3d P_whole = R_whole * it->second * R_whole.transpose();
    const Eigen::Matrix3d P_first = Rz * P_whole * Rz.transpose();
    const Eigen::Vector3d e_whole = p_gt - p_aligned;
    const Eigen::Vector3d e_first = p_gt - (Rz * p_aligned + t_first);
    sum_whole += e_whole.dot(P_whole.ldlt().solve(e_whole));
    const double nees_first = e_first.dot(P_first.ldlt().solve(e_first));
    sum_first += nees_first;
    a.nees_samples.push_back({posyaw.aligned_estimate[i].t, e_first, P_first.diagonal(), nees_first});
    ++a.nees_frames;
  }
  if (a.nees_frames > 0) {
    a.position_nees = sum_first / static_cast<double>(a.nees_frames);
    a.position_nees_whole_run_alignment = sum_whole / static_cast<double>(a.nees_frames);
  }
  return a;
}

void writeNeesCsv(const RunAccuracy& accuracy, const std::string& path) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path);
  f << "# t [s], p_gt - p_estimate [m] (x, y, z; estimate aligned at its first pose), sigma [m] (x, y, z), NEES\n";
  for (const auto& s : accuracy.nees_samples)
    f << std::fixed << std::setprecision(9) << toSeconds(s.t) << std::defaultfloat << "," << s.error.x() << "," << s.error.y() << "," << s.error.z() << ","
      << std::sqrt(s.variance.x()) << "," << std::sqrt(s.variance.y()) << "," << std::sqrt(s.variance.z()) << ","
      << s.nees << "\n";
  if (!f) throw std::runtime_error("error writing " + path);
}

}  // namespace mcvio::pipeline::sequences
