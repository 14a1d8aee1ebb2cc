// The frontend on real EuRoC V1_01 images (skipped when $MCVIO_SHARED_DIR is absent).
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <opencv2/core.hpp>
#include <set>
#include <vector>

#include "euroc_excerpt.hpp"
#include "mcvio/frontend/feature_tracker.hpp"

namespace mcvio::frontend {
namespace {

using testing::EurocExcerpt;

struct EurocRun {
  std::vector<TrackingResult> results;
};

class FeatureTrackerEurocTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto mav0 = EurocExcerpt::locate();
    if (!mav0) GTEST_SKIP() << "MCVIO_SHARED_DIR/data/euroc_V1_01_excerpt not available";
    if (!excerpt_) excerpt_ = std::make_unique<EurocExcerpt>(*mav0);
  }

  // Runs the whole excerpt; `gains` (if set) scales each image by a per-frame factor.
  static EurocRun runAll(bool gains) {
    FeatureTracker tracker;
    tracker.setCalibration(excerpt_->calibration());
    EurocRun run;
    for (std::size_t i = 0; i < excerpt_->size(); ++i) {
      StereoInput in = excerpt_->frame(i);
      if (gains) {
        // Alternating strong gain steps, different for the two cameras.
        const double gl = (i % 2 == 0) ? 0.6 : 1.35;
        const double gr = (i % 3 == 0) ? 1.3 : 0.7;
        in.left.convertTo(in.left, CV_8U, gl);
        in.right.convertTo(in.right, CV_8U, gr);
      }
      run.results.push_back(tracker.track(in));
    }
    return run;
  }

  static std::unique_ptr<EurocExcerpt> excerpt_;
};
std::unique_ptr<EurocExcerpt> FeatureTrackerEurocTest::excerpt_;

std::map<std::uint64_t, Eigen::Vector2d> leftPixels(const FeatureFrame& f) {
  std::map<std::uint64_t, Eigen::Vector2d> m;
  for (const auto& o : f.features) {
    if (o.camera_index == 0) m[o.track_id] = o.pixel;
  }
  return m;
}

TEST_F(FeatureTrackerEurocTest, PairsImagesByTimestamp) {
  EXPECT_EQ(excerpt_->size(), 95u);
  // cam1/data.csv lists 4 images that do not exist; the reader reports and skips them.
  EXPECT_EQ(excerpt_->dataset().warnings().size(), 4u);
}

TEST_F(FeatureTrackerEurocTest, AtLeast120StereoMatchesEveryFrame) {
  const EurocRun run = runAll(false);
  int min_stereo = 1 << 30;
  for (const auto& r : run.results) {
    ASSERT_TRUE(r.ok()) << r.message;
    EXPECT_GE(r.stats.stereo_matched, 120) << "frame " << r.features.frame_index;
    min_stereo = std::min(min_stereo, r.stats.stereo_matched);
  }
  std::printf("EuRoC: min stereo matches per frame %d over %zu frames\n", min_stereo,
              run.results.size());
}

TEST_F(FeatureTrackerEurocTest, TrackIdsStableOverStaticSequence) {
  const EurocRun run = runAll(false);
  const FeatureFrame& f0 = run.results.front().features;
  const FeatureFrame& fn = run.results.back().features;
  std::map<std::uint64_t, const FeatureObservation*> first, last;
  for (const auto& o : f0.features) {
    if (o.camera_index == 0) first[o.track_id] = &o;
  }
  for (const auto& o : fn.features) {
    if (o.camera_index == 0) last[o.track_id] = &o;
  }
  // "Standing still" still turns by ~0.15 deg over the excerpt (ground truth), so the surviving
  // tracks must move together: fit one rotation to their bearings (Kabsch) and require every
  // track to follow it. A track that wandered or jumped to another corner would not.
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> bearings;
  std::vector<Eigen::Vector2d> last_pixels;
  std::vector<double> displacement;
  for (const auto& kv : first) {
    const auto it = last.find(kv.first);
    if (it == last.end()) continue;
    bearings.emplace_back(kv.second->normalized.homogeneous().normalized(),
                          it->second->normalized.homogeneous().normalized());
    last_pixels.push_back(it->second->pixel);
    displacement.push_back((it->second->pixel - kv.second->pixel).norm());
  }
  ASSERT_GE(bearings.size(), 10u);
  Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
  for (const auto& b : bearings) h += b.second * b.first.transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() > 0 ? 1.0 : -1.0;
  const Eigen::Matrix3d R = svd.matrixU() * d * svd.matrixV().transpose();
  std::vector<double> residual;
  const CameraModel& cam0 = excerpt_->calibration().cam0.model;
  for (std::size_t i = 0; i < bearings.size(); ++i) {
    Eigen::Vector2d predicted;
    ASSERT_TRUE(cam0.projectAnywhere(R * bearings[i].first, &predicted));
    residual.push_back((predicted - last_pixels[i]).norm());
  }
  std::set<std::uint64_t> all_ids;
  int consistent = 0, labelled = 0;
  for (const auto& r : run.results) {
    for (const auto& o : r.features.features) {
      all_ids.insert(o.track_id);
      if (o.camera_index == 0 && o.label != TrackLabel::kUnknown) {
        ++labelled;
        consistent += o.label == TrackLabel::kConsistent ? 1 : 0;
      }
    }
  }
  std::sort(displacement.begin(), displacement.end());
  std::sort(residual.begin(), residual.end());
  const double angle_deg = Eigen::AngleAxisd(R).angle() * 180.0 / M_PI;
  std::printf(
      "EuRoC static: %zu/%zu first-frame tracks survive %zu frames; they moved %.3f px (median) "
      "as a rotation of %.3f deg, residual median %.3f / 90%% %.3f px; %zu distinct ids; "
      "consistent labels %d/%d\n",
      bearings.size(), first.size(), run.results.size(), displacement[displacement.size() / 2],
      angle_deg, residual[residual.size() / 2], residual[residual.size() * 9 / 10], all_ids.size(),
      consistent, labelled);
  EXPECT_GE(bearings.size(), 0.8 * static_cast<double>(first.size()));
  EXPECT_LE(residual[residual.size() / 2], 0.3);
  EXPECT_LE(residual[residual.size() * 9 / 10], 1.0);
  EXPECT_LT(angle_deg, 0.5);
  EXPECT_LE(all_ids.size(), first.size() * 3 / 2);
  EXPECT_GE(consistent, 0.9 * labelled);
}

TEST_F(FeatureTrackerEurocTest, StereoDisparitiesConsistentWithCalibration) {
  const EurocRun run = runAll(false);
  const StereoRigCalibration& calib = excerpt_->calibration();
  const Eigen::Isometry3d T10 = calib.T_C0C1().inverse();
  Eigen::Matrix3d tx;
  const Eigen::Vector3d t = T10.translation();
  tx << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
  const Eigen::Matrix3d E = tx * T10.linear();
  std::vector<double> epi;
  std::map<std::uint64_t, std::vector<double>> depth_by_track;
  for (const auto& r : run.results) {
    std::map<std::uint64_t, Eigen::Vector2d> left;
    for (const auto& o : r.features.features) {
      if (o.camera_index == 0) left[o.track_id] = o.pixel;
    }
    for (const auto& o : r.features.features) {
      if (o.camera_index != 1) continue;
      // Recompute everything from the published pixels with the calibration alone.
      Eigen::Vector2d x0, x1;
      ASSERT_TRUE(calib.cam0.model.unproject(left.at(o.track_id), &x0));
      ASSERT_TRUE(calib.cam1.model.unproject(o.pixel, &x1));
      const Eigen::Vector3d line = E * x0.homogeneous();
      epi.push_back(std::abs(x1.homogeneous().dot(line)) / line.head<2>().norm() *
                    calib.cam1.model.fu());
      Eigen::Matrix<double, 3, 2> a;
      a.col(0) = T10.linear() * x0.homogeneous();
      a.col(1) = -x1.homogeneous();
      const Eigen::Vector2d d = (a.transpose() * a).ldlt().solve(-a.transpose() * t);
      depth_by_track[o.track_id].push_back(d[0]);
    }
  }
  ASSERT_FALSE(epi.empty());
  std::sort(epi.begin(), epi.end());
  const double median_epi = epi[epi.size() / 2];
  std::vector<double> depths, rel_spread;
  for (const auto& kv : depth_by_track) {
    std::vector<double> d = kv.second;
    std::sort(d.begin(), d.end());
    depths.push_back(d[d.size() / 2]);
    if (d.size() >= 50) {
      // Same point, still camera: its stereo depth must not wander.
      const double lo = d[d.size() / 10], hi = d[d.size() * 9 / 10];
      rel_spread.push_back((hi - lo) / d[d.size() / 2]);
    }
  }
  std::sort(depths.begin(), depths.end());
  std::sort(rel_spread.begin(), rel_spread.end());
  std::printf(
      "EuRoC stereo: median epipolar distance %.3f px (max %.3f), depth 10/50/90%% %.2f/%.2f/%.2f "
      "m, "
      "median per-track depth spread %.2f%% over %zu tracks\n",
      median_epi, epi.back(), depths[depths.size() / 10], depths[depths.size() / 2],
      depths[depths.size() * 9 / 10], 100 * rel_spread[rel_spread.size() / 2], rel_spread.size());
  EXPECT_LE(median_epi, 0.5);
  // The frontend measures with the mean focal length, this test with fu: allow that difference.
  EXPECT_LE(epi.back(), 1.01 * FrontendOptions().stereo_epipolar_threshold_px);
  // V1_01 is a Vicon room a few metres across.
  EXPECT_GT(depths.front(), 0.0);
  EXPECT_GT(depths[depths.size() / 2], 1.0);
  EXPECT_LT(depths[depths.size() / 2], 10.0);
  ASSERT_FALSE(rel_spread.empty());
  EXPECT_LE(rel_spread[rel_spread.size() / 2], 0.05);
}

TEST_F(FeatureTrackerEurocTest, GainChangesDoNotBreakTracks) {
  const EurocRun run = runAll(true);
  int min_stereo = 1 << 30;
  for (const auto& r : run.results) {
    ASSERT_TRUE(r.ok()) << r.message;
    min_stereo = std::min(min_stereo, r.stats.stereo_matched);
  }
  const auto first = leftPixels(run.results.front().features);
  const auto last = leftPixels(run.results.back().features);
  int survived = 0;
  for (const auto& kv : first) survived += last.count(kv.first) ? 1 : 0;
  std::printf("EuRoC with gain steps: min stereo %d, %d/%zu first-frame tracks survive\n",
              min_stereo, survived, first.size());
  EXPECT_GE(min_stereo, 120);
  EXPECT_GE(survived, 0.7 * static_cast<double>(first.size()));
}

}  // namespace
}  // namespace mcvio::frontend
