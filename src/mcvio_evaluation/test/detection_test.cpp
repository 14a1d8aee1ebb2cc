#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/evaluation/detection_metrics.hpp"
#include "synthetic_trajectory.hpp"

namespace mcvio::evaluation {
namespace {

constexpr Timestamp kT0 = 1'000'000'000;
constexpr Timestamp kFrame = 50'000'000;  // 20 Hz

/// 20 frames, frames 5..12 in conflict (8 positives, 12 negatives).
ConflictLabelTimeline twentyFrameLabels() {
  std::vector<dataset::ConflictLabel> labels;
  for (int i = 0; i < 20; ++i) {
    dataset::ConflictLabel l;
    l.t = kT0 + i * kFrame;
    l.in_conflict = i >= 5 && i <= 12;
    l.motion = l.in_conflict ? "elevator" : "none";
    labels.push_back(l);
  }
  return ConflictLabelTimeline(labels, "labels.csv");
}

DetectorRecord row(int frame, DetectorRecord::State state, double chi2_ratio, double fraction) {
  DetectorRecord r;
  r.t = kT0 + frame * kFrame + 1000;  // stamps a microsecond off: matched within the tolerance
  r.state = state;
  r.propagated_chi2 = chi2_ratio * 12.6;
  r.propagated_threshold = 12.6;
  r.inconsistent_fraction = fraction;
  return r;
}

std::string loadError(const std::string& name, const std::string& text, std::string* path_out = nullptr) {
  const std::string path = test::freshDir(name) + "/conflict.csv";
  test::writeText(path, text);
  if (path_out) *path_out = path;
  try {
    DetectorLog::load(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

const std::string kHeader =
    "timestamp_ns,state,propagated_chi2,propagated_threshold,landmarks_tested,landmarks_inconsistent,"
    "inconsistent_fraction,coherence,interval_start_ns,resolution_mode\n";

TEST(Roc, KnownAreas) {
  // Positives 0.9 and 0.6, negatives 0.8 and 0.3: 3 of 4 pairs ordered correctly.
  const RocCurve mixed = computeRoc({0.9, 0.8, 0.6, 0.3}, {true, false, true, false}, "s");
  EXPECT_DOUBLE_EQ(mixed.auc, 0.75);
  ASSERT_EQ(mixed.points.size(), 5u);
  EXPECT_DOUBLE_EQ(mixed.points[1].tpr, 0.5);
  EXPECT_DOUBLE_EQ(mixed.points[1].fpr, 0.0);
  EXPECT_DOUBLE_EQ(mixed.points[2].fpr, 0.5);
  EXPECT_DOUBLE_EQ(mixed.points.back().tpr, 1.0);
  EXPECT_DOUBLE_EQ(mixed.points.back().fpr, 1.0);
  EXPECT_DOUBLE_EQ(computeRoc({3, 2, 1, 0}, {true, true, false, false}, "s").auc, 1.0);
  EXPECT_DOUBLE_EQ(computeRoc({3, 2, 1, 0}, {false, false, true, true}, "s").auc, 0.0);
  // A tie between a positive and a negative counts half.
  EXPECT_DOUBLE_EQ(computeRoc({0.5, 0.5}, {true, false}, "s").auc, 0.5);
  const RocCurve with_nan = computeRoc({NAN, 1, 0}, {true, true, false}, "s");
  EXPECT_EQ(with_nan.skipped, 1u);
  EXPECT_DOUBLE_EQ(with_nan.auc, 1.0);
  EXPECT_TRUE(std::isnan(computeRoc({1, 2}, {true, true}, "s").auc));
  EXPECT_THROW(computeRoc({1}, {}, "s"), std::invalid_argument);
}

TEST(Detection, TprFprPerFrameOnConstructedLabels) {
  // Detector late by one frame: conflict on frames 6..13.
  std::vector<DetectorRecord> rows;
  for (int i = 0; i < 20; ++i) {
    const bool flagged = i >= 6 && i <= 13;
    rows.push_back(row(i, flagged ? DetectorRecord::State::kConflict
                                  : (i == 5 ? DetectorRecord::State::kSuspected : DetectorRecord::State::kNone),
                       flagged ? 2.0 : 0.5, i >= 5 && i <= 12 ? 0.6 : 0.1));
  }
  const DetectorLog log(rows, {"timestamp_ns", "state", "propagated_chi2", "propagated_threshold", "inconsistent_fraction"}, "c.csv");
  const DetectionResult r = evaluateDetection(log, twentyFrameLabels());
  EXPECT_EQ(r.frames, 20u);
  EXPECT_EQ(r.counts.tp, 7u);
  EXPECT_EQ(r.counts.fn, 1u);
  EXPECT_EQ(r.counts.fp, 1u);
  EXPECT_EQ(r.counts.tn, 11u);
  EXPECT_DOUBLE_EQ(r.counts.tpr(), 7.0 / 8.0);
  EXPECT_DOUBLE_EQ(r.counts.fpr(), 1.0 / 12.0);
  EXPECT_DOUBLE_EQ(r.counts.precision(), 7.0 / 8.0);
  ASSERT_EQ(r.roc.size(), 2u);
  // chi2 ratio 2.0 on frames 6..13, 0.5 elsewhere. Over the 8 x 12 pairs: 7 high positives beat
  // 11 low negatives, tie with 1 high negative; 1 low positive ties with 11 low negatives.
  EXPECT_EQ(r.roc[0].score, "propagated_chi2_ratio");
  EXPECT_NEAR(r.roc[0].auc, (7.0 * 11 + 0.5 * 7 * 1 + 0.5 * 1 * 11) / 96.0, 1e-12);
  EXPECT_EQ(r.roc[1].score, "inconsistent_fraction");
  EXPECT_DOUBLE_EQ(r.roc[1].auc, 1.0);

  DetectionOptions suspected;
  suspected.suspected_is_positive = true;
  const DetectionResult s = evaluateDetection(log, twentyFrameLabels(), suspected);
  EXPECT_EQ(s.counts.tp, 8u);
  EXPECT_EQ(s.counts.fn, 0u);
}

TEST(Detection, OnsetDelayAndReleaseLagPerLabelledInterval) {
  // 30 frames, three labelled intervals: 3..6, 12..16, 22..24.
  std::vector<dataset::ConflictLabel> labels;
  for (int i = 0; i < 30; ++i) {
    dataset::ConflictLabel l;
    l.t = kT0 + i * kFrame;
    l.in_conflict = (i >= 3 && i <= 6) || (i >= 12 && i <= 16) || (i >= 22 && i <= 24);
    l.motion = l.in_conflict ? "vehicle" : "none";
    labels.push_back(l);
  }
  // The first two frames late and three frames past the end; the second two frames late and one
  // frame early; the third never (a detection after it, at 26, belongs to no interval).
  std::vector<DetectorRecord> rows;
  for (int i = 0; i < 30; ++i) {
    const bool on = (i >= 5 && i <= 9) || (i >= 14 && i <= 15) || i == 26;
    rows.push_back(row(i, on ? DetectorRecord::State::kConflict : DetectorRecord::State::kNone, 0.1, 0.0));
  }
  // Rows given out of time order are put in order first.
  std::swap(rows[8], rows[20]);
  const DetectionResult r =
      evaluateDetection(DetectorLog(rows, {"timestamp_ns", "state"}, "c.csv"), ConflictLabelTimeline(labels, "l.csv"));
  ASSERT_EQ(r.intervals.size(), 3u);
  const double frame_s = toSeconds(kFrame);
  EXPECT_EQ(r.intervals[0].frames, 4u);
  EXPECT_EQ(r.intervals[0].detected_frames, 2u);
  EXPECT_NEAR(r.intervals[0].onset_delay_s, 2 * frame_s, 1e-5);
  EXPECT_NEAR(r.intervals[0].release_lag_s, 3 * frame_s, 1e-5);
  EXPECT_EQ(r.intervals[1].detected_frames, 2u);
  EXPECT_NEAR(r.intervals[1].onset_delay_s, 2 * frame_s, 1e-5);
  EXPECT_NEAR(r.intervals[1].release_lag_s, -1 * frame_s, 1e-5);
  EXPECT_EQ(r.intervals[2].frames, 3u);
  EXPECT_EQ(r.intervals[2].detected_frames, 0u);
  EXPECT_TRUE(std::isnan(r.intervals[2].onset_delay_s));
  EXPECT_TRUE(std::isnan(r.intervals[2].release_lag_s));
  EXPECT_EQ(r.intervals[2].label.start, kT0 + 22 * kFrame);
  EXPECT_EQ(r.intervals[2].label.end, kT0 + 24 * kFrame);

  // As one span (3..24): detected from frame 5, the last detection inside ends at frame 15.
  const IntervalDetection span = r.labelledSpan();
  EXPECT_EQ(span.label.start, kT0 + 3 * kFrame);
  EXPECT_EQ(span.label.end, kT0 + 24 * kFrame);
  EXPECT_EQ(span.frames, 12u);
  EXPECT_EQ(span.detected_frames, 4u);
  EXPECT_NEAR(span.onset_delay_s, 2 * frame_s, 1e-5);
  EXPECT_NEAR(span.release_lag_s, -9 * frame_s, 1e-5);
  // A first interval never detected (a label flickering on before the real onset): the onset
  // counts from it to the first detection of the next one.
  DetectionResult flicker;
  flicker.intervals = {r.intervals[2], r.intervals[2]};
  flicker.intervals[0].label = {kT0 + 1 * kFrame, kT0 + 1 * kFrame};
  flicker.intervals[1] = r.intervals[1];
  EXPECT_NEAR(flicker.labelledSpan().onset_delay_s, 13 * frame_s, 1e-5);
  EXPECT_NEAR(flicker.labelledSpan().release_lag_s, -1 * frame_s, 1e-5);
  EXPECT_TRUE(std::isnan(DetectionResult{}.labelledSpan().onset_delay_s));
}

TEST(Detection, UnmatchedRowsAndLabelsAreCounted) {
  std::vector<DetectorRecord> rows;
  for (int i = 3; i < 20; ++i) rows.push_back(row(i, DetectorRecord::State::kNone, 0.1, 0.0));
  DetectorRecord late = row(40, DetectorRecord::State::kNone, 0.1, 0.0);
  rows.push_back(late);
  const DetectionResult r = evaluateDetection(DetectorLog(rows, {"timestamp_ns", "state"}, "c.csv"), twentyFrameLabels());
  EXPECT_EQ(r.frames, 17u);
  EXPECT_EQ(r.labels_without_row, 3u);
  EXPECT_EQ(r.rows_without_label, 1u);
  EXPECT_EQ(r.counts.fn, 8u);
  EXPECT_DOUBLE_EQ(r.counts.tpr(), 0.0);
  EXPECT_TRUE(r.roc.empty());  // no score columns in this log
}

TEST(ConflictLabelTimeline, IntervalsAndLookups) {
  const ConflictLabelTimeline labels = twentyFrameLabels();
  ASSERT_EQ(labels.conflictIntervals().size(), 1u);
  EXPECT_EQ(labels.conflictIntervals()[0].start, kT0 + 5 * kFrame);
  EXPECT_EQ(labels.conflictIntervals()[0].end, kT0 + 12 * kFrame);
  EXPECT_EQ(labels.conflictFrames(), 8u);
  EXPECT_EQ(labels.inConflictAt(kT0 + 5 * kFrame + 10'000'000, 0.02), std::optional<bool>(true));
  EXPECT_EQ(labels.inConflictAt(kT0 + 4 * kFrame + 10'000'000, 0.02), std::optional<bool>(false));
  EXPECT_FALSE(labels.inConflictAt(kT0 + 30 * kFrame, 0.02).has_value());
}

TEST(ConflictLabelTimeline, LoadsFromAFolderAndNamesBadLines) {
  const std::string dir = test::freshDir("labels");
  std::filesystem::create_directories(dir + "/mav0");
  test::writeText(dir + "/mav0/conflict_labels.csv",
                  "#timestamp [ns],in_conflict,motion,covered_fraction\n1000,0,none,0\n2000,1,elevator,0.9\n"
                  "3000,1,elevator,0.9\n4000,0,none,0\n5000,1,vehicle,0.5\n");
  const ConflictLabelTimeline labels = ConflictLabelTimeline::load(dir);
  EXPECT_EQ(labels.conflictIntervals().size(), 2u);
  EXPECT_EQ(labels.source(), dir + "/mav0/conflict_labels.csv");
  test::writeText(dir + "/bad.csv", "#timestamp [ns],in_conflict,motion,covered_fraction\n1000,0,none,0\n2000,2,x,0\n");
  try {
    ConflictLabelTimeline::load(dir + "/bad.csv");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/bad.csv:3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("in_conflict"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ConflictLabelTimeline::load(test::freshDir("labels_none")), InputError);
}

TEST(DetectorLog, ReadsTheFullFormat) {
  const std::string dir = test::freshDir("detector_full");
  test::writeText(dir + "/conflict.csv", kHeader +
                                             "1000,none,1.5,12.59,40,2,0.05,0,0,reference\n"
                                             "2000,suspected,20.0,12.59,38,10,0.26,0.9,2000,imu\n"
                                             "3000,conflict,30.5,12.59,35,20,0.57,0.95,2000,imu\n");
  const DetectorLog log = DetectorLog::load(dir + "/conflict.csv");
  ASSERT_EQ(log.size(), 3u);
  EXPECT_TRUE(log.hasColumn("coherence"));
  const auto& r = log.records()[2];
  EXPECT_EQ(r.t, 3000);
  EXPECT_EQ(r.state, DetectorRecord::State::kConflict);
  EXPECT_DOUBLE_EQ(r.propagated_chi2, 30.5);
  EXPECT_EQ(r.landmarks_tested, 35);
  EXPECT_EQ(r.landmarks_inconsistent, 20);
  EXPECT_DOUBLE_EQ(r.inconsistent_fraction, 0.57);
  EXPECT_EQ(r.interval_start, 2000);
  EXPECT_EQ(r.resolution_mode, "imu");
  EXPECT_NEAR(r.propagatedRatio(), 30.5 / 12.59, 1e-12);
}

TEST(DetectorLog, IntervalsInHindsight) {
  const std::string dir = test::freshDir("detector_hindsight");
  const std::string h = "timestamp_ns,state,interval_start_ns,interval_onset_ns,interval_end_ns\n";
  test::writeText(dir + "/conflict.csv", h +
                                             "1000,none,0,0,0\n"
                                             "2000,suspected,0,0,0\n"
                                             "3000,conflict,2000,1500,0\n"
                                             "4000,conflict,2000,1500,0\n"
                                             "5000,none,2000,1500,3500\n"  // closed: last evidence at 3500
                                             "6000,none,2000,1500,3500\n"
                                             "7000,conflict,7000,6500,0\n"   // still open at the end
                                             "8000,conflict,7000,6500,0\n");
  const DetectorLog log = DetectorLog::load(dir + "/conflict.csv");
  ASSERT_TRUE(log.hasHindsightIntervals());
  const auto iv = log.hindsightIntervals();
  ASSERT_EQ(iv.size(), 2u);
  EXPECT_EQ(iv[0], std::make_pair(Timestamp{1500}, Timestamp{3500}));
  EXPECT_EQ(iv[1], std::make_pair(Timestamp{6500}, Timestamp{8000}));
  EXPECT_EQ(log.records()[4].interval_end, 3500);

  // Labels: conflict over frames 2..4 and 7..8 of 1 us spacing.
  const std::string ldir = test::freshDir("detector_hindsight_labels");
  std::filesystem::create_directories(ldir + "/mav0");
  test::writeText(ldir + "/mav0/conflict_labels.csv",
                  "#timestamp [ns],in_conflict,motion,covered_fraction\n1000,0,none,0\n2000,1,elevator,1\n3000,1,elevator,1\n"
                  "4000,1,elevator,1\n5000,0,none,0\n6000,0,none,0\n7000,1,elevator,1\n8000,1,elevator,1\n");
  DetectionOptions o;
  o.label_tolerance_s = 1e-7;
  const auto d = evaluateDetection(log, ConflictLabelTimeline::load(ldir), o);
  // Online: frames 3, 4, 7, 8 detected of 2, 3, 4, 7, 8.
  EXPECT_EQ(d.counts.tp, 4u);
  EXPECT_EQ(d.counts.fn, 1u);
  // In hindsight [1500, 3500] and [6500, 8000]: frame 2 and 3 in, frame 4 (after the last
  // evidence) out.
  ASSERT_TRUE(d.has_hindsight);
  EXPECT_EQ(d.hindsight.tp, 4u);
  EXPECT_EQ(d.hindsight.fn, 1u);
  EXPECT_EQ(d.hindsight.fp, 0u);
  EXPECT_EQ(d.hindsight.tn, 3u);
}

TEST(DetectorLog, TheEvidenceScoreGivesItsOwnRoc) {
  // The combined score separates what neither statistic alone does: frames 5..8 of the labelled
  // interval show in the chi2 only, frames 9..12 in the fraction only.
  const std::string dir = test::freshDir("detector_evidence");
  std::string text = "timestamp_ns,state,propagated_chi2,propagated_threshold,inconsistent_fraction,evidence_score\n";
  for (int i = 0; i < 20; ++i) {
    const bool chi2_part = i >= 5 && i <= 8, fraction_part = i >= 9 && i <= 12;
    const double chi2 = chi2_part ? 30.0 : 2.0, fraction = fraction_part ? 0.5 : 0.02;
    const std::string score = i < 2 ? "nan" : std::to_string(std::max(chi2 / 20.0, fraction / 0.6));
    text += std::to_string(kT0 + i * kFrame) + (chi2_part || fraction_part ? ",conflict," : ",none,") +
            std::to_string(chi2) + ",20," + std::to_string(fraction) + "," + score + "\n";
  }
  test::writeText(dir + "/conflict.csv", text);
  const DetectorLog log = DetectorLog::load(dir + "/conflict.csv");
  EXPECT_TRUE(std::isnan(log.records()[0].evidence_score)) << "nan: not tested";
  EXPECT_DOUBLE_EQ(log.records()[5].evidence_score, 1.5);
  const DetectionResult r = evaluateDetection(log, twentyFrameLabels());
  ASSERT_EQ(r.roc.size(), 3u);
  EXPECT_EQ(r.roc[2].score, "evidence_score");
  EXPECT_EQ(r.roc[2].skipped, 2u);
  EXPECT_DOUBLE_EQ(r.roc[2].auc, 1.0);
  EXPECT_LT(r.roc[0].auc, 0.8);
  EXPECT_LT(r.roc[1].auc, 0.8);

  std::string path;
  const std::string h = "timestamp_ns,state,evidence_score\n";
  std::string e = loadError("det_score", h + "1000,none,-0.5\n", &path);
  EXPECT_NE(e.find(path + ":2:"), std::string::npos) << e;
  EXPECT_NE(e.find("evidence_score"), std::string::npos) << e;
  e = loadError("det_score_text", h + "1000,none,high\n", &path);
  EXPECT_NE(e.find("evidence_score"), std::string::npos) << e;
  e = loadError("det_score_inf", h + "1000,none,inf\n", &path);
  EXPECT_NE(e.find("evidence_score"), std::string::npos) << e;
}

TEST(DetectorLog, ToleratesMissingOptionalColumnsInAnyOrder) {
  const std::string dir = test::freshDir("detector_partial");
  test::writeText(dir + "/conflict.csv", "# state,inconsistent_fraction,timestamp_ns\nnone,0.1,1000\nconflict,0.7,2000\n");
  const DetectorLog log = DetectorLog::load(dir + "/conflict.csv");
  ASSERT_EQ(log.size(), 2u);
  EXPECT_FALSE(log.hasColumn("propagated_chi2"));
  EXPECT_TRUE(std::isnan(log.records()[1].propagated_chi2));
  EXPECT_EQ(log.records()[1].t, 2000);
  EXPECT_DOUBLE_EQ(log.records()[1].inconsistent_fraction, 0.7);
  EXPECT_EQ(log.records()[1].landmarks_tested, -1);
  // Without a header: the full order, with or without the two hindsight columns.
  test::writeText(dir + "/old.csv", "1000,none,1,12,4,0,0,0,0,reference\n2000,conflict,30,12,4,3,0.7,1,2000,imu\n");
  const DetectorLog old = DetectorLog::load(dir + "/old.csv");
  ASSERT_EQ(old.size(), 2u);
  EXPECT_FALSE(old.hasHindsightIntervals());
  test::writeText(dir + "/new.csv", "1000,none,1,12,4,0,0,0,0,reference,0,0\n2000,conflict,30,12,4,3,0.7,1,2000,imu,1500,0\n");
  const DetectorLog now = DetectorLog::load(dir + "/new.csv");
  ASSERT_TRUE(now.hasHindsightIntervals());
  EXPECT_EQ(now.records()[1].interval_onset, 1500);
}

TEST(DetectorLog, MalformedLinesNameFileLineAndColumn) {
  std::string path;
  std::string e = loadError("det_state", kHeader + "1000,none,1,12,4,0,0,0,0,reference\n2000,maybe,1,12,4,0,0,0,0,reference\n", &path);
  EXPECT_NE(e.find(path + ":3:"), std::string::npos) << e;
  EXPECT_NE(e.find("'state'"), std::string::npos) << e;

  e = loadError("det_number", kHeader + "1000,none,abc,12,4,0,0,0,0,reference\n", &path);
  EXPECT_NE(e.find(path + ":2:"), std::string::npos) << e;
  EXPECT_NE(e.find("propagated_chi2"), std::string::npos) << e;

  e = loadError("det_columns", kHeader + "1000,none,1,12,4,0,0\n", &path);
  EXPECT_NE(e.find(path + ":2:"), std::string::npos) << e;
  EXPECT_NE(e.find("7 columns"), std::string::npos) << e;

  e = loadError("det_time", kHeader + "2000,none,1,12,4,0,0,0,0,reference\n1000,none,1,12,4,0,0,0,0,reference\n", &path);
  EXPECT_NE(e.find(path + ":3:"), std::string::npos) << e;
  EXPECT_NE(e.find("does not increase"), std::string::npos) << e;

  e = loadError("det_header", "timestamp_ns,propagated_chi2\n1000,1\n", &path);
  EXPECT_NE(e.find(path), std::string::npos) << e;
  EXPECT_NE(e.find("'state'"), std::string::npos) << e;

  e = loadError("det_count", kHeader + "1000,none,1,12,-4,0,0,0,0,reference\n", &path);
  EXPECT_NE(e.find("landmarks_tested"), std::string::npos) << e;

  const std::string hh = "timestamp_ns,state,interval_onset_ns,interval_end_ns\n";
  e = loadError("det_end", hh + "1000,none,900,800\n", &path);
  EXPECT_NE(e.find(path + ":2:"), std::string::npos) << e;
  EXPECT_NE(e.find("interval_end_ns"), std::string::npos) << e;
  e = loadError("det_onset", hh + "1000,none,-5,0\n", &path);
  EXPECT_NE(e.find("interval_onset_ns"), std::string::npos) << e;

  EXPECT_THROW(DetectorLog::load(test::freshDir("det_missing") + "/conflict.csv"), InputError);
  e = loadError("det_empty", "", &path);
  EXPECT_NE(e.find(path + ": is empty"), std::string::npos) << e;
}

}  // namespace
}  // namespace mcvio::evaluation
