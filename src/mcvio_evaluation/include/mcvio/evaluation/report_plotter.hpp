#pragma once
#include <string>
#include <vector>

#include "mcvio/evaluation/evaluator.hpp"
#include "mcvio/evaluation/plot_canvas.hpp"

namespace mcvio::evaluation {

/// The PNG figures of an evaluation (estimates SE(3)-aligned, labelled conflict intervals shaded):
///   trajectory_top.png   x-y top view, equal scale, ground truth and every run
///   trajectory_side.png  height z over time
///   error_over_time.png  ATE (SE(3)) translation error of every run over time
///   roc.png              ROC curves of each run's detector scores (only with labels and detector logs)
class ReportPlotter {
 public:
  /// Writes the figures into `dir` (created) and returns their paths. Throws mcvio::InputError
  /// naming a file it cannot write.
  static std::vector<std::string> write(const EvaluationReport& report, const std::string& dir,
                                        const PlotStyle& style = {});

  /// Colour of the i-th run (BGR), distinct from the black ground truth and the shading.
  static cv::Scalar runColor(std::size_t i);
  /// Colour of the ground truth (BGR): near black.
  static cv::Scalar groundTruthColor();
  /// Colour of the labelled conflict intervals' shading (BGR): orange-red.
  static cv::Scalar conflictColor();
};

}  // namespace mcvio::evaluation
