#include "mcvio/pipeline/offline_run.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>

#include <nlohmann/json.hpp>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/progress_bar.hpp"
#include "mcvio/dataset/euroc_dataset.hpp"

namespace mcvio::pipeline {
namespace {

struct StageStats {
  std::vector<double> values;
  void add(double v) { values.push_back(v); }
  nlohmann::json summary() const {
    if (values.empty()) return nlohmann::json::object();
    auto v = values;
    std::sort(v.begin(), v.end());
    double sum = 0;
    for (double x : v) sum += x;
    return {{"median", v[v.size() / 2]}, {"p90", v[std::min(v.size() - 1, v.size() * 9 / 10)]},
            {"mean", sum / static_cast<double>(v.size())}, {"max", v.back()}};
  }
};

}  // namespace

OfflineRunSummary runOffline(const OfflineRunOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto data = dataset::EurocDataset::open(options.dataset_dir);
  for (const auto& w : data.warnings()) std::cerr << "mcvio run: warning: " << w << "\n";
  if (data.stereoFrames().empty()) throw InputError(options.dataset_dir + ": no stereo frames to run on");
  if (data.imu().empty()) throw InputError(options.dataset_dir + ": no IMU samples (mav0/imu0/data.csv)");
  const auto vio_options = options.config_file.empty() ? VioPipelineOptions{} : VioPipelineOptions::fromYamlFile(options.config_file);
  std::filesystem::create_directories(options.output_dir);
  const std::string tum_path = options.output_dir + "/trajectory.tum";
  std::ofstream tum(tum_path);
  if (!tum) throw InputError("cannot write " + tum_path);
  tum << "# t x y z qx qy qz qw  (pose of imu0 in world; t in seconds)\n" << std::setprecision(9) << std::fixed;

  VioPipeline vio(data.calibration(), vio_options);
  OfflineRunSummary summary;
  StageStats frontend_ms, backend_ms, features, stereo, landmarks;
  std::size_t keyframes = 0, zero_velocity = 0, not_initialized = 0;
  std::map<std::string, std::size_t> skip_reasons;
  const auto& imu = data.imu();
  std::size_t next_imu = 0;
  ProgressBar bar("run", data.stereoFrames().size(), options.progress);
  const auto start = Clock::now();
  for (std::size_t i = 0; i < data.stereoFrames().size(); ++i) {
    const auto& f = data.stereoFrames()[i];
    // Everything the IMU measured up to the image time comes first, as on the bus.
    while (next_imu < imu.size() && imu[next_imu].t <= f.t) vio.addImu(imu[next_imu++]);
    const auto r = vio.addFrame(f.t, data.loadImage(f, 0), data.loadImage(f, 1));
    ++summary.frames;
    frontend_ms.add(r.tracking.stats.cpu_ms_total);
    if (!r.estimated) {
      ++summary.skipped;
      ++skip_reasons[r.tracking.message];
      continue;
    }
    features.add(r.tracking.stats.tracked + r.tracking.stats.detected);
    stereo.add(r.tracking.stats.stereo_matched);
    const auto& e = r.estimate;
    backend_ms.add(e.timings.cpu_total_ms);
    if (e.status == estimator::EstimatorStatus::kReset) ++summary.resets;
    if (e.status == estimator::EstimatorStatus::kNotInitialized) ++not_initialized;
    keyframes += e.is_keyframe;
    zero_velocity += e.zero_velocity;
    landmarks.add(e.num_landmarks);
    if (e.status == estimator::EstimatorStatus::kTracking && e.frame_accepted) {
      ++summary.estimated;
      tum << toSeconds(e.t) << ' ' << e.p_WB.x() << ' ' << e.p_WB.y() << ' ' << e.p_WB.z() << ' ' << e.q_WB.x() << ' '
          << e.q_WB.y() << ' ' << e.q_WB.z() << ' ' << e.q_WB.w() << '\n';
    }
    if (i % 5 == 0) bar.update(i + 1, std::to_string(summary.estimated) + " poses");
  }
  bar.finish();
  summary.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  summary.data_seconds = toSeconds(data.stereoFrames().back().t - data.stereoFrames().front().t);

  nlohmann::json stats = {
      {"dataset", options.dataset_dir},
      {"frames", summary.frames},
      {"poses", summary.estimated},
      {"skipped_frames", summary.skipped},
      {"skip_reasons", skip_reasons},
      {"not_initialized_frames", not_initialized},
      {"resets", summary.resets},
      {"keyframes", keyframes},
      {"zero_velocity_frames", zero_velocity},
      {"wall_seconds", summary.wall_seconds},
      {"data_seconds", summary.data_seconds},
      {"realtime_factor", summary.wall_seconds > 0 ? summary.data_seconds / summary.wall_seconds : 0.0},
      {"cpu_ms_per_frame", {{"frontend", frontend_ms.summary()}, {"backend", backend_ms.summary()}}},
      {"features_per_frame", features.summary()},
      {"stereo_matches_per_frame", stereo.summary()},
      {"landmarks_in_window", landmarks.summary()},
      {"warnings", data.warnings()}};
  std::ofstream(options.output_dir + "/stats.json") << stats.dump(2) << "\n";
  return summary;
}

}  // namespace mcvio::pipeline
