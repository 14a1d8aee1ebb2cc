// BenchmarkSuite: option checks, the plan, target bookkeeping on constructed results, and one
// short simulated elevator run end to end (deterministic seed).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/time.hpp"
#include "mcvio/evaluation/benchmark_report_writer.hpp"
#include "mcvio/evaluation/benchmark_suite.hpp"
#include "mcvio/evaluation/mode_run_recorder.hpp"
#include "mcvio/sim/feature_simulator.hpp"

using namespace mcvio::evaluation;
namespace fs = std::filesystem;

namespace {

std::string invalidMessage(const BenchmarkOptions& o) {
  try {
    o.validate();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

BenchmarkRun makeRun(const std::string& mode, double ate, double rpe, double tpr, double fpr, double cpu) {
  BenchmarkRun r;
  r.mode = mode;
  r.ate_posyaw_m = ate;
  r.rpe_translation_m = rpe;
  r.tpr = tpr;
  r.fpr = fpr;
  r.cpu_mean_ms = cpu;
  return r;
}

}  // namespace

TEST(BenchmarkOptions, DefaultsAndQuickAreValid) {
  EXPECT_NO_THROW(BenchmarkOptions{}.validate());
  EXPECT_NO_THROW(BenchmarkOptions::quick().validate());
}

TEST(BenchmarkOptions, BadValuesNameTheOption) {
  BenchmarkOptions o;
  o.modes = {"imu", "auto"};
  EXPECT_NE(invalidMessage(o).find("modes: must include 'reference'"), std::string::npos) << invalidMessage(o);
  o = {};
  o.modes = {"reference", "fast"};
  EXPECT_NE(invalidMessage(o).find("modes"), std::string::npos) << invalidMessage(o);
  o = {};
  o.scenarios = {"none", "tornado"};
  EXPECT_NE(invalidMessage(o).find("scenarios"), std::string::npos) << invalidMessage(o);
  o = {};
  o.sweep_scenarios = {"pedestrian"};
  EXPECT_NE(invalidMessage(o).find("sweep_scenarios"), std::string::npos) << invalidMessage(o);
  o = {};
  o.conflict_duration_s = 50;
  EXPECT_NE(invalidMessage(o).find("conflict_duration_s"), std::string::npos) << invalidMessage(o);
  o = {};
  o.seeds = {1, 1};
  EXPECT_NE(invalidMessage(o).find("seeds"), std::string::npos) << invalidMessage(o);
  o = {};
  o.jobs = 0;
  EXPECT_NE(invalidMessage(o).find("jobs"), std::string::npos) << invalidMessage(o);
  EXPECT_THROW(BenchmarkSuite{o}, std::invalid_argument);
  o = {};
  o.estimator.conflict.horizon_frames = 0;
  EXPECT_NE(invalidMessage(o).find("estimator: "), std::string::npos) << invalidMessage(o);
  EXPECT_NE(invalidMessage(o).find("horizon_frames"), std::string::npos) << invalidMessage(o);
}

// `mcvio bench --config` at feature level: the estimator options reach every run.
TEST(BenchmarkSuite, EstimatorOptionsReachTheRuns) {
  BenchmarkOptions o = BenchmarkOptions::quick();
  o.scenarios = {"none"};
  o.modes = {"reference"};
  o.sequence_duration_s = 8.0;
  o.onset_s = 2.0;
  o.conflict_duration_s = 2.0;
  const auto tracked = [&o] { return BenchmarkSuite(o).run({}).sequences.at(0).runs.at(0).tracked_frames; };
  const std::size_t with_defaults = tracked();
  o.estimator.init_window_s = 4.0;  // the first pose waits for 4 s of IMU instead of 1 s
  const std::size_t with_late_start = tracked();
  EXPECT_GT(with_defaults, 8u * 20u - 2u * 20u);
  EXPECT_LE(with_late_start, with_defaults - 2u * 20u);
}

TEST(BenchmarkSuite, PlanHasEveryScenarioSeedAndTheSweep) {
  BenchmarkOptions o;
  o.seeds = {3, 4};
  o.sweep_durations_s = {0, 10, 40};
  const auto plan = BenchmarkSuite(o).plan();
  ASSERT_EQ(plan.size(), 6u * 2u + 2u * 3u);
  EXPECT_EQ(plan[0].name, "none_s3");
  EXPECT_FALSE(plan[0].hasConflict());
  EXPECT_EQ(plan[3].name, "elevator_s4");
  EXPECT_TRUE(plan[3].hasConflict());
  EXPECT_DOUBLE_EQ(plan[3].conflict_duration_s, 15.0);
  EXPECT_DOUBLE_EQ(plan[3].travel_m, 0.0);
  const auto& zero = plan[12];
  EXPECT_TRUE(zero.sweep);
  EXPECT_EQ(zero.name, "sweep_elevator_0s_s3");
  EXPECT_FALSE(zero.hasConflict());
  EXPECT_GT(zero.travel_m, 0.0);
  EXPECT_LT(zero.travel_m, 1e-3);
  const auto& longest = plan[17];
  EXPECT_EQ(longest.name, "sweep_vehicle_40s_s3");
  EXPECT_DOUBLE_EQ(longest.duration_s, 20.0 + 40.0 + 15.0);
  EXPECT_DOUBLE_EQ(longest.travel_m, 4.0 * 40.0);
}

TEST(BenchmarkSuite, TargetsCountPassesAndTheWorstRun) {
  BenchmarkResult result;
  result.options.modes = {"reference", "auto"};
  auto sequence = [](const std::string& scenario, double conflict_s) {
    BenchmarkSequenceResult sr;
    sr.sequence.scenario = scenario;
    sr.sequence.name = scenario + "_s1";
    sr.sequence.conflict_duration_s = conflict_s;
    sr.conflict_frames = conflict_s > 0 ? 100 : 0;
    return sr;
  };
  // Elevator: 90% less ATE, 50% less RPE, detection 0.97/0.01, 10% added CPU, ride 2% off, cabin 4%.
  auto elevator = sequence("elevator", 15);
  elevator.runs = {makeRun("reference", 10.0, 0.2, 0.5, 0.0, 10.0), makeRun("auto", 1.0, 0.1, 0.97, 0.01, 11.0)};
  for (auto& r : elevator.runs) {
    r.ate_reduction_percent = 100.0 * (10.0 - r.ate_posyaw_m) / 10.0;
    r.rpe_reduction_percent = 100.0 * (0.2 - r.rpe_translation_m) / 0.2;
    r.added_cost_percent = 100.0 * (r.cpu_mean_ms - 10.0) / 10.0;
  }
  elevator.runs[1].ride_error_percent = 2.0;
  elevator.runs[1].secondary_error_percent = 4.0;
  // Vehicle: only 50% less ATE and TPR 0.9.
  auto vehicle = sequence("vehicle", 15);
  vehicle.runs = {makeRun("reference", 2.0, 0.2, 0.5, 0.0, 10.0), makeRun("auto", 1.0, 0.1, 0.9, 0.0, 10.0)};
  vehicle.runs[1].ate_reduction_percent = 50.0;
  vehicle.runs[1].rpe_reduction_percent = 50.0;
  vehicle.runs[1].added_cost_percent = 0.0;
  vehicle.runs[1].secondary_travel_error_percent = 12.0;  // the vehicle's own motion 12 % off
  // Clean: 3% more ATE, FPR 0.05.
  auto clean = sequence("none", 0);
  clean.runs = {makeRun("reference", 1.0, 0.1, NAN, 0.0, 10.0), makeRun("auto", 1.03, 0.1, NAN, 0.05, 10.0)};
  clean.runs[1].ate_reduction_percent = -3.0;
  clean.runs[1].added_cost_percent = 0.0;
  result.sequences = {elevator, vehicle, clean};

  BenchmarkSuite::applyTargets(result);
  const auto& e = result.sequences[0].runs[1].checks;
  EXPECT_TRUE(e.ate_reduction.value_or(false));
  EXPECT_TRUE(e.rpe_reduction.value_or(false));
  EXPECT_FALSE(e.clean_ate.has_value());
  EXPECT_TRUE(e.detection.value_or(false));
  EXPECT_TRUE(e.ride_displacement.value_or(false));
  EXPECT_TRUE(e.secondary_motion.value_or(false));
  EXPECT_TRUE(e.cost.value_or(false));
  EXPECT_TRUE(e.allPass());
  const auto& v = result.sequences[1].runs[1].checks;
  EXPECT_FALSE(v.ate_reduction.value_or(true));
  EXPECT_FALSE(v.detection.value_or(true));
  EXPECT_FALSE(v.ride_displacement.has_value());
  EXPECT_FALSE(v.secondary_motion.has_value());
  EXPECT_FALSE(v.vehicle_motion.value_or(true));
  EXPECT_FALSE(e.vehicle_motion.has_value());
  EXPECT_FALSE(v.allPass());
  const auto& c = result.sequences[2].runs[1].checks;
  EXPECT_TRUE(c.clean_ate.value_or(false));
  EXPECT_FALSE(c.detection.value_or(true));  // FPR 0.05 > 0.02
  EXPECT_FALSE(c.ate_reduction.has_value());
  EXPECT_FALSE(result.sequences[0].runs[0].checks.ate_reduction.has_value());  // reference is the baseline

  auto summary = [&](const std::string& prefix) -> const BenchmarkTargetSummary& {
    for (const auto& t : result.targets)
      if (t.target.rfind(prefix, 0) == 0) return t;
    throw std::runtime_error("no target " + prefix);
  };
  const auto& ate = summary("conflict ATE reduction");
  EXPECT_EQ(ate.mode, "auto");
  EXPECT_EQ(ate.passed, 1u);
  EXPECT_EQ(ate.total, 2u);
  EXPECT_FALSE(ate.pass());
  EXPECT_DOUBLE_EQ(ate.worst, 50.0);
  EXPECT_EQ(ate.worst_sequence, "vehicle_s1");
  const auto& fpr = summary("detection FPR");
  EXPECT_EQ(fpr.total, 3u);
  EXPECT_EQ(fpr.passed, 2u);
  EXPECT_DOUBLE_EQ(fpr.worst, 0.05);
  const auto& clean_target = summary("clean ATE");
  EXPECT_TRUE(clean_target.pass());
  EXPECT_NEAR(clean_target.worst, 3.0, 1e-12);
  EXPECT_TRUE(summary("added backend CPU").pass());
  EXPECT_DOUBLE_EQ(summary("added backend CPU").worst, 10.0);
  const auto& cabin = summary("elevator cabin (secondary) motion");
  EXPECT_EQ(cabin.total, 1u);
  EXPECT_TRUE(cabin.pass());
  EXPECT_DOUBLE_EQ(cabin.worst, 4.0);
  const auto& travel = summary("vehicle (secondary) motion");
  EXPECT_EQ(travel.total, 1u);
  EXPECT_FALSE(travel.pass());
  EXPECT_DOUBLE_EQ(travel.worst, 12.0);
}

// The vehicle's own motion: the secondary frame's translation, in the estimator's world, which
// differs from the ground truth's by a yaw of 40 degrees and an offset, against the body's travel.
TEST(BenchmarkSuite, VehicleTravelOfTheSecondaryFrameInTheGroundTruthsFrame) {
  using mcvio::fromSeconds;
  BenchmarkSequence sequence;
  sequence.scenario = "vehicle";
  sequence.name = "vehicle_s1";
  sequence.conflict_duration_s = 4.0;
  const Eigen::AngleAxisd yaw(40.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ());
  const Eigen::Vector3d offset(3.0, -2.0, 0.5);
  std::vector<StampedPose> truth, estimate, secondary;
  std::vector<mcvio::dataset::ConflictLabel> labels;
  for (int k = 0; k <= 120; ++k) {  // 6 s at 20 Hz, the vehicle moving 1-5 s along x, 4 m/s
    const double t = 0.05 * k;
    const double travel = 4.0 * std::clamp(t - 1.0, 0.0, 4.0);
    StampedPose g;
    g.t = fromSeconds(t);
    g.p = Eigen::Vector3d(travel, 0.1 * std::sin(t), 1.0);
    truth.push_back(g);
    StampedPose est = g;
    est.p = yaw.inverse() * (g.p - offset);  // the estimator's world
    est.q = Eigen::Quaterniond(yaw.inverse());
    estimate.push_back(est);
    const bool moving = t >= 1.0 && t <= 5.0;
    labels.push_back({g.t, moving, moving ? "vehicle" : "none", moving ? 0.7 : 0.0});
    if (t >= 1.4 && t <= 5.0) {  // tracked from the detection, 5 % short
      StampedPose sp;
      sp.t = g.t;
      sp.p = yaw.inverse() * Eigen::Vector3d(0.95 * (travel - 1.6), 0.0, 0.0);
      secondary.push_back(sp);
    }
  }
  std::vector<BenchmarkModeRun> runs(2);
  runs[0].mode = "reference";
  runs[1].mode = "auto";
  for (auto& r : runs) {
    r.estimate = Trajectory(estimate, r.mode);
    r.frames = estimate.size();
  }
  runs[1].secondary = Trajectory(secondary, "secondary");
  BenchmarkOptions options;
  options.modes = {"reference", "auto"};
  const auto sr = BenchmarkSuite::evaluateSequence(sequence, Trajectory(truth, "truth"), ConflictLabelTimeline(labels, "labels"),
                                                   runs, options);
  ASSERT_EQ(sr.runs.size(), 2u);
  EXPECT_FALSE(std::isfinite(sr.runs[0].secondary_travel_error_percent));  // no secondary frame
  const BenchmarkRun& a = sr.runs[1];
  EXPECT_NEAR(a.travel_truth_m, 16.0, 0.15);  // plus the body's own sway
  // The secondary frame started 0.4 s (1.6 m) in and came out 5 % short: 0.95 * 14.4 m.
  EXPECT_NEAR(a.secondary_travel_m, 0.95 * 14.4, 1e-6);
  EXPECT_NEAR(a.secondary_travel_error_percent, 100.0 * (16.0 - 0.95 * 14.4) / 16.0, 0.5);
  const std::string md = BenchmarkReportWriter::toMarkdown([&] {
    BenchmarkResult result;
    result.options = options;
    result.sequences = {sr};
    BenchmarkSuite::applyTargets(result);
    return result;
  }());
  EXPECT_NE(md.find("## Vehicle travel"), std::string::npos);
  EXPECT_NE(md.find("vehicle FAIL"), std::string::npos);  // 14.5 % > 10 %
}

// The suite steps every mode's estimator frame by frame in turn (so their CPU per frame sees the
// same host load). That must not change what any of them estimates: no state is shared.
TEST(ModeRunRecorder, ModesSteppedInTurnEstimateWhatEachDoesAlone) {
  mcvio::sim::SimulatorOptions so;
  so.duration_s = 18.0;
  so.scenario.kind = mcvio::sim::ScenarioKind::kElevator;
  so.scenario.onset_s = 8.0;
  so.scenario.duration_s = 6.0;
  const mcvio::sim::FeatureSimulatorOptions fo;
  const auto seq = mcvio::sim::simulateFeatureSequence(so, fo);
  const mcvio::estimator::EstimatorOptions eo;
  const double sigma = fo.pixel_noise_sigma;
  const std::vector<std::string> modes = {"reference", "imu"};
  std::vector<BenchmarkModeRun> alone;
  for (const auto& mode : modes) {
    ModeRunRecorder r(seq, mode, eo, sigma);
    for (std::size_t i = 0; i < seq.frames.size(); ++i) r.addFrame(i);
    alone.push_back(r.finish());
  }
  const std::vector<BenchmarkModeRun> in_turn = ModeRunRecorder::runInTurn(seq, modes, eo, sigma);
  ASSERT_EQ(in_turn.size(), modes.size());
  for (std::size_t m = 0; m < modes.size(); ++m) {
    SCOPED_TRACE(modes[m]);
    EXPECT_EQ(in_turn[m].mode, modes[m]);
    EXPECT_EQ(in_turn[m].frames, seq.frames.size());
    ASSERT_GT(alone[m].estimate.size(), seq.frames.size() / 2);
    ASSERT_EQ(in_turn[m].estimate.size(), alone[m].estimate.size());
    for (std::size_t i = 0; i < alone[m].estimate.size(); ++i) {
      ASSERT_EQ(in_turn[m].estimate[i].t, alone[m].estimate[i].t);
      ASSERT_EQ(in_turn[m].estimate[i].p, alone[m].estimate[i].p) << "pose " << i;
    }
    ASSERT_EQ(in_turn[m].detector.size(), alone[m].detector.size());
    for (std::size_t i = 0; i < alone[m].detector.size(); ++i)
      ASSERT_EQ(in_turn[m].detector[i].state, alone[m].detector[i].state) << "frame " << i;
    EXPECT_EQ(in_turn[m].cpu_ms.size(), alone[m].cpu_ms.size());
    EXPECT_GT(in_turn[m].wall_s, 0.0);
  }
  // The two modes differ on this ride: a mix-up between the recorders would show.
  EXPECT_NE(alone[0].estimate.poses().back().p, alone[1].estimate.poses().back().p);
  EXPECT_THROW(ModeRunRecorder(seq, "fast", eo, sigma), mcvio::InputError);
}

TEST(BenchmarkSuite, ShortElevatorRunEndToEnd) {
  BenchmarkOptions o = BenchmarkOptions::quick();
  o.scenarios = {"elevator"};
  o.modes = {"reference", "imu"};
  o.sequence_duration_s = 22.0;
  o.onset_s = 8.0;
  o.conflict_duration_s = 8.0;
  o.sweep_durations_s = {0};
  o.sweep_scenarios = {"vehicle"};
  o.sweep_tail_s = 4.0;
  o.jobs = 2;
  std::size_t calls = 0, last_total = 0;
  const BenchmarkResult result = BenchmarkSuite(o).run([&](std::size_t done, std::size_t total, const std::string& line) {
    ++calls;
    last_total = total;
    EXPECT_LE(done, total);
    EXPECT_FALSE(line.empty());
  });
  EXPECT_EQ(calls, 4u);
  EXPECT_EQ(last_total, 4u);
  ASSERT_EQ(result.sequences.size(), 2u);
  const auto& sr = result.sequences[0];
  EXPECT_EQ(sr.sequence.name, "elevator_s1");
  EXPECT_EQ(sr.frames, std::size_t(22.0 * 20.0) + 1);  // both ends
  EXPECT_GT(sr.conflict_frames, 100u);
  ASSERT_EQ(sr.runs.size(), 2u);
  for (const auto& r : sr.runs) {
    SCOPED_TRACE(r.mode);
    EXPECT_GT(r.tracked_frames, sr.frames / 2);
    EXPECT_TRUE(std::isfinite(r.ate_posyaw_m));
    EXPECT_TRUE(std::isfinite(r.ate_se3_m));
    EXPECT_TRUE(std::isfinite(r.ate_posyaw_in_conflict_m));
    EXPECT_TRUE(std::isfinite(r.rpe_translation_m));
    EXPECT_EQ(r.tp + r.fp + r.tn + r.fn, r.tracked_frames);
    EXPECT_GT(r.cpu_median_ms, 0.0);
    // The elevator's 12 m ride falls inside the labelled interval.
    EXPECT_GT(r.ride_truth_dz_m, 10.0);
    EXPECT_TRUE(std::isfinite(r.ride_estimate_dz_m));
  }
  EXPECT_DOUBLE_EQ(sr.runs[0].ate_reduction_percent, 0.0);
  // The plain VIO revises nothing: its per-frame output is its trajectory. The IMU-dominated
  // interval is revised once it ends, so what the run published frame by frame was further off.
  EXPECT_DOUBLE_EQ(sr.runs[0].ate_posyaw_online_m, sr.runs[0].ate_posyaw_m);
  EXPECT_GT(sr.runs[1].ate_posyaw_online_m, sr.runs[1].ate_posyaw_m);
  EXPECT_TRUE(std::isfinite(sr.runs[1].ate_reduction_percent));
  EXPECT_TRUE(sr.runs[1].checks.ate_reduction.has_value());
  EXPECT_TRUE(sr.runs[1].checks.ride_displacement.has_value());
  // The zero-length sweep point has no conflict labels.
  EXPECT_TRUE(result.sequences[1].sequence.sweep);
  EXPECT_EQ(result.sequences[1].conflict_frames, 0u);

  const fs::path dir = fs::temp_directory_path() / "mcvio_benchmark_suite_test";
  fs::remove_all(dir);
  const auto files = BenchmarkReportWriter::write(result, dir.string());
  for (const char* name : {"bench.json", "bench.md", "ate_by_scenario.png", "rpe_by_scenario.png", "ate_vs_duration_vehicle.png"})
    EXPECT_TRUE(fs::is_regular_file(dir / name) && fs::file_size(dir / name) > 100) << name;
  std::ifstream jf(dir / "bench.json");
  const auto j = nlohmann::json::parse(jf);
  ASSERT_EQ(j["sequences"].size(), 2u);
  EXPECT_DOUBLE_EQ(j["sequences"][0]["runs"][1]["ate_posyaw_rmse_m"].get<double>(), sr.runs[1].ate_posyaw_m);
  EXPECT_DOUBLE_EQ(j["sequences"][0]["runs"][1]["ate_posyaw_online_rmse_m"].get<double>(), sr.runs[1].ate_posyaw_online_m);
  EXPECT_EQ(j["sequences"][0]["runs"][1]["checks"]["all_pass"].get<bool>(), sr.runs[1].checks.allPass());
  const std::string md = BenchmarkReportWriter::toMarkdown(result);
  EXPECT_NE(md.find("| elevator_s1 | imu |"), std::string::npos);
  EXPECT_NE(md.find("## Elevator ride"), std::string::npos);
  // Detection timing: every mode of the conflict sequence, none of the sweep's.
  const auto timing_at = md.find("## Detection timing");
  ASSERT_NE(timing_at, std::string::npos);
  EXPECT_NE(md.find("| elevator_s1 | reference | ", timing_at), std::string::npos);
  EXPECT_NE(md.find("| elevator_s1 | imu | ", timing_at), std::string::npos);
  const std::string timing = md.substr(timing_at, md.find("\n## ", timing_at + 1) - timing_at);
  std::size_t rows = 0;
  for (auto at = timing.find("\n| "); at != std::string::npos; at = timing.find("\n| ", at + 1)) ++rows;
  EXPECT_EQ(rows, 3u) << timing;  // the header and the two modes of elevator_s1; the sweep has no conflict
  // The imu run's detector: its onset delay is within the interval when it detected at all.
  const auto& det = j["sequences"][0]["runs"][1]["detection"];
  if (sr.runs[1].tp > 0) {
    EXPECT_GE(det["onset_delay_s"].get<double>(), 0.0);
    EXPECT_LT(det["onset_delay_s"].get<double>(), o.conflict_duration_s);
    EXPECT_DOUBLE_EQ(det["release_lag_s"].get<double>(), sr.runs[1].release_lag_s);
  } else {
    EXPECT_TRUE(det["onset_delay_s"].is_null());
  }
  EXPECT_NE(md.find("| vehicle | 0 |"), std::string::npos);
  EXPECT_EQ(md.find("## Clean floor"), std::string::npos) << "no floor was measured";
  // A clean floor at half the reference's error: at most 50 % reduction is reachable.
  BenchmarkResult with_floor = result;
  with_floor.sequences[0].clean_floor_ate_m = 0.5 * sr.runs[0].ate_posyaw_m;
  const std::string md_floor = BenchmarkReportWriter::toMarkdown(with_floor);
  const auto floor_at = md_floor.find("## Clean floor");
  ASSERT_NE(floor_at, std::string::npos);
  EXPECT_NE(md_floor.find(" | 50.0 | imu | ", floor_at), std::string::npos) << md_floor.substr(floor_at);
  EXPECT_DOUBLE_EQ(nlohmann::json::parse(BenchmarkReportWriter::toJson(with_floor))["sequences"][0]["clean_floor_ate_posyaw_m"].get<double>(),
                   with_floor.sequences[0].clean_floor_ate_m);
  // An image-level report says which rig and texture filter rendered it; a feature-level one does not.
  EXPECT_FALSE(nlohmann::json::parse(BenchmarkReportWriter::toJson(result))["options"].contains("texture_filter"));
  BenchmarkResult rendered = result;
  rendered.level = "images";
  rendered.render_rig = "/data/fisheye_rig";
  rendered.texture_filter = "anisotropic";
  const auto rj = nlohmann::json::parse(BenchmarkReportWriter::toJson(rendered));
  EXPECT_EQ(rj["options"]["render_rig"], "/data/fisheye_rig");
  EXPECT_EQ(rj["options"]["texture_filter"], "anisotropic");
  EXPECT_NE(BenchmarkReportWriter::toMarkdown(rendered).find("Rendered with the rig of `/data/fisheye_rig`, anisotropic texture filter."),
            std::string::npos);
  fs::remove_all(dir);
}
