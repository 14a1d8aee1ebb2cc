// A EuRoC folder through mcvio_frontend and SlidingWindowEstimator: prints drift from the first
// tracked position, velocity, biases and CPU time every 10 frames. Usage: euroc_check <dir> [options.yaml]
#include <cstdio>

#include "mcvio/dataset/euroc_dataset.hpp"
#include "mcvio/estimator/sliding_window_estimator.hpp"
#include "mcvio/frontend/feature_tracker.hpp"

using namespace mcvio;

int main(int argc, char** argv) {
  const auto ds = dataset::EurocDataset::open(argv[1]);
  estimator::EstimatorOptions eo;
  if (argc > 2) eo = estimator::EstimatorOptions::fromYamlFile(argv[2]);
  estimator::SlidingWindowEstimator est(eo, ds.calibration());
  frontend::FeatureTracker tracker;
  tracker.setCalibration(ds.calibration());
  std::size_t k = 0;
  const auto& imu = ds.imu();
  Eigen::Vector3d p0 = Eigen::Vector3d::Zero();
  bool have_p0 = false;
  int n = 0;
  for (const auto& f : ds.stereoFrames()) {
    frontend::StereoInput in;
    in.t = f.t;
    in.left = ds.loadImage(f, 0);
    in.right = ds.loadImage(f, 1);
    while (k < imu.size() && imu[k].t <= f.t) {
      in.imu.push_back(imu[k]);
      est.addImu(imu[k++]);
    }
    const auto r = tracker.track(in);
    if (!r.ok()) { std::printf("frontend: %s\n", r.message.c_str()); continue; }
    const auto out = est.addFrame(r.features);
    if (out.frame_accepted && out.status == estimator::EstimatorStatus::kTracking) {
      if (!have_p0) { p0 = out.p_WB; have_p0 = true; }
      ++n;
      if (n % 10 == 1 || n < 3)
        std::printf("frame %u feats %zu lm %d vis %d zv %d |p-p0| %.4f m |v| %.4f bg %.4f %.4f %.4f ba %.3f %.3f %.3f cpu %.1f ms %s\n",
                    out.frame_index, r.features.features.size(), out.num_landmarks, out.num_visual_residuals, out.zero_velocity,
                    (out.p_WB - p0).norm(), out.v_WB.norm(), out.bias.gyro.x(), out.bias.gyro.y(), out.bias.gyro.z(),
                    out.bias.accel.x(), out.bias.accel.y(), out.bias.accel.z(), out.timings.cpu_total_ms, out.message.c_str());
    } else {
      std::printf("frame %u status %s accepted %d: %s\n", out.frame_index, estimator::toString(out.status), out.frame_accepted, out.message.c_str());
    }
  }
  if (!ds.groundTruth().empty()) {
    const auto& g = ds.groundTruth().front();
    std::printf("ground truth biases at start: bg %.4f %.4f %.4f ba %.3f %.3f %.3f\n", g.bias_gyro.x(), g.bias_gyro.y(),
                g.bias_gyro.z(), g.bias_accel.x(), g.bias_accel.y(), g.bias_accel.z());
  }
  std::printf("tracked %d frames, resets %d\n", n, est.resetCount());
  return 0;
}
