#pragma once
#include <string>

#include "mcvio/evaluation/alignment.hpp"
#include "mcvio/evaluation/association.hpp"
#include "mcvio/evaluation/detection_metrics.hpp"

namespace mcvio::evaluation {

/// Everything an evaluation measures, with the defaults `mcvio eval` uses.
struct EvaluationOptions {
  AssociationOptions association;
  AlignmentOptions alignment;
  /// RPE over this time [s]: 1 s spans 20 frames of a 20 Hz camera, short-term drift.
  double rpe_delta_s = 1.0;
  /// RPE over this ground-truth path length [m]: EuRoC rooms and the simulator's scenes are a
  /// few metres across, so 1 m yields many pairs per run.
  double rpe_delta_m = 1.0;
  /// Relative slack of an RPE pair's separation (see RpeOptions::tolerance).
  double rpe_tolerance = 0.1;
  DetectionOptions detection;
  /// Name of the estimate the others are compared with; empty: the first estimate.
  std::string baseline;

  /// Keys as the field names, optionally under `association:` / `detection:` maps, e.g.
  ///   rpe_delta_s: 2.0
  ///   association: {method: nearest, max_time_difference_s: 0.01}
  ///   alignment: {min_position_spread_m: 0.2}
  ///   detection: {suspected_is_positive: true}
  /// Throws mcvio::InputError naming the file and key for unknown keys, wrong types or values.
  static EvaluationOptions fromYamlFile(const std::string& path);

  /// Throws std::invalid_argument naming the field.
  void validate() const;
};

}  // namespace mcvio::evaluation
