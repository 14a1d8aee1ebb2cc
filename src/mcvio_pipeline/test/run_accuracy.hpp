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
  /// Mean of e^T P^-1 e over frames with a covariance, the estimate aligned at its first pose
  /// (the estimator's gauge): 3 = consistent.
  double position_nees = 0;
  /// The same after the whole-run position+yaw alignment (ATE's): not in the covariance's gauge,
  /// it counts the alignment's shift at the start, where the covariance is millimetres.
  double position_nees_whole_run_alignment = 0;
  std::size_t nees_frames = 0;
  /// Per frame with a covariance: the first-pose-aligned error and its covariance's diagonal.
  struct NeesSample {
    Timestamp t = 0;
    Eigen::Vector3d error = Eigen::Vector3d::Zero();     ///< p_gt - p_estimate [m], ground-truth world
    Eigen::Vector3d variance = Eigen::Vector3d::Zero();  ///< diagonal of the rotated covariance [m^2]
    double nees = 0;
  };
  std::vector<NeesSample> nees_samples;
};

/// Writes RunAccuracy::nees_samples as CSV (t [s], error xyz, sigma xyz, NEES); throws on I/O errors.
void writeNeesCsv(const RunAccuracy& accuracy, const std::string& path);

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
