// Accuracy of the whole offline pipeline (real frontend on rendered images + estimator) on clean
// 60 s sequences: the synthetic office (`none`) and semi-real V1_01 (rendered along the real
// ground truth, real IMU), with the shipped config/vio_pipeline.yaml. Each test renders its frames
// while the run consumes them (no files), so the decoding stage is the renderer.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <unistd.h>

#include "clean_sequences.hpp"
#include "rendered_frame_cache.hpp"
#include "mcvio/dataset/euroc_writer.hpp"
#include "mcvio/pipeline/offline_run.hpp"
#include "mcvio/sim/euroc_rig_defaults.hpp"
#include "mcvio/sim/simulator.hpp"
#include "run_accuracy.hpp"

using namespace mcvio;
using pipeline::sequences::CovarianceLog;
using pipeline::sequences::RenderedFrameCache;

namespace {

// The bound for 60 s clean sequences, after position + yaw alignment.
constexpr double kMaxAteM = 0.05;

// A clean sequence may show a motion conflict in at most this share of its frames (issue 6).
constexpr double kMaxConflictFraction = 0.02;

pipeline::sequences::RunAccuracy runAndEvaluate(RenderedFrameCache& frames, const std::string& name,
                                                pipeline::OfflineRunSummary* summary, std::size_t* conflict_frames,
                                                const std::string& mode = "",
                                                const std::string& config_file = MCVIO_PIPELINE_CONFIG,
                                                Timestamp* first_conflict = nullptr) {
  const std::string out = ::testing::TempDir() + "/accuracy_" + name + "_" + std::to_string(getpid());
  pipeline::OfflineRunOptions o;
  o.dataset_dir = name;
  o.output_dir = out;
  o.progress = false;
  o.config_file = config_file;  // by default the shipped, measured configuration
  o.mode = mode;
  CovarianceLog covariances;
  *conflict_frames = 0;
  o.on_frame = [&](std::size_t, const pipeline::VioFrameResult& r) {
    covariances.add(r);
    if (!r.estimated || r.estimate.conflict.state != estimator::ConflictReport::State::kConflict) return;
    ++*conflict_frames;
    if (first_conflict != nullptr && *first_conflict == 0) *first_conflict = r.estimate.t;
  };
  if (first_conflict != nullptr) *first_conflict = 0;
  *summary = pipeline::runOffline(frames.input(), o);
  const auto a =
      pipeline::sequences::evaluateRun(out + "/trajectory.tum", frames.simulator().groundTruth(), covariances);
  std::cout << name << ": " << summary->frames << " frames, " << a.poses << " poses, " << summary->resets
            << " resets, ATE pos+yaw " << a.ate_pos_yaw_rmse << " m (max " << a.ate_pos_yaw_max << "), ATE SE3 "
            << a.ate_se3_rmse << " m, RPE 1 s " << a.rpe_1s_translation_rmse << " m / " << a.rpe_1s_rotation_rmse_deg
            << " deg, position NEES " << a.position_nees << " (whole-run aligned " << a.position_nees_whole_run_alignment << ") over " << a.nees_frames << " frames, motion conflict in "
            << *conflict_frames << " frames\n";
  ::testing::Test::RecordProperty("ate_pos_yaw_m", std::to_string(a.ate_pos_yaw_rmse));
  ::testing::Test::RecordProperty("position_nees", std::to_string(a.position_nees));
  std::filesystem::remove_all(out);
  return a;
}

/// What every clean 60 s run must show: at most kMaxConflictFraction of its frames in conflict,
/// every frame consumed without a reset, every frame tracked once initialised (which waits for
/// 1 s of IMU), ATE within kMaxAteM and a position NEES inside (1, max_nees).
void expectCleanRun(const sim::Simulator& simulator, const pipeline::OfflineRunSummary& s,
                    const pipeline::sequences::RunAccuracy& a, std::size_t conflict_frames, double max_nees) {
  EXPECT_LE(static_cast<double>(conflict_frames), kMaxConflictFraction * static_cast<double>(s.frames));
  EXPECT_EQ(s.frames, simulator.frameTimes().size());
  EXPECT_EQ(s.resets, 0u);
  EXPECT_EQ(s.skipped, 0u);
  EXPECT_GE(a.poses + 25, s.frames);
  EXPECT_LE(a.ate_pos_yaw_rmse, kMaxAteM);
  EXPECT_GE(a.nees_frames + 25, s.frames);
  EXPECT_GT(a.position_nees, 1.0);
  EXPECT_LT(a.position_nees, max_nees);
}

/// The shipped configuration with `from` replaced by `to` (the first occurrence, or every one with
/// `everywhere`), written to a temporary file whose path is returned; empty (and a test failure)
/// if `from` is not in it.
std::string shippedConfigWith(const std::string& from, const std::string& to, const std::string& name,
                              bool everywhere = false) {
  std::ifstream shipped(MCVIO_PIPELINE_CONFIG);
  EXPECT_TRUE(shipped.good()) << MCVIO_PIPELINE_CONFIG;
  std::stringstream text;
  text << shipped.rdbuf();
  std::string yaml = text.str();
  const auto at = yaml.find(from);
  EXPECT_NE(at, std::string::npos) << MCVIO_PIPELINE_CONFIG << " has no '" << from << "'";
  if (at == std::string::npos) return {};
  yaml.replace(at, from.size(), to);
  for (auto next = yaml.find(from, at + to.size()); everywhere && next != std::string::npos;
       next = yaml.find(from, next + to.size()))
    yaml.replace(next, from.size(), to);
  const std::string path = ::testing::TempDir() + "/" + name + "_" + std::to_string(getpid()) + ".yaml";
  std::ofstream(path) << yaml;
  return path;
}

/// The rendered office with a conflict: `mcvio sim --scenario KIND --seed SEED --duration
/// DURATION --onset ONSET --scenario-duration LENGTH`.
sim::SimulatorOptions renderedScenario(sim::ScenarioKind kind, std::uint64_t seed, double duration_s, double onset_s,
                                       double length_s) {
  sim::SimulatorOptions so;
  so.seed = seed;
  so.duration_s = duration_s;
  so.overwrite = true;
  so.scenario.kind = kind;
  so.scenario.onset_s = onset_s;
  so.scenario.duration_s = length_s;
  return so;
}

/// One sequence run with the shipped configuration and with a variant of it (`from` replaced by
/// `to`, see shippedConfigWith): the pair an option's test compares.
struct ShippedAndVariant {
  bool ran = false;  ///< false: the shipped configuration has no `from`
  pipeline::sequences::RunAccuracy shipped, variant;
  pipeline::OfflineRunSummary shipped_summary, variant_summary;
  std::size_t shipped_conflict_frames = 0, variant_conflict_frames = 0;
  Timestamp shipped_first_conflict = 0, variant_first_conflict = 0;  ///< 0: no conflict frame
};

ShippedAndVariant runShippedAndVariant(RenderedFrameCache& frames, const std::string& name,
                                       const std::string& from, const std::string& to, const std::string& mode) {
  ShippedAndVariant r;
  const std::string variant = shippedConfigWith(from, to, name + "_variant");
  if (variant.empty()) return r;
  r.variant = runAndEvaluate(frames, name + "_variant", &r.variant_summary, &r.variant_conflict_frames, mode, variant,
                             &r.variant_first_conflict);
  r.shipped = runAndEvaluate(frames, name + "_shipped", &r.shipped_summary, &r.shipped_conflict_frames, mode,
                             MCVIO_PIPELINE_CONFIG, &r.shipped_first_conflict);
  std::filesystem::remove(variant);
  // Both runs drew on one rendering of every pair.
  EXPECT_EQ(frames.rendered(), frames.simulator().frameTimes().size());
  r.ran = true;
  return r;
}

}  // namespace

TEST(OfflineAccuracy, RenderedOffice60sNoneScenario) {
  const sim::Simulator simulator(pipeline::sequences::renderedNone(60.0, 1));
  RenderedFrameCache frames(simulator);
  pipeline::OfflineRunSummary s;
  std::size_t conflict_frames = 0;
  const auto a = runAndEvaluate(frames, "rendered_none_60s", &s, &conflict_frames);
  // Consistent covariance (position NEES in the estimator's gauge, expectation 3): measured 3.72 with
  // the shipped IMU noise x3 and 0.4 px feature noise (1.20 at x6; 0.30 with x6 and 1 px); 1.30
  // since the still-tracked landmarks' history goes into the prior (ATE 0.0115 m).
  expectCleanRun(simulator, s, a, conflict_frames, 6.0);
}

// A 140-degree double-sphere rig (Kalibr's ds, as Basalt calibrates wide lenses; EuRoC's
// pinhole sees 77 degrees across) on the rendered office: the renderer and the frontend go
// through the lens model, and the run must be as good as any clean run. Judged in the lens's own
// pixels (pixel_scale wide_angle, the 2x2 pixel Jacobian at each feature) its motion over a second
// is three times tighter than with the centre's scale for every feature, and its drift no worse
// (measured 2026-12-03: ATE pos+yaw 0.0071 -> 0.0066 m, RPE 1 s 0.0056 -> 0.0018 m, position NEES
// 4.41 -> 1.69; with an isotropic local scale 0.0040 m, 0.0015 m, 1.07: over 18 rendered seeds
// the two drift alike, see src/mcvio_estimator/README.md).
TEST(OfflineAccuracy, ARenderedDoubleSphereRigTracksTheOffice) {
  StereoRigCalibration rig = sim::eurocRigDefaults();
  for (int i = 0; i < 2; ++i) {
    CameraModel& m = rig.camera(i).model;
    m = CameraModel(m.width(), m.height(), {260.0, 259.5, m.cu(), m.cv()}, DistortionModel::kDoubleSphere,
                    {-0.2, 0.6, 0.0, 0.0});
  }
  const std::string dir = ::testing::TempDir() + "/double_sphere_rig_" + std::to_string(getpid());
  std::filesystem::remove_all(dir);
  dataset::EurocWriter(dir, rig).close();
  sim::SimulatorOptions so = pipeline::sequences::renderedNone(30.0, 1);
  so.calibration_dir = dir;
  const sim::Simulator simulator(so);
  std::filesystem::remove_all(dir);
  ASSERT_EQ(simulator.calibration().cam0.model.distortionModel(), DistortionModel::kDoubleSphere);
  ASSERT_EQ(simulator.calibration().cam1.model.distortionCoefficients(), Eigen::Vector4d(-0.2, 0.6, 0.0, 0.0));
  RenderedFrameCache frames(simulator);
  pipeline::OfflineRunSummary s;
  std::size_t conflict_frames = 0;
  const auto a = runAndEvaluate(frames, "double_sphere_30s", &s, &conflict_frames);
  expectCleanRun(simulator, s, a, conflict_frames, 6.0);
  const std::string centre = shippedConfigWith("pixel_scale: wide_angle", "pixel_scale: centre", "double_sphere_centre", true);
  ASSERT_FALSE(centre.empty());
  pipeline::OfflineRunSummary centre_summary;
  std::size_t centre_conflict_frames = 0;
  const auto c = runAndEvaluate(frames, "double_sphere_30s_centre", &centre_summary, &centre_conflict_frames, "", centre);
  std::filesystem::remove(centre);
  EXPECT_LT(a.ate_pos_yaw_rmse, c.ate_pos_yaw_rmse);
  EXPECT_LT(a.rpe_1s_translation_rmse, 0.5 * c.rpe_1s_translation_rmse);
}

TEST(OfflineAccuracy, SemiRealV101First60s) {
  const auto excerpt = pipeline::sequences::realExcerptDir();
  if (excerpt.empty()) GTEST_SKIP() << "no $MCVIO_SHARED_DIR/data/euroc_V1_01_excerpt";
  const std::string work = ::testing::TempDir() + "/semi_real_csv_" + std::to_string(getpid());
  const sim::Simulator simulator(pipeline::sequences::semiRealV101(excerpt, work, 60.0));
  RenderedFrameCache frames(simulator);
  std::filesystem::remove_all(work);
  pipeline::OfflineRunSummary s;
  std::size_t conflict_frames = 0;
  const auto a = runAndEvaluate(frames, "semi_real_v101_60s", &s, &conflict_frames);
  // The real IMU's takeoff once froze a still-moving bias estimate into the detector's reference
  // and kept a false conflict open for 90 % of the run (the conflict-frame bound below).
  // Consistent with the real IMU: position NEES near its expectation 3 (measured 2.03 with the IMU
  // noise x3, 1.49 at x6; 7.77 since the still-tracked landmarks' history goes into the prior, ATE
  // 0.0139 m). After the whole-run alignment instead it is 29 (36): the alignment shifts the
  // start, where the covariance is mm.
  expectCleanRun(simulator, s, a, conflict_frames, 10.0);
}

// A slow object (`mcvio sim --scenario slow_object --duration 30 --onset 10 --scenario-duration 12
// --seed 3`) fills 44 % of the view when its interval opens, and vision as a whole, pulled by it,
// fails the propagated-state test on a frame where the region split has found its group. Auto
// took that for a whole-view conflict and went IMU-dominated for 5.7 s (ATE 0.133 m against the
// reference's 0.395 m); a group found by the split beside a side that agrees with the IMU now
// makes the conflict partial: 0.053 m (IMU noise x6; 0.055 against 0.334 m at x3, shipped since
// 1015e6c; 0.039 m since vision's motion weighs its points by their depth uncertainty, 5432f6a).
TEST(OfflineAccuracy, RenderedSlowObjectFoundByTheRegionSplitStaysSelective) {
  const sim::Simulator simulator(renderedScenario(sim::ScenarioKind::kSlowObject, 3, 30.0, 10.0, 12.0));
  RenderedFrameCache frames(simulator);
  pipeline::OfflineRunSummary s_ref, s_auto;
  std::size_t conflict_ref = 0, conflict_auto = 0;
  const auto ref = runAndEvaluate(frames, "rendered_slow_object_ref", &s_ref, &conflict_ref, "reference");
  const auto aut = runAndEvaluate(frames, "rendered_slow_object_auto", &s_auto, &conflict_auto, "auto");
  EXPECT_EQ(s_auto.resets, 0u);
  EXPECT_GT(ref.ate_pos_yaw_rmse, 0.2);
  EXPECT_LT(aut.ate_pos_yaw_rmse, 0.2 * ref.ate_pos_yaw_rmse);
  EXPECT_GT(conflict_auto, 100u);  // 197 labelled frames
}

// A carried object covering the whole view for 4 s (`mcvio sim --scenario self_occlusion
// --duration 32 --onset 24 --scenario-duration 4 --coverage 1.0 --seed 1`): auto goes
// IMU-dominated, and the KLT frontend gives every corner it finds again a new track id. The
// conflict window registers the window's landmarks against the map remembered before the interval
// by position, and the end position they give takes out the drift of 4 s on the IMU alone
// (measured: ATE 0.0387 m without the registration, 0.0141 m with it; 0.0372 / 0.0145 m before the
// shipped config dropped an outlier's landmark).
TEST(OfflineAccuracy, RenderedFullOcclusionFindsTheMapAgainByPosition) {
  sim::SimulatorOptions so = renderedScenario(sim::ScenarioKind::kSelfOcclusion, 1, 32.0, 24.0, 4.0);
  so.scenario.coverage = 1.0;
  const sim::Simulator simulator(so);
  RenderedFrameCache frames(simulator);
  // The variant: the registration off.
  const std::string section = "\n  conflict:\n";
  const auto r = runShippedAndVariant(frames, "rendered_full_occlusion", section,
                                      section + "    smoothing_registration_radius_m: 0\n", "auto");
  ASSERT_TRUE(r.ran);
  EXPECT_EQ(r.shipped_summary.resets, 0u);
  EXPECT_GT(r.shipped_conflict_frames, 60u);  // 80 labelled frames
  EXPECT_LT(r.shipped.ate_pos_yaw_rmse, 0.025);
  EXPECT_LT(r.shipped.ate_pos_yaw_rmse, 0.6 * r.variant.ate_pos_yaw_rmse);
}

// With a keyframe on nearly every frame (the rendered office seen from close by) the keyframe
// window spans half a second. Dropping the older observations of the landmarks still tracked
// left the window to forget the rest; `marginalize_tracked_landmark_history` keeps them in the
// prior (measured on this sequence: ATE 0.012 -> 0.006 m; the image-level bench's clean runs of
// seeds 1, 8 and 9 0.012 / 0.022 / 0.017 -> 0.006 / 0.008 / 0.005 m).
TEST(OfflineAccuracy, TrackedLandmarkHistoryInThePriorHalvesTheCleanError) {
  const sim::Simulator simulator(pipeline::sequences::renderedNone(30.0, 1));
  RenderedFrameCache frames(simulator);
  const auto r = runShippedAndVariant(frames, "rendered_none_history", "marginalize_tracked_landmark_history: true",
                                      "marginalize_tracked_landmark_history: false", "");
  ASSERT_TRUE(r.ran);
  EXPECT_EQ(r.shipped_summary.resets, 0u);
  EXPECT_LT(r.shipped.ate_pos_yaw_rmse, 0.7 * r.variant.ate_pos_yaw_rmse);
}

// A pedestrian (`mcvio sim --scenario pedestrian --duration 30 --onset 10 --scenario-duration 12
// --seed 8`) is found 3.9 s into its walk, when three of its tracks are eliminated. With Ceres'
// tolerance tightened from 1e-3 to 1e-4 inside conflicts the solve on that frame moved the whole
// window 21 mm, to a minimum the looser solves before it had not reached (ATE 0.0187 m; the same
// tolerance in and out: 0.0087 m, its clean run 0.0082 m). Since the shipped config drops an
// outlier's landmark: 0.0160 against 0.0081 m.
TEST(OfflineAccuracy, APedestrianFoundLateDoesNotMoveTheWindowWhenItsTracksGo) {
  const sim::Simulator simulator(renderedScenario(sim::ScenarioKind::kPedestrian, 8, 30.0, 10.0, 12.0));
  RenderedFrameCache frames(simulator);
  // The variant: the tighter tolerance inside conflicts.
  const auto r = runShippedAndVariant(frames, "rendered_pedestrian_tolerance", "conflict_function_tolerance: 1.0e-3",
                                      "conflict_function_tolerance: 1.0e-4", "auto");
  ASSERT_TRUE(r.ran);
  EXPECT_EQ(r.shipped_summary.resets, 0u);
  EXPECT_GT(r.shipped_conflict_frames, 50u);  // 216 labelled frames, found after 3.9 s
  EXPECT_LT(r.shipped.ate_pos_yaw_rmse, 0.012);
  EXPECT_LT(r.shipped.ate_pos_yaw_rmse, 0.6 * r.variant.ate_pos_yaw_rmse);
}

// A laptop covering three quarters of the tracks for 12 s (`mcvio sim --scenario self_occlusion
// --duration 30 --onset 10 --scenario-duration 12 --seed 9`): only the frontend's labels find it,
// and they eliminate its tracks at once. The few static landmarks left keep their history going
// into the prior (frontend_conflict_keeps_history); paused, as for a conflict the backend's own
// tests find, the thin window floats (measured: auto 0.0090 m, paused 0.0118 m, the plain VIO
// 0.0154 m, the clean run of this seed 0.0048 m; before the shipped probation_agreeing_tests
// (2), 0.0083 / 0.0123 / 0.0154 m; before the shipped moving_track_budget_share left the world
// more tracks, 0.0077 / 0.0222 / 0.0138 m).
TEST(OfflineAccuracy, AnOccluderOnlyTheFrontendFindsKeepsTheStaticHistory) {
  const sim::Simulator simulator(renderedScenario(sim::ScenarioKind::kSelfOcclusion, 9, 30.0, 10.0, 12.0));
  RenderedFrameCache frames(simulator);
  const std::string section = "\n  conflict:\n";
  const std::string paused =
      shippedConfigWith(section, section + "    frontend_conflict_keeps_history: false\n", "history_paused");
  ASSERT_FALSE(paused.empty());
  pipeline::OfflineRunSummary s_ref, s_paused, s_auto;
  std::size_t conflict_ref = 0, conflict_paused = 0, conflict_auto = 0;
  const auto ref = runAndEvaluate(frames, "rendered_laptop_ref", &s_ref, &conflict_ref, "reference");
  const auto off = runAndEvaluate(frames, "rendered_laptop_paused", &s_paused, &conflict_paused, "auto", paused);
  const auto aut = runAndEvaluate(frames, "rendered_laptop_auto", &s_auto, &conflict_auto, "auto");
  std::filesystem::remove(paused);
  EXPECT_EQ(s_auto.resets, 0u);
  EXPECT_GT(conflict_auto, 200u);  // 240 labelled frames
  EXPECT_LT(aut.ate_pos_yaw_rmse, 0.8 * off.ate_pos_yaw_rmse);
  EXPECT_LT(aut.ate_pos_yaw_rmse, 0.7 * ref.ate_pos_yaw_rmse);
}

// The laptop of seed 8 (`mcvio sim --scenario self_occlusion --duration 30 --onset 10
// --scenario-duration 12 --seed 8`) covers two thirds of the view for 12 s and never leaves it.
// Counted like any track, its tracks held ~150 of the frontend's 200 and left the static world
// ~50; the shipped moving_track_budget_share (0.6) gives the world the rest of the budget
// (measured: auto 0.0056 m, with the share at 1 0.0119 m; the clean run of this seed 0.0079 m;
// before the shipped probation_agreeing_tests, 0.0064 / 0.0136 m).
TEST(OfflineAccuracy, AMovingOccluderLeavesTheBudgetToTheStaticView) {
  const sim::Simulator simulator(renderedScenario(sim::ScenarioKind::kSelfOcclusion, 8, 30.0, 10.0, 12.0));
  RenderedFrameCache frames(simulator);
  // The variant: the laptop's tracks count like any other.
  const auto r = runShippedAndVariant(frames, "rendered_laptop_budget", "moving_track_budget_share: 0.6",
                                      "moving_track_budget_share: 1.0", "auto");
  ASSERT_TRUE(r.ran);
  EXPECT_EQ(r.shipped_summary.resets, 0u);
  EXPECT_GT(r.shipped_conflict_frames, 200u);  // 240 labelled frames
  EXPECT_LT(r.shipped.ate_pos_yaw_rmse, 0.7 * r.variant.ate_pos_yaw_rmse);
}

// A laptop carried in front of the cameras for 12 s (`mcvio sim --scenario self_occlusion
// --duration 30 --onset 10 --scenario-duration 12 --seed 5`) leaves the landmark test a few dozen
// stereo tracks a frame. A landmark born during the conflict stays out of the estimate until that
// test has agreed with it on probation_agreeing_tests frames in a row; the shipped 2 (library 3)
// lets the static landmarks born behind the laptop in sooner (measured: auto 0.0105 m, with 3
// 0.0149 m; the plain VIO 0.0273 m, the clean run of this seed 0.0069 m).
TEST(OfflineAccuracy, StaticLandmarksBornBehindAnOccluderJoinAfterTwoAgreeingTests) {
  const sim::Simulator simulator(renderedScenario(sim::ScenarioKind::kSelfOcclusion, 5, 30.0, 10.0, 12.0));
  RenderedFrameCache frames(simulator);
  const auto r = runShippedAndVariant(frames, "rendered_laptop_probation", "probation_agreeing_tests: 2",
                                      "probation_agreeing_tests: 3", "auto");
  ASSERT_TRUE(r.ran);
  EXPECT_EQ(r.shipped_summary.resets, 0u);
  EXPECT_GT(r.shipped_conflict_frames, 200u);  // 240 labelled frames
  EXPECT_LT(r.shipped.ate_pos_yaw_rmse, 0.013);
  EXPECT_LT(r.shipped.ate_pos_yaw_rmse, 0.8 * r.variant.ate_pos_yaw_rmse);
}

// A vehicle pulling away (`mcvio sim --scenario vehicle --duration 30 --onset 10
// --scenario-duration 12 --seed 4`, 48 m in 12 s) is labelled from the first frame after 10 s, and
// an online TPR of 0.95 over its 239 labelled frames allows 11 of them missed: 0.55 s. The
// estimator bends its accelerometer bias to explain the acceleration vision does not see, by
// 0.12 m/s^2 at 0.45 s and 0.16 at 0.5 s; the shipped fast bias-drift test (1.3 x 0.11 m/s^2) takes
// that as evidence on its first frame (measured: found 0.50 s after the first labelled frame; with
// the library's factor 1.5, 0.65 s, TPR 0.946).
TEST(OfflineAccuracy, AVehicleIsFoundWithinTheFirstHalfSecondOfItsRide) {
  const sim::Simulator simulator(renderedScenario(sim::ScenarioKind::kVehicle, 4, 30.0, 10.0, 12.0));
  RenderedFrameCache frames(simulator);
  // The variant: a bend must reach the library's 1.5 x the limit.
  const auto r = runShippedAndVariant(frames, "rendered_vehicle_fast_drift", "bias_drift_fast_factor: 1.3",
                                      "bias_drift_fast_factor: 1.5", "auto");
  ASSERT_TRUE(r.ran);
  const auto& times = simulator.frameTimes();
  const Timestamp onset = times.front() + fromSeconds(10.0);
  const auto first_labelled = *std::upper_bound(times.begin(), times.end(), onset);
  ASSERT_GT(r.shipped_first_conflict, 0);
  ASSERT_GT(r.variant_first_conflict, 0);
  const double shipped_delay = toSeconds(r.shipped_first_conflict - first_labelled);
  const double variant_delay = toSeconds(r.variant_first_conflict - first_labelled);
  std::cout << "vehicle found " << shipped_delay << " s after its first labelled frame (variant " << variant_delay << " s)\n";
  EXPECT_EQ(r.shipped_summary.resets, 0u);
  EXPECT_GE(shipped_delay, 0.0);  // no false interval before the ride
  EXPECT_LE(shipped_delay, 0.55);
  EXPECT_GT(variant_delay, shipped_delay);
  EXPECT_GT(r.shipped_conflict_frames, 220u);  // 239 labelled frames
}
