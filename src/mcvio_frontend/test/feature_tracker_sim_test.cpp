// The frontend on the team simulator's rendering (mcvio_sim): a pedestrian walks across a
// textured office in front of a moving stereo rig. The per-pixel body ids of the rendering say
// which features sit on the pedestrian; those must be labelled inconsistent.
#include <gtest/gtest.h>

#include <cstdio>
#include <map>

#include "mcvio/frontend/feature_tracker.hpp"
#include "mcvio/sim/simulator.hpp"

namespace mcvio::frontend {
namespace {

TEST(FeatureTrackerSim, PedestrianFeaturesAreInconsistentStaticOnesConsistent) {
  sim::SimulatorOptions o;
  o.duration_s = 6.0;
  o.camera_rate_hz = 20.0;
  o.texture_size = 512;
  o.seed = 3;
  o.scenario.kind = sim::ScenarioKind::kPedestrian;
  o.scenario.onset_s = 1.0;
  o.scenario.duration_s = 4.0;
  const sim::Simulator simulator(o);
  FeatureTracker tracker;
  tracker.setCalibration(simulator.calibration());

  const auto& times = simulator.frameTimes();
  const auto& imu = simulator.imu();
  std::size_t imu_next = 0;
  int moving_labelled = 0, moving_inconsistent = 0, static_labelled = 0, static_consistent = 0;
  int min_stereo = 1 << 30, conflict_frames = 0;
  // 0.5 s .. 5.5 s: before, during and after the walk.
  for (std::size_t k = 10; k < 110 && k < times.size(); ++k) {
    const sim::StereoRender render = simulator.renderFrame(k);
    StereoInput in;
    in.t = render.t;
    in.left = render.cam0;
    in.right = render.cam1;
    while (imu_next < imu.size() && imu[imu_next].t <= in.t) in.imu.push_back(imu[imu_next++]);
    const TrackingResult r = tracker.track(in);
    ASSERT_TRUE(r.ok()) << r.message;
    min_stereo = std::min(min_stereo, r.stats.stereo_matched);
    conflict_frames += render.label.in_conflict ? 1 : 0;
    for (const auto& f : r.features.features) {
      if (f.camera_index != 0 || f.label == TrackLabel::kUnknown) continue;
      const int u = static_cast<int>(std::lround(f.pixel.x())),
                v = static_cast<int>(std::lround(f.pixel.y()));
      // Judge only features well inside one body: the 5x5 neighbourhood has a single id.
      const cv::Rect box(u - 2, v - 2, 5, 5);
      if ((box & cv::Rect(0, 0, render.cam0_body_ids.cols, render.cam0_body_ids.rows)) != box)
        continue;
      const cv::Mat ids = render.cam0_body_ids(box);
      const int id = ids.at<uchar>(2, 2);
      if (cv::countNonZero(ids != id) > 0) continue;
      bool moving = false;
      for (int b : simulator.world().conflict_bodies) moving = moving || b == id;
      if (moving) {
        ++moving_labelled;
        moving_inconsistent += f.label == TrackLabel::kInconsistent ? 1 : 0;
      } else {
        ++static_labelled;
        static_consistent += f.label == TrackLabel::kConsistent ? 1 : 0;
      }
    }
  }
  std::printf(
      "sim pedestrian: %d conflict frames; pedestrian labels inconsistent %d/%d, static consistent "
      "%d/%d, min stereo %d\n",
      conflict_frames, moving_inconsistent, moving_labelled, static_consistent, static_labelled,
      min_stereo);
  ASSERT_GT(conflict_frames, 0);
  ASSERT_GE(moving_labelled, 20);
  EXPECT_GE(moving_inconsistent, 0.7 * moving_labelled);
  EXPECT_GE(static_consistent, 0.95 * static_labelled);
}

}  // namespace
}  // namespace mcvio::frontend
