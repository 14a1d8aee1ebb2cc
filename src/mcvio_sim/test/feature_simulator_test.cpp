#include <gtest/gtest.h>

#include <map>

#include "mcvio/core/input_error.hpp"
#include "mcvio/sim/feature_simulator.hpp"
#include "mcvio/sim/simulator.hpp"

namespace mcvio::sim {
namespace {

SimulatorOptions shortRun(ScenarioKind kind) {
  SimulatorOptions o;
  o.duration_s = 10.0;
  o.texture_size = 64;
  o.scenario.kind = kind;
  o.scenario.onset_s = 3.0;
  o.scenario.duration_s = 4.0;
  return o;
}

TEST(FeatureSimulator, TracksAreStereoNoisyProjectionsOfTheirLandmarksWithFiniteLifetimes) {
  const SimulatorOptions so = shortRun(ScenarioKind::kNone);
  FeatureSimulatorOptions fo;
  fo.pixel_noise_sigma = 0.5;
  const FeatureSequence seq = simulateFeatureSequence(so, fo);
  ASSERT_EQ(seq.frames.size(), 201u);
  EXPECT_EQ(seq.imu.size(), 2001u);
  EXPECT_EQ(seq.labels.size(), seq.frames.size());

  const Simulator sim(so);  // same seed: same world and trajectory
  std::map<std::uint64_t, std::pair<std::size_t, std::size_t>> life;  // first, last frame
  double err2 = 0;
  std::size_t n = 0, right = 0, left = 0;
  for (const FeatureFrame& f : seq.frames) {
    std::size_t cam0 = 0;
    const Eigen::Isometry3d T_WB = sim.bodyPose(f.t);
    for (const FeatureObservation& o : f.features) {
      EXPECT_EQ(o.label, TrackLabel::kConsistent);
      const LandmarkTruth& l = seq.track_truth.at(o.track_id);
      const auto& cam = seq.calibration.camera(o.camera_index);
      const Eigen::Vector3d p_c = (T_WB * cam.T_BC).inverse() * (sim.world().scene.bodyPose(l.body, f.t, T_WB) * l.p_body);
      Eigen::Vector2d px;
      ASSERT_TRUE(cam.model.project(p_c, &px));
      err2 += (px - o.pixel).squaredNorm();
      n += 2;
      Eigen::Vector2d xy;
      ASSERT_TRUE(cam.model.unproject(o.pixel, &xy));
      EXPECT_LT((xy - o.normalized).norm(), 1e-9);
      if (o.camera_index == 0) {
        ++cam0;
        ++left;
        auto it = life.find(o.track_id);
        if (it == life.end()) {
          life[o.track_id] = {f.frame_index, f.frame_index};
        } else {
          EXPECT_EQ(it->second.second + 1, f.frame_index) << "tracks do not come back after ending";
          it->second.second = f.frame_index;
        }
      } else {
        ++right;
      }
    }
    if (f.frame_index > 0) {
      EXPECT_GE(cam0, 120u) << "frame " << f.frame_index;
    }
  }
  EXPECT_NEAR(std::sqrt(err2 / n), 0.5, 0.05);
  EXPECT_GT(right, left * 7 / 10) << "most tracks are seen by cam1 too";
  double mean_len = 0;
  for (const auto& [id, span] : life) mean_len += span.second - span.first + 1;
  mean_len /= life.size();
  EXPECT_GT(mean_len, 8.0);
  EXPECT_LT(mean_len, 45.0);
}

TEST(FeatureSimulator, ReidentificationChangesOnlyTheIdsOfReturningTracks) {
  SimulatorOptions so = shortRun(ScenarioKind::kSelfOcclusion);
  so.duration_s = 14.0;
  FeatureSimulatorOptions fo;
  const FeatureSequence plain = simulateFeatureSequence(so, fo);
  fo.reidentify_probability = 1.0;
  const FeatureSequence reid = simulateFeatureSequence(so, fo);
  ASSERT_EQ(plain.frames.size(), reid.frames.size());
  std::map<std::uint64_t, std::size_t> last_frame;  // per id, with re-identification
  int returned = 0;
  for (std::size_t k = 0; k < plain.frames.size(); ++k) {
    const auto& a = plain.frames[k].features;
    const auto& b = reid.frames[k].features;
    ASSERT_EQ(a.size(), b.size()) << "frame " << k;
    for (std::size_t i = 0; i < a.size(); ++i) {
      EXPECT_EQ(a[i].pixel, b[i].pixel);
      EXPECT_EQ(a[i].camera_index, b[i].camera_index);
      // The same landmark under either id.
      EXPECT_EQ(plain.track_truth.at(a[i].track_id).p_body, reid.track_truth.at(b[i].track_id).p_body);
      if (b[i].camera_index != 0) continue;
      const auto it = last_frame.find(b[i].track_id);
      if (it != last_frame.end() && it->second + 1 < k) {
        ++returned;
        // Back at least reidentify_min_age_s (3 s = 60 frames) after it ended.
        EXPECT_GE(k - it->second, 60u);
      }
      last_frame[b[i].track_id] = k;
    }
  }
  EXPECT_GT(returned, 10);
  FeatureSimulatorOptions bad;
  bad.reidentify_probability = 1.5;
  EXPECT_THROW(bad.validate(), InputError);
  bad = FeatureSimulatorOptions();
  bad.reidentify_min_age_s = 70.0;
  EXPECT_THROW(bad.validate(), InputError);
}

TEST(FeatureSimulator, LandmarksOnTheRidingCabinAreInconsistentDuringTheRideOnly) {
  SimulatorOptions so = shortRun(ScenarioKind::kElevator);
  so.scenario.coverage = 1.0;  // closed cabin: no static shaft seen through a window
  const FeatureSequence a = simulateFeatureSequence(so);
  const FeatureSequence b = simulateFeatureSequence(so);
  const Timestamp onset = a.frames.front().t + fromSeconds(3.0), end = onset + fromSeconds(4.0);
  for (std::size_t k = 0; k < a.frames.size(); ++k) {
    const FeatureFrame& f = a.frames[k];
    const bool riding = f.t > onset && f.t < end;
    ASSERT_FALSE(f.features.empty());
    for (const auto& o : f.features)
      EXPECT_EQ(o.label, riding ? TrackLabel::kInconsistent : TrackLabel::kConsistent) << "frame " << k;
    EXPECT_EQ(a.labels[k].in_conflict, riding);
    // Deterministic for the seed.
    ASSERT_EQ(f.features.size(), b.frames[k].features.size());
    for (std::size_t i = 0; i < f.features.size(); ++i) {
      EXPECT_EQ(f.features[i].track_id, b.frames[k].features[i].track_id);
      EXPECT_EQ(f.features[i].pixel, b.frames[k].features[i].pixel);
    }
  }
}

TEST(FeatureSimulator, APedestrianMakesAPartialConflict) {
  const FeatureSequence seq = simulateFeatureSequence(shortRun(ScenarioKind::kPedestrian));
  std::size_t mixed = 0;
  for (std::size_t k = 0; k < seq.frames.size(); ++k) {
    std::size_t bad = 0, good = 0;
    for (const auto& o : seq.frames[k].features) {
      if (o.label == TrackLabel::kInconsistent) ++bad;
      else ++good;
    }
    if (bad > 0 && good > 0) ++mixed;
    if (bad > 0) {
      EXPECT_TRUE(seq.labels[k].in_conflict);
    }
  }
  EXPECT_GT(mixed, 5u);
}

}  // namespace
}  // namespace mcvio::sim
