#pragma once
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "mcvio/dataset/ground_truth_state.hpp"
#include "mcvio/pipeline/vio_pipeline.hpp"

namespace mcvio::pipeline::sequences {

/// Accuracy of one `mcvio run` output against ground truth.
struct RunAccuracy {
  std::size_t poses = 0;
  double ate_pos_yaw_rmse = 0, ate_pos_yaw_max = 0;  ///< [m], position + yaw alignment
  double ate_se3_rmse = 0;                            ///< [m], SE(3) alignment
  double rpe_1s_translation_rmse = 0;                 ///< [m] over 1 s
  double rpe_1s_rotation_rmse_deg = 0;
  double position_nees = 0;  ///< mean of e^T P^-1 e over frames with a covariance (3 = consistent)
  std::size_t nees_frames = 0;
};

/// Position covariances of a run by frame time, collected with OfflineRunOptions::on_frame.
class CovarianceLog {
 public:
  void add(const VioFrameResult& r);
  const std::map<Timestamp, Eigen::Matrix3d>& byTime() const { return by_time_; }

 private:
  std::map<Timestamp, Eigen::Matrix3d> by_time_;
};

/// Reads OUT/trajectory.tum and measures it against `ground_truth`.
RunAccuracy evaluateRun(const std::string& tum_path, const std::vector<dataset::GroundTruthState>& ground_truth,
                        const CovarianceLog& covariances);

}  // namespace mcvio::pipeline::sequences
