#pragma once
#include <optional>
#include <string>
#include <vector>

#include "mcvio/evaluation/ate.hpp"
#include "mcvio/evaluation/conflict_label_timeline.hpp"
#include "mcvio/evaluation/detection_metrics.hpp"
#include "mcvio/evaluation/detector_log.hpp"
#include "mcvio/evaluation/evaluation_options.hpp"
#include "mcvio/evaluation/rpe.hpp"
#include "mcvio/evaluation/trajectory.hpp"

namespace mcvio::evaluation {

/// One run to evaluate: a named trajectory and, if the run wrote one, its detector log.
struct EstimateInput {
  std::string name;  ///< e.g. "reference", "mcvio"; unique within an evaluation
  Trajectory trajectory;
  std::optional<DetectorLog> detector;
  /// The run's per-frame (online) output where a later revision changed it (`mcvio run`'s
  /// trajectory_online.tum): what a live user saw. Unset: the same as `trajectory`.
  std::optional<Trajectory> online_trajectory;
};

/// Everything measured for one run.
struct EstimateEvaluation {
  std::string name;
  std::string trajectory_source;
  std::string detector_source;  ///< empty without a detector log
  std::size_t poses = 0;
  AteResult ate_se3;
  AteResult ate_posyaw;
  /// The per-frame output's ATE after position+yaw alignment, with an online trajectory.
  std::optional<AteResult> ate_posyaw_online;
  /// ATE pos+yaw RMSE of what the run output frame by frame: the online trajectory's, else the
  /// trajectory's (nothing was revised).
  double onlineAtePosYawRmse() const {
    return ate_posyaw_online ? ate_posyaw_online->translation.rmse : ate_posyaw.translation.rmse;
  }
  /// With labels: ATE over frames labelled in conflict and over the others (whole-run alignment).
  bool has_conflict_split = false;
  ErrorStatistics ate_se3_in_conflict, ate_posyaw_in_conflict, ate_se3_outside_conflict;
  RpeResult rpe_time;
  RpeResult rpe_distance;
  std::optional<DetectionResult> detection;  ///< with labels and a detector log
};

/// The whole evaluation of several runs of one sequence.
struct EvaluationReport {
  EvaluationOptions options;
  std::string ground_truth_source;
  std::size_t ground_truth_poses = 0;
  double ground_truth_duration_s = 0;
  double ground_truth_path_length_m = 0;
  Trajectory ground_truth;  ///< for plots
  std::optional<ConflictLabelTimeline> labels;
  std::string baseline;  ///< name of the estimate the others are compared with
  std::vector<EstimateEvaluation> estimates;

  const EstimateEvaluation* find(const std::string& name) const;
};

/// Runs ATE (SE(3), position+yaw, inside/outside conflict), RPE (time, distance) and detection
/// metrics for every estimate against one ground truth.
class Evaluator {
 public:
  explicit Evaluator(EvaluationOptions options = {});

  /// Throws std::invalid_argument for no estimates, duplicate names or an unknown baseline;
  /// mcvio::InputError if an estimate shares no time with the ground truth.
  EvaluationReport evaluate(const Trajectory& ground_truth, const std::vector<EstimateInput>& estimates,
                            const std::optional<ConflictLabelTimeline>& labels = std::nullopt) const;

 private:
  EvaluationOptions options_;
};

}  // namespace mcvio::evaluation
