#include "run_accuracy.hpp"

#include <Eigen/Cholesky>

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
  // NEES in the ground truth's world: the alignment rotates the estimate's covariance too.
  const Eigen::Matrix3d R = posyaw.T_gt_est.linear();
  double sum = 0;
  for (std::size_t i = 0; i < posyaw.aligned_estimate.size(); ++i) {
    const auto it = covariances.byTime().find(posyaw.aligned_estimate[i].t);
    if (it == covariances.byTime().end()) continue;
    const Eigen::Matrix3d P = R * it->second * R.transpose();
    const Eigen::Vector3d e = posyaw.ground_truth[i].p - posyaw.aligned_estimate[i].p;
    sum += e.dot(P.ldlt().solve(e));
    ++a.nees_frames;
  }
  a.position_nees = a.nees_frames ? sum / static_cast<double>(a.nees_frames) : 0.0;
  return a;
}

}  // namespace mcvio::pipeline::sequences
