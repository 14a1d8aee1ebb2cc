#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "mcvio/core/input_error.hpp"
#include "mcvio/evaluation/evaluator.hpp"
#include "mcvio/evaluation/report_writer.hpp"
#include "mcvio/evaluation/trajectory_io.hpp"
#include "synthetic_trajectory.hpp"

namespace mcvio::evaluation {
namespace {

constexpr Timestamp kT0 = 1'000'000'000;

/// 10 s straight line at 1 m/s with conflict labels on t in [4, 6) s; "reference" is 0.2 m off in
/// height during the conflict, "mcvio" 0.05 m.
struct Scenario {
  Trajectory gt = test::straightLine(10, 200, 1.0, kT0);
  ConflictLabelTimeline labels;
  std::vector<EstimateInput> estimates;

  Scenario() {
    std::vector<dataset::ConflictLabel> l;
    for (int i = 0; i <= 200; ++i) {
      dataset::ConflictLabel label;
      label.t = kT0 + Timestamp{i} * 50'000'000;
      label.in_conflict = i >= 80 && i < 120;
      l.push_back(label);
    }
    labels = ConflictLabelTimeline(l, "labels.csv");
    estimates.push_back({"reference", withHeightError(0.2), std::nullopt, std::nullopt});
    estimates.push_back({"mcvio", withHeightError(0.05), std::nullopt, std::nullopt});
  }

  Trajectory withHeightError(double dz) const {
    Trajectory est({}, "est_" + std::to_string(dz));
    for (const auto& label : labels.labels()) {
      StampedPose p = *gt.interpolate(label.t, 0.1);
      if (label.in_conflict) p.p.z() += dz;
      est.append(p);
    }
    return est;
  }
};

TEST(Evaluator, ConflictSplitAndBaselineReduction) {
  Scenario s;
  EvaluationOptions options;
  options.baseline = "reference";
  const EvaluationReport report = Evaluator(options).evaluate(s.gt, s.estimates, s.labels);
  ASSERT_EQ(report.estimates.size(), 2u);
  const auto& ref = report.estimates[0];
  const auto& mc = report.estimates[1];
  // Unaligned the conflict frames are off by exactly dz; alignment spreads part of it, so the
  // in-conflict figures scale with dz and the outside ones stay smaller.
  EXPECT_EQ(ref.ate_se3_in_conflict.count, 40u);
  EXPECT_EQ(ref.ate_se3_outside_conflict.count, 161u);
  EXPECT_GT(ref.ate_se3_in_conflict.rmse, ref.ate_se3_outside_conflict.rmse);
  EXPECT_NEAR(mc.ate_se3.translation.rmse / ref.ate_se3.translation.rmse, 0.25, 1e-6);
  EXPECT_NEAR(ReportWriter::relativeReduction(ref.ate_se3.translation.rmse, mc.ate_se3.translation.rmse), 75.0, 1e-4);
  // The height step is seen by RPE pairs that straddle the interval ends only.
  EXPECT_GT(ref.rpe_time.translation.max, 0.19);
  EXPECT_LT(ref.rpe_time.translation.min, 1e-9);
  // Position+yaw alignment only shifts the height: in-conflict error is dz * (1 - 40/201).
  EXPECT_NEAR(ref.ate_posyaw_in_conflict.mean, 0.2 * (1.0 - 40.0 / 201.0), 1e-9);
}

TEST(Evaluator, RejectsBadRunLists) {
  Scenario s;
  EXPECT_THROW(Evaluator().evaluate(s.gt, {}), std::invalid_argument);
  auto twice = s.estimates;
  twice[1].name = "reference";
  EXPECT_THROW(Evaluator().evaluate(s.gt, twice), std::invalid_argument);
  auto slash = s.estimates;
  slash[1].name = "a/b";
  EXPECT_THROW(Evaluator().evaluate(s.gt, slash), std::invalid_argument);
  EvaluationOptions unknown;
  unknown.baseline = "okvis";
  EXPECT_THROW(Evaluator(unknown).evaluate(s.gt, s.estimates), std::invalid_argument);
}

TEST(ReportWriter, JsonAndMarkdownCarryTheSameNumbers) {
  Scenario s;
  const EvaluationReport report = Evaluator().evaluate(s.gt, s.estimates, s.labels);
  EXPECT_EQ(report.baseline, "reference");  // the first run by default
  const std::string dir = test::freshDir("report");
  ReportWriter::write(report, dir);
  std::ifstream in(dir + "/eval.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["baseline"], "reference");
  EXPECT_EQ(j["estimates"].size(), 2u);
  EXPECT_EQ(j["labels"]["conflict_intervals"].size(), 1u);
  const double ref = j["metrics"]["reference"]["ate_se3_rmse_m"];
  const double mc = j["metrics"]["mcvio"]["ate_se3_rmse_m"];
  EXPECT_DOUBLE_EQ(ref, report.estimates[0].ate_se3.translation.rmse);
  EXPECT_NEAR(j["relative_reduction_percent"]["mcvio"]["ate_se3_rmse_m"].get<double>(), 100 * (ref - mc) / ref, 1e-9);
  EXPECT_FALSE(j["relative_reduction_percent"].contains("reference"));
  EXPECT_TRUE(j["estimates"][0]["detection"].is_null());

  std::ifstream md_in(dir + "/eval.md");
  std::stringstream md;
  md << md_in.rdbuf();
  EXPECT_EQ(md.str(), ReportWriter::toMarkdown(report));
  EXPECT_NE(md.str().find("| Metric | reference | mcvio | mcvio reduction vs reference |"), std::string::npos) << md.str();
  EXPECT_NE(md.str().find("| ATE SE(3) RMSE in conflict [m] |"), std::string::npos);
  EXPECT_NE(md.str().find("+75.0%"), std::string::npos) << md.str();

  // The aligned estimates and the ground truth are TUM files evo can read.
  EXPECT_EQ(loadTum(dir + "/mcvio_aligned_se3.tum").size(), 201u);
  EXPECT_EQ(loadTum(dir + "/ground_truth.tum").size(), s.gt.size());
}

TEST(Evaluator, PerFrameOutputIsMeasuredBesideTheRevisedTrajectory) {
  Scenario s;
  // mcvio's final trajectory is its 0.05 m one; frame by frame it had published 0.2 m off (a
  // conflict window revised it afterwards). The reference revised nothing.
  s.estimates[1].online_trajectory = s.withHeightError(0.2);
  const EvaluationReport report = Evaluator().evaluate(s.gt, s.estimates, s.labels);
  const auto& ref = report.estimates[0];
  const auto& mc = report.estimates[1];
  EXPECT_FALSE(ref.ate_posyaw_online.has_value());
  EXPECT_DOUBLE_EQ(ref.onlineAtePosYawRmse(), ref.ate_posyaw.translation.rmse);
  ASSERT_TRUE(mc.ate_posyaw_online.has_value());
  EXPECT_DOUBLE_EQ(mc.onlineAtePosYawRmse(), ref.ate_posyaw.translation.rmse);  // the same 0.2 m error
  EXPECT_GT(mc.onlineAtePosYawRmse(), 2.0 * mc.ate_posyaw.translation.rmse);

  const std::string dir = test::freshDir("report_online");
  ReportWriter::write(report, dir);
  std::ifstream in(dir + "/eval.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_DOUBLE_EQ(j["metrics"]["mcvio"]["ate_posyaw_online_rmse_m"].get<double>(), mc.onlineAtePosYawRmse());
  EXPECT_TRUE(j["estimates"][1]["ate"].contains("posyaw_online"));
  EXPECT_FALSE(j["estimates"][0]["ate"].contains("posyaw_online"));
  EXPECT_NE(ReportWriter::toMarkdown(report).find("| ATE pos+yaw RMSE, per-frame output [m] |"), std::string::npos);

  // Without any online trajectory the row is left out.
  Scenario plain;
  EXPECT_EQ(ReportWriter::toMarkdown(Evaluator().evaluate(plain.gt, plain.estimates, plain.labels)).find("per-frame output"),
            std::string::npos);
}

TEST(ReportWriter, EmptyStatisticsAreNullAndNa) {
  // A run shorter than the RPE delta: no pairs, so null in JSON and n/a in the table.
  const Trajectory gt = test::straightLine(0.5, 200, 1.0, kT0);
  const EvaluationReport report = Evaluator().evaluate(gt, {{"short", test::straightLine(0.5, 20, 1.0, kT0), std::nullopt, std::nullopt}});
  const auto j = nlohmann::json::parse(ReportWriter::toJson(report));
  EXPECT_TRUE(j["metrics"]["short"]["rpe_time_translation_rmse_m"].is_null());
  EXPECT_NE(ReportWriter::toMarkdown(report).find("n/a"), std::string::npos);
}

TEST(EvaluationOptions, YamlKeysAndErrors) {
  const std::string dir = test::freshDir("options");
  test::writeText(dir + "/ok.yaml", "rpe_delta_s: 2.5\nbaseline: ref\nassociation: {method: nearest, max_time_difference_s: 0.01}\n"
                                    "detection: {suspected_is_positive: true}\n");
  const EvaluationOptions o = EvaluationOptions::fromYamlFile(dir + "/ok.yaml");
  EXPECT_DOUBLE_EQ(o.rpe_delta_s, 2.5);
  EXPECT_EQ(o.baseline, "ref");
  EXPECT_EQ(o.association.method, AssociationOptions::Method::kNearest);
  EXPECT_DOUBLE_EQ(o.association.max_time_difference_s, 0.01);
  EXPECT_TRUE(o.detection.suspected_is_positive);
  const auto error = [&](const std::string& text) -> std::string {
    test::writeText(dir + "/bad.yaml", text);
    try {
      EvaluationOptions::fromYamlFile(dir + "/bad.yaml");
    } catch (const InputError& e) {
      return e.what();
    }
    return {};
  };
  EXPECT_NE(error("rpe_delta_x: 1\n").find("unknown evaluation option 'rpe_delta_x'"), std::string::npos);
  EXPECT_NE(error("rpe_delta_m: far\n").find("rpe_delta_m"), std::string::npos);
  EXPECT_NE(error("rpe_delta_m: -1\n").find("rpe_delta_m must be a finite number > 0"), std::string::npos);
  EXPECT_NE(error("association: {method: spline}\n").find("association.method"), std::string::npos);
  EXPECT_NE(error("association: [1]\n").find("'association' must be a map"), std::string::npos);
  EXPECT_NE(error("detection: {label_tolerance: 1}\n").find("unknown evaluation option 'detection.label_tolerance'"),
            std::string::npos);
  EXPECT_NE(error("rpe_delta_m: -1\n").find(dir + "/bad.yaml"), std::string::npos);
}

TEST(EvaluationOptions, ShippedConfigHoldsTheDefaults) {
  if (!std::filesystem::exists(MCVIO_EVAL_CONFIG)) GTEST_SKIP() << "no " << MCVIO_EVAL_CONFIG;
  const EvaluationOptions o = EvaluationOptions::fromYamlFile(MCVIO_EVAL_CONFIG);
  const EvaluationOptions d;
  EXPECT_EQ(o.rpe_delta_s, d.rpe_delta_s);
  EXPECT_EQ(o.rpe_delta_m, d.rpe_delta_m);
  EXPECT_EQ(o.rpe_tolerance, d.rpe_tolerance);
  EXPECT_EQ(o.baseline, d.baseline);
  EXPECT_EQ(o.association.method, d.association.method);
  EXPECT_EQ(o.association.max_interpolation_gap_s, d.association.max_interpolation_gap_s);
  EXPECT_EQ(o.association.max_time_difference_s, d.association.max_time_difference_s);
  EXPECT_EQ(o.alignment.min_position_spread_m, d.alignment.min_position_spread_m);
  EXPECT_EQ(o.detection.label_tolerance_s, d.detection.label_tolerance_s);
  EXPECT_EQ(o.detection.suspected_is_positive, d.detection.suspected_is_positive);
}

}  // namespace
}  // namespace mcvio::evaluation
