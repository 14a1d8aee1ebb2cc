// Frontend accuracy against exact ground truth from the ray-cast synthetic stereo scene.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <vector>

#include "mcvio/frontend/feature_tracker.hpp"
#include "synthetic_stereo_scene.hpp"

namespace mcvio::frontend {
namespace {

using testing::SyntheticStereoScene;

constexpr int kFrames = 60;

struct RunSummary {
  std::vector<double> left_errors;  // tracked vs true pixel, observations after the first
  int stereo_total = 0;
  int stereo_wrong = 0;  // right pixel > 1 px from the true projection
  std::map<std::uint64_t, int> track_length;
  // Per frame labels of tracks whose first observation landed on the moving patch / background.
  int patch_labelled = 0, patch_inconsistent = 0;
  int background_labelled = 0, background_consistent = 0;
  std::map<std::uint64_t, std::pair<int, int>> patch_tracks;  // id -> (labelled, inconsistent)
  int min_stereo = 1 << 30;
};

double median(std::vector<double> v) {
  if (v.empty()) return 1e9;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

const std::vector<StereoInput>& renders(const SyntheticStereoScene& scene, int key) {
  static std::map<int, std::vector<StereoInput>> cache;
  auto& frames = cache[key];
  if (frames.empty()) {
    for (int k = 0; k < kFrames; ++k) frames.push_back(scene.render(k));
  }
  return frames;
}

RunSummary run(const SyntheticStereoScene& scene, const std::vector<StereoInput>& frames,
               const FrontendOptions& options, bool with_imu) {
  FeatureTracker tracker(options);
  tracker.setCalibration(scene.calibration());
  RunSummary s;
  std::map<std::uint64_t, SyntheticStereoScene::SurfacePoint> truth;
  for (int k = 0; k < static_cast<int>(frames.size()); ++k) {
    StereoInput in = frames[static_cast<std::size_t>(k)];
    if (!with_imu) in.imu.clear();
    const TrackingResult r = tracker.track(in);
    EXPECT_TRUE(r.ok()) << r.message;
    s.min_stereo = std::min(s.min_stereo, r.stats.stereo_matched);
    for (const FeatureObservation& o : r.features.features) {
      if (o.camera_index == 0) {
        ++s.track_length[o.track_id];
        auto it = truth.find(o.track_id);
        if (it == truth.end()) {
          SyntheticStereoScene::SurfacePoint hit;
          if (scene.castRay(k, 0, o.pixel, &hit)) truth[o.track_id] = hit;
          continue;
        }
        Eigen::Vector2d expected;
        if (scene.project(it->second, k, 0, &expected)) {
          s.left_errors.push_back((expected - o.pixel).norm());
        }
        if (o.label == TrackLabel::kUnknown) continue;
        if (it->second.surface == 3) {
          // Inner patch points only: the border mixes patch and background texture.
          if (std::abs(it->second.point.x()) > 0.28 || std::abs(it->second.point.y()) > 0.28)
            continue;
          ++s.patch_labelled;
          auto& pt = s.patch_tracks[o.track_id];
          ++pt.first;
          if (o.label == TrackLabel::kInconsistent) {
            ++s.patch_inconsistent;
            ++pt.second;
          }
        } else {
          ++s.background_labelled;
          if (o.label == TrackLabel::kConsistent) ++s.background_consistent;
        }
      } else {
        // Right observation: the true projection of the point under this frame's left pixel.
        const auto left = std::find_if(r.features.features.begin(), r.features.features.end(),
                                       [&](const FeatureObservation& l) {
                                         return l.camera_index == 0 && l.track_id == o.track_id;
                                       });
        SyntheticStereoScene::SurfacePoint hit;
        Eigen::Vector2d expected;
        if (left != r.features.features.end() && scene.castRay(k, 0, left->pixel, &hit) &&
            scene.project(hit, k, 1, &expected)) {
          ++s.stereo_total;
          if ((expected - o.pixel).norm() > 1.0) ++s.stereo_wrong;
        }
      }
    }
  }
  return s;
}

double meanTrackLength(const RunSummary& s) {
  double sum = 0;
  for (const auto& kv : s.track_length) sum += kv.second;
  return s.track_length.empty() ? 0 : sum / static_cast<double>(s.track_length.size());
}

TEST(FeatureTrackerSynthetic, CleanSceneMeetsAccuracyTargets) {
  SyntheticStereoScene scene({});
  const RunSummary s = run(scene, renders(scene, 0), FrontendOptions(), true);
  const double med = median(s.left_errors);
  const double wrong = static_cast<double>(s.stereo_wrong) / std::max(1, s.stereo_total);
  std::printf(
      "clean: median reprojection error %.3f px over %zu obs, wrong stereo %d/%d (%.2f%%), "
      "mean track length %.1f frames over %zu tracks, min stereo per frame %d\n",
      med, s.left_errors.size(), s.stereo_wrong, s.stereo_total, 100 * wrong, meanTrackLength(s),
      s.track_length.size(), s.min_stereo);
  EXPECT_LE(med, 0.3);
  EXPECT_LE(wrong, 0.01);
  EXPECT_GE(meanTrackLength(s), 15.0);
  EXPECT_GT(s.stereo_total, 1000);
  // A still scene: nearly every background track agrees with the camera motion.
  EXPECT_GE(s.background_consistent, 0.95 * s.background_labelled);
}

TEST(FeatureTrackerSynthetic, PerFrameGainChangesDoNotBreakTracks) {
  SyntheticStereoScene::Config config;
  config.random_gain = true;
  SyntheticStereoScene scene(config);
  const RunSummary s = run(scene, renders(scene, 1), FrontendOptions(), true);
  const double med = median(s.left_errors);
  std::printf("gain changes: median error %.3f px, mean track length %.1f, wrong stereo %d/%d\n",
              med, meanTrackLength(s), s.stereo_wrong, s.stereo_total);
  EXPECT_LE(med, 0.3);
  EXPECT_GE(meanTrackLength(s), 15.0);
  EXPECT_LE(s.stereo_wrong, 0.01 * s.stereo_total);
}

void expectPatchInconsistent(const RunSummary& s, const char* what) {
  int tracks_mostly_inconsistent = 0, judged_tracks = 0;
  for (const auto& kv : s.patch_tracks) {
    if (kv.second.first < 3) continue;
    ++judged_tracks;
    if (kv.second.second * 2 > kv.second.first) ++tracks_mostly_inconsistent;
  }
  std::printf(
      "%s: patch labels inconsistent %d/%d, patch tracks mostly inconsistent %d/%d, "
      "background consistent %d/%d\n",
      what, s.patch_inconsistent, s.patch_labelled, tracks_mostly_inconsistent, judged_tracks,
      s.background_consistent, s.background_labelled);
  ASSERT_GE(judged_tracks, 5);
  EXPECT_GE(s.patch_inconsistent, 0.8 * s.patch_labelled);
  EXPECT_GE(tracks_mostly_inconsistent, 0.9 * judged_tracks);
  EXPECT_GE(s.background_consistent, 0.95 * s.background_labelled);
}

TEST(FeatureTrackerSynthetic, MovingPatchIsLabelledInconsistent) {
  SyntheticStereoScene::Config config;
  config.moving_patch = true;
  SyntheticStereoScene scene(config);
  expectPatchInconsistent(run(scene, renders(scene, 2), FrontendOptions(), true), "patch, gyro");
}

TEST(FeatureTrackerSynthetic, MovingPatchIsLabelledInconsistentWithoutImu) {
  SyntheticStereoScene::Config config;
  config.moving_patch = true;
  SyntheticStereoScene scene(config);
  expectPatchInconsistent(run(scene, renders(scene, 2), FrontendOptions(), false), "patch, no IMU");
}

}  // namespace
}  // namespace mcvio::frontend
