#include "mcvio/evaluation/evaluator.hpp"

#include <algorithm>
#include <cctype>
#include <set>
#include <stdexcept>

namespace mcvio::evaluation {

const EstimateEvaluation* EvaluationReport::find(const std::string& name) const {
  for (const auto& e : estimates) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

Evaluator::Evaluator(EvaluationOptions options) : options_(std::move(options)) { options_.validate(); }

EvaluationReport Evaluator::evaluate(const Trajectory& ground_truth, const std::vector<EstimateInput>& estimates,
                                     const std::optional<ConflictLabelTimeline>& labels) const {
  if (estimates.empty()) throw std::invalid_argument("evaluation: no estimates");
  std::set<std::string> names;
  for (const auto& e : estimates) {
    // Names become file names in the report folder.
    const bool plain = !e.name.empty() && std::all_of(e.name.begin(), e.name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
    });
    if (!plain || e.name == "." || e.name == "..") {
      throw std::invalid_argument("evaluation: estimate name '" + e.name + "' must be letters, digits, '_', '-' or '.'");
    }
    if (!names.insert(e.name).second) throw std::invalid_argument("evaluation: estimate name '" + e.name + "' used twice");
  }
  EvaluationReport report;
  report.options = options_;
  report.ground_truth_source = ground_truth.source();
  report.ground_truth_poses = ground_truth.size();
  report.ground_truth_duration_s = ground_truth.durationSeconds();
  report.ground_truth_path_length_m = ground_truth.pathLength();
  report.ground_truth = ground_truth;
  report.labels = labels;
  report.baseline = options_.baseline.empty() ? estimates.front().name : options_.baseline;
  if (!names.count(report.baseline)) {
    throw std::invalid_argument("evaluation: baseline '" + report.baseline + "' is not one of the estimates");
  }

  AteOptions ate_options;
  ate_options.association = options_.association;
  ate_options.alignment = options_.alignment;
  RpeOptions rpe_time = RpeOptions::time(options_.rpe_delta_s);
  RpeOptions rpe_distance = RpeOptions::distance(options_.rpe_delta_m);
  for (RpeOptions* o : {&rpe_time, &rpe_distance}) {
    o->tolerance = options_.rpe_tolerance;
    o->association = options_.association;
  }
  const double label_tolerance = options_.detection.label_tolerance_s;
  const auto in_conflict = [&](Timestamp t) { return labels && labels->inConflictAt(t, label_tolerance).value_or(false); };
  const auto outside_conflict = [&](Timestamp t) {
    return labels && labels->inConflictAt(t, label_tolerance).value_or(true) == false;
  };

  for (const auto& input : estimates) {
    EstimateEvaluation e;
    e.name = input.name;
    e.trajectory_source = input.trajectory.source();
    e.poses = input.trajectory.size();
    e.ate_se3 = computeAte(input.trajectory, ground_truth, Alignment::kSe3, ate_options);
    e.ate_posyaw = computeAte(input.trajectory, ground_truth, Alignment::kPositionYaw, ate_options);
    if (input.online_trajectory)
      e.ate_posyaw_online = computeAte(*input.online_trajectory, ground_truth, Alignment::kPositionYaw, ate_options);
    if (labels) {
      e.has_conflict_split = true;
      e.ate_se3_in_conflict = e.ate_se3.translationWithin(in_conflict);
      e.ate_posyaw_in_conflict = e.ate_posyaw.translationWithin(in_conflict);
      e.ate_se3_outside_conflict = e.ate_se3.translationWithin(outside_conflict);
    }
    e.rpe_time = computeRpe(input.trajectory, ground_truth, rpe_time);
    e.rpe_distance = computeRpe(input.trajectory, ground_truth, rpe_distance);
    if (input.detector) {
      e.detector_source = input.detector->source();
      if (labels) e.detection = evaluateDetection(*input.detector, *labels, options_.detection);
    }
    report.estimates.push_back(std::move(e));
  }
  return report;
}

}  // namespace mcvio::evaluation
