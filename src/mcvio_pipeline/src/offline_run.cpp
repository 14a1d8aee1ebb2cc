#include "mcvio/pipeline/offline_run.hpp"

#include <algorithm>
#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>

#include <nlohmann/json.hpp>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/progress_bar.hpp"
#include "mcvio/bag/bag_reader.hpp"
#include "mcvio/dataset/euroc_dataset.hpp"
#include "mcvio/dataset/euroc_file_reader.hpp"
#include "mcvio/rosmsg/cdr_codec.hpp"

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

// The input of a run, whether from a EuRoC folder or a bag: IMU, and stereo frames whose images
// are produced on demand.
struct RunInput {
  StereoRigCalibration calibration;
  std::vector<ImuSample> imu;
  std::vector<Timestamp> frame_times;
  std::function<std::pair<cv::Mat, cv::Mat>(std::size_t)> images;
  std::vector<std::string> warnings;
};

Timestamp stampOf(const rosmsg::MessageValue& msg) {
  const auto& stamp = msg["header"]["stamp"];
  return std::get<std::int64_t>(stamp["sec"].value) * 1000000000 +
         static_cast<Timestamp>(std::get<std::uint64_t>(stamp["nanosec"].value));
}

double number(const rosmsg::MessageValue& v) { return std::get<double>(v.value); }

RunInput readBag(const OfflineRunOptions& options) {
  if (options.calibration_dir.empty()) {
    throw InputError(options.dataset_dir + " is a bag: give --calib DIR (EuRoC sensor.yaml folder); "
                     "camera_info carries no stereo extrinsics");
  }
  RunInput in;
  in.calibration = dataset::EurocFileReader::readCalibration(options.calibration_dir);
  bag::BagReaderOptions ro;
  ro.topics = {"/cam0/image_raw", "/cam1/image_raw", "/imu0"};
  bag::BagReader reader(options.dataset_dir, ro);
  std::map<std::string, std::unique_ptr<rosmsg::MessageDefinitionSet>> defs;
  for (const auto& t : reader.topics()) {
    if (t.message_definition.empty()) throw InputError(options.dataset_dir + ": topic " + t.name + " has no message definition");
    defs[t.name] = std::make_unique<rosmsg::MessageDefinitionSet>(rosmsg::MessageDefinitionSet::parse(t.type, t.message_definition));
  }
  for (const char* needed : {"/cam0/image_raw", "/cam1/image_raw", "/imu0"}) {
    if (!defs.count(needed)) throw InputError(options.dataset_dir + ": the bag has no " + std::string(needed));
  }
  std::map<Timestamp, std::pair<cv::Mat, cv::Mat>> frames;
  bag::BagMessage m;
  while (reader.next(m)) {
    const auto value = rosmsg::CdrCodec(*defs[m.topic]).decode(m.data);
    const Timestamp t = stampOf(value);
    if (m.topic == "/imu0") {
      ImuSample s;
      s.t = t;
      s.gyro = {number(value["angular_velocity"]["x"]), number(value["angular_velocity"]["y"]), number(value["angular_velocity"]["z"])};
      s.accel = {number(value["linear_acceleration"]["x"]), number(value["linear_acceleration"]["y"]), number(value["linear_acceleration"]["z"])};
      in.imu.push_back(s);
      continue;
    }
    const auto& enc = std::get<std::string>(value["encoding"].value);
    const auto w = static_cast<int>(std::get<std::uint64_t>(value["width"].value));
    const auto h = static_cast<int>(std::get<std::uint64_t>(value["height"].value));
    const auto step = static_cast<std::size_t>(std::get<std::uint64_t>(value["step"].value));
    const auto& bytes = std::get<rosmsg::MessageValue::Bytes>(value["data"].value);
    if (enc != "mono8" || bytes.size() < step * static_cast<std::size_t>(h) || step < static_cast<std::size_t>(w)) {
      in.warnings.push_back(m.topic + " at " + std::to_string(t) + ": not a mono8 image, skipped");
      continue;
    }
    cv::Mat img = cv::Mat(h, w, CV_8UC1, const_cast<std::uint8_t*>(bytes.data()), step).clone();
    (m.topic == "/cam0/image_raw" ? frames[t].first : frames[t].second) = img;
  }
  std::vector<std::pair<cv::Mat, cv::Mat>> pairs;
  for (auto& [t, p] : frames) {
    if (p.first.empty() || p.second.empty()) {
      in.warnings.push_back("frame at " + std::to_string(t) + " has no " + (p.first.empty() ? "left" : "right") + " image, skipped");
      continue;
    }
    in.frame_times.push_back(t);
    pairs.push_back(std::move(p));
  }
  std::sort(in.imu.begin(), in.imu.end(), [](const ImuSample& a, const ImuSample& b) { return a.t < b.t; });
  auto shared = std::make_shared<std::vector<std::pair<cv::Mat, cv::Mat>>>(std::move(pairs));
  in.images = [shared](std::size_t i) { return (*shared)[i]; };
  return in;
}

RunInput readEuroc(const OfflineRunOptions& options) {
  auto data = std::make_shared<dataset::EurocDataset>(dataset::EurocDataset::open(options.dataset_dir));
  RunInput in;
  in.calibration = options.calibration_dir.empty() ? data->calibration()
                                                   : dataset::EurocFileReader::readCalibration(options.calibration_dir);
  in.imu = data->imu();
  for (const auto& f : data->stereoFrames()) in.frame_times.push_back(f.t);
  in.warnings = data->warnings();
  in.images = [data](std::size_t i) {
    const auto& f = data->stereoFrames()[i];
    return std::make_pair(data->loadImage(f, 0), data->loadImage(f, 1));
  };
  return in;
}

}  // namespace

OfflineRunSummary runOffline(const OfflineRunOptions& options) {
  using Clock = std::chrono::steady_clock;
  namespace fs = std::filesystem;
  const fs::path p(options.dataset_dir);
  const bool is_bag = fs::exists(p / "metadata.yaml") || p.extension() == ".mcap" || p.extension() == ".db3";
  const RunInput data = is_bag ? readBag(options) : readEuroc(options);
  for (const auto& w : data.warnings) std::cerr << "mcvio run: warning: " << w << "\n";
  if (data.frame_times.empty()) throw InputError(options.dataset_dir + ": no stereo frames to run on");
  if (data.imu.empty()) throw InputError(options.dataset_dir + ": no IMU samples");
  const auto vio_options = options.config_file.empty() ? VioPipelineOptions{} : VioPipelineOptions::fromYamlFile(options.config_file);
  std::filesystem::create_directories(options.output_dir);
  const std::string tum_path = options.output_dir + "/trajectory.tum";
  std::ofstream tum(tum_path);
  if (!tum) throw InputError("cannot write " + tum_path);
  tum << "# t x y z qx qy qz qw  (pose of imu0 in world; t in seconds)\n" << std::setprecision(9) << std::fixed;

  VioPipeline vio(data.calibration, vio_options);
  OfflineRunSummary summary;
  StageStats frontend_ms, backend_ms, features, stereo, landmarks;
  std::size_t keyframes = 0, zero_velocity = 0, not_initialized = 0;
  std::map<std::string, std::size_t> skip_reasons;
  const auto& imu = data.imu;
  std::size_t next_imu = 0;
  ProgressBar bar("run", data.frame_times.size(), options.progress);
  const auto start = Clock::now();
  for (std::size_t i = 0; i < data.frame_times.size(); ++i) {
    const Timestamp t = data.frame_times[i];
    // Everything the IMU measured up to the image time comes first, as on the bus.
    while (next_imu < imu.size() && imu[next_imu].t <= t) vio.addImu(imu[next_imu++]);
    const auto images = data.images(i);
    const auto r = vio.addFrame(t, images.first, images.second);
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
  summary.data_seconds = toSeconds(data.frame_times.back() - data.frame_times.front());

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
      {"warnings", data.warnings}};
  std::ofstream(options.output_dir + "/stats.json") << stats.dump(2) << "\n";
  return summary;
}

}  // namespace mcvio::pipeline
