#pragma once
#include <string>

#include "mcvio/evaluation/evaluator.hpp"

namespace mcvio::evaluation {

/// Text forms of an EvaluationReport: JSON for scripts, Markdown for people.
///
/// The Markdown table has one row per metric and one column per estimate, plus for every
/// estimate other than the baseline a column with its relative reduction of each error
/// metric: 100 * (baseline - estimate) / baseline, so +20% means 20% less error than the
/// baseline and a negative value means more.
class ReportWriter {
 public:
  static std::string toJson(const EvaluationReport& report);
  static std::string toMarkdown(const EvaluationReport& report);

  /// Writes DIR/eval.json, DIR/eval.md, DIR/ground_truth.tum and DIR/<name>_aligned_se3.tum per
  /// estimate (creating DIR). Throws mcvio::InputError naming the file it cannot write.
  static void write(const EvaluationReport& report, const std::string& dir);

  /// 100 * (baseline - value) / baseline; NaN if either is NaN or the baseline is 0.
  static double relativeReduction(double baseline, double value);
};

}  // namespace mcvio::evaluation
