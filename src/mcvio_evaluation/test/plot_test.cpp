#include <algorithm>
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "mcvio/core/input_error.hpp"
#include "mcvio/evaluation/evaluator.hpp"
#include "mcvio/evaluation/plot_canvas.hpp"
#include "mcvio/evaluation/report_plotter.hpp"
#include "synthetic_trajectory.hpp"

namespace mcvio::evaluation {
namespace {

/// Pixels within `tol` of `color` (BGR) in every channel.
int countColor(const cv::Mat& img, cv::Scalar color, int tol = 10) {
  cv::Mat mask;
  cv::inRange(img, color - cv::Scalar::all(tol), color + cv::Scalar::all(tol), mask);
  return cv::countNonZero(mask);
}

TEST(PlotCanvas, NiceTicks) {
  const auto a = PlotCanvas::niceTicks(0, 1, 5);
  ASSERT_EQ(a.size(), 6u);
  EXPECT_NEAR(a[1], 0.2, 1e-12);
  EXPECT_NEAR(a[5], 1.0, 1e-12);
  const auto b = PlotCanvas::niceTicks(-3.7, 12.2, 6);  // raw step 2.65 -> 2
  ASSERT_EQ(b.size(), 8u);
  EXPECT_NEAR(b.front(), -2.0, 1e-12);
  EXPECT_NEAR(b.back(), 12.0, 1e-12);
  EXPECT_TRUE(PlotCanvas::niceTicks(1, 1).empty());
}

TEST(PlotCanvas, WritesAPngOfTheRequestedSizeWithTheData) {
  PlotStyle style;
  style.width = 640;
  style.height = 480;
  PlotCanvas c("test", style);
  c.setXLabel("x [m]");
  c.setYLabel("y [m]");
  const cv::Scalar blue(200, 60, 20);
  c.addLine({0, 1, 2, 3}, {0, 1, 0, 1}, blue, "zigzag", 3);
  c.addXBand(1, 2, cv::Scalar(80, 130, 255), "band");
  const std::string path = test::freshDir("plot_canvas") + "/p.png";
  c.save(path);
  ASSERT_GT(std::filesystem::file_size(path), 1000u);
  const cv::Mat img = cv::imread(path);
  ASSERT_FALSE(img.empty());
  EXPECT_EQ(img.cols, 640);
  EXPECT_EQ(img.rows, 480);
  EXPECT_GT(countColor(img, cv::Scalar(255, 255, 255), 0), 640 * 480 / 2);  // white background
  EXPECT_GT(countColor(img, blue), 300);  // the line (plot and legend)
}

TEST(PlotCanvas, DegenerateDataStillRenders) {
  PlotCanvas c("one point");
  c.addLine({2.0}, {3.0}, cv::Scalar(0, 0, 255), "point");
  c.addLine({}, {}, cv::Scalar(0, 255, 0), "");
  c.addLine({0, 1}, {NAN, NAN}, cv::Scalar(255, 0, 0), "nan");
  const cv::Mat img = c.render();
  EXPECT_EQ(img.cols, 1000);
  EXPECT_GT(countColor(img, cv::Scalar(0, 0, 255)), 20);
  EXPECT_THROW(c.addLine({1, 2}, {1}, cv::Scalar(), "bad"), std::invalid_argument);
}

TEST(PlotCanvas, UnwritablePathNamesTheFile) {
  PlotCanvas c("x");
  c.addLine({0, 1}, {0, 1}, cv::Scalar(0, 0, 0), "l");
  const std::string path = test::freshDir("plot_unwritable") + "/no/such/dir/p.png";
  try {
    c.save(path);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
  }
}

TEST(ReportPlotter, WritesEveryFigure) {
  const Timestamp t0 = 1'000'000'000;
  const Trajectory gt = test::lissajous(20, 200, t0);
  std::vector<dataset::ConflictLabel> labels;
  std::vector<DetectorRecord> rows;
  for (int i = 0; i <= 400; ++i) {
    dataset::ConflictLabel l;
    l.t = t0 + Timestamp{i} * 50'000'000;
    l.in_conflict = i >= 150 && i < 250;
    labels.push_back(l);
    DetectorRecord r;
    r.t = l.t;
    r.state = (i >= 160 && i < 250) ? DetectorRecord::State::kConflict : DetectorRecord::State::kNone;
    r.propagated_chi2 = (i >= 160 && i < 250) ? 30.0 + i % 7 : 5.0 + i % 11;
    r.propagated_threshold = 12.6;
    r.inconsistent_fraction = l.in_conflict ? 0.5 + 0.01 * (i % 10) : 0.02 * (i % 30);
    // Untested during the warm-up; far above 1 inside the interval (clipped in the plot).
    r.evidence_score = i < 20 ? NAN : std::max(r.propagated_chi2 / r.propagated_threshold, r.inconsistent_fraction / 0.6);
    rows.push_back(r);
  }
  Trajectory ref, mc;
  for (const auto& l : labels) {
    StampedPose p = *gt.interpolate(l.t, 0.1);
    const double s = toSeconds(l.t - t0);
    StampedPose q = p;
    p.p += Eigen::Vector3d(0.01 * s, 0.005 * s, l.in_conflict ? 0.3 : 0.0);
    q.p += Eigen::Vector3d(0.004 * s, -0.002 * s, l.in_conflict ? 0.05 : 0.0);
    ref.append(p);
    mc.append(q);
  }
  const DetectorLog log(rows, {"timestamp_ns", "state", "propagated_chi2", "propagated_threshold", "inconsistent_fraction", "evidence_score"}, "c.csv");
  const EvaluationReport report = Evaluator().evaluate(
      gt, {{"reference", ref, std::nullopt, std::nullopt}, {"mcvio", mc, log, std::nullopt}}, ConflictLabelTimeline(labels, "labels.csv"));
  const std::string dir = test::freshDir("plots");
  const auto files = ReportPlotter::write(report, dir);
  ASSERT_EQ(files.size(), 5u);
  for (const char* name : {"trajectory_top.png", "trajectory_side.png", "error_over_time.png", "evidence_over_time.png", "roc.png"}) {
    const std::string path = dir + "/" + name;
    ASSERT_TRUE(std::filesystem::exists(path)) << path;
    EXPECT_GT(std::filesystem::file_size(path), 5000u) << path;
    const cv::Mat img = cv::imread(path);
    ASSERT_FALSE(img.empty()) << path;
    EXPECT_EQ(img.cols, 1000) << path;
    EXPECT_EQ(img.rows, 700) << path;
    EXPECT_GT(countColor(img, ReportPlotter::runColor(1), 20), 200) << path;  // the mcvio curve
  }
  // Without a detector log there is no ROC or evidence figure.
  const EvaluationReport plain = Evaluator().evaluate(gt, {{"reference", ref, std::nullopt, std::nullopt}});
  EXPECT_EQ(ReportPlotter::write(plain, test::freshDir("plots_plain")).size(), 3u);
}

}  // namespace
}  // namespace mcvio::evaluation
