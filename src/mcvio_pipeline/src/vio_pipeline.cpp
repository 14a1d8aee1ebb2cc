#include "mcvio/pipeline/vio_pipeline.hpp"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/yaml_file.hpp"
#include "shipped_config.hpp"

namespace mcvio::pipeline {

namespace {

VioPipelineOptions fromYaml(const YAML::Node& root, const std::string& where) {
  VioPipelineOptions o;
  if (root.IsNull()) return o;
  if (!root.IsMap()) throw InputError(where + ": expected a map with frontend: and estimator: sections");
  for (const auto& kv : root) {
    const auto key = kv.first.as<std::string>();
    if (key == "frontend") {
      o.frontend = frontend::FrontendOptions::fromYaml(kv.second, where + ": frontend");
    } else if (key == "estimator") {
      o.estimator = estimator::EstimatorOptions::fromYaml(kv.second, where + ": estimator");
    } else if (key == "frontend_gyro_bias_feedback") {
      try {
        o.frontend_gyro_bias_feedback = kv.second.as<bool>();
      } catch (const YAML::Exception&) {
        throw InputError(where + ": key 'frontend_gyro_bias_feedback' must be true or false");
      }
    } else {
      throw InputError(where + ": unknown section '" + key + "' (expected frontend, estimator, frontend_gyro_bias_feedback)");
    }
  }
  return o;
}

}  // namespace

VioPipelineOptions VioPipelineOptions::fromYamlFile(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "pipeline config file");
  // An empty file would run every stage on its compiled-in defaults, not the shipped config: most
  // likely a truncated or wrong file, so say so rather than run something nobody asked for.
  if (root.IsNull())
    throw InputError(path + ": the pipeline config file is empty (expected frontend: and estimator: sections; "
                            "leave out --config for the shipped config)");
  VioPipelineOptions o = fromYaml(root, path);
  o.frontend.resolvePathsFrom(std::filesystem::path(path).parent_path().string());
  return o;
}

VioPipelineOptions VioPipelineOptions::shipped() {
  // Parsed once: the text is compiled in and cannot change.
  static const VioPipelineOptions options = fromYaml(parseYamlText(kShippedConfigYaml, "built-in config/vio_pipeline.yaml"), "built-in config/vio_pipeline.yaml");
  return options;
}

VioPipeline::VioPipeline(const StereoRigCalibration& rig, const VioPipelineOptions& options)
    : tracker_(options.frontend), estimator_(options.estimator, rig), bias_feedback_(options.frontend_gyro_bias_feedback) {
  tracker_.setCalibration(rig);
}

void VioPipeline::addImu(const ImuSample& sample) {
  estimator_.addImu(sample);
  imu_since_frame_.push_back(sample);
}

VioFrameResult VioPipeline::addFrame(Timestamp t, const cv::Mat& left, const cv::Mat& right) {
  std::vector<ImuSample> imu;
  imu.swap(imu_since_frame_);
  return estimate(track(t, left, right, std::move(imu)));
}

TrackedFrame VioPipeline::trackFrame(Timestamp t, const cv::Mat& left, const cv::Mat& right,
                                     std::vector<ImuSample> imu) {
  TrackedFrame f;
  f.index = next_track_index_;
  f.imu = imu;
  f.tracking = track(t, left, right, std::move(imu));
  return f;
}

VioFrameResult VioPipeline::estimateFrame(TrackedFrame frame) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (frame.index != estimated_frames_) {
      throw std::logic_error("VioPipeline::estimateFrame: frame " + std::to_string(frame.index) +
                             " out of order (expected " + std::to_string(estimated_frames_) + ")");
    }
  }
  for (const auto& s : frame.imu) estimator_.addImu(s);
  return estimate(std::move(frame.tracking));
}

void VioPipeline::cancel() {
  std::lock_guard<std::mutex> lock(mutex_);
  cancelled_ = true;
  estimated_cv_.notify_all();
}

frontend::TrackingResult VioPipeline::track(Timestamp t, const cv::Mat& left, const cv::Mat& right,
                                            std::vector<ImuSample> imu) {
  const std::size_t index = next_track_index_++;
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();
  if (index >= 2) {
    std::unique_lock<std::mutex> lock(mutex_);
    estimated_cv_.wait(lock, [&] { return cancelled_ || estimated_frames_ + 2 > index; });
    if (cancelled_) throw std::runtime_error("VioPipeline: cancelled while waiting for the estimator");
    const auto it = std::find_if(bias_after_.begin(), bias_after_.end(),
                                 [&](const auto& b) { return b.first == index - 2; });
    if (it == bias_after_.end()) throw std::logic_error("VioPipeline: gyro bias of frame " + std::to_string(index - 2) + " is gone");
    bias = it->second;
  }
  tracker_.setGyroBias(bias_feedback_ ? bias : Eigen::Vector3d::Zero());
  frontend::StereoInput in;
  in.t = t;
  in.left = left;
  in.right = right;
  in.imu = std::move(imu);
  return tracker_.track(in);
}

VioFrameResult VioPipeline::estimate(frontend::TrackingResult tracking) {
  VioFrameResult r;
  r.tracking = std::move(tracking);
  if (r.tracking.ok()) {
    r.estimate = estimator_.addFrame(r.tracking.features);
    r.estimated = true;
    if (r.estimate.status == estimator::EstimatorStatus::kTracking) gyro_bias_ = r.estimate.bias.gyro;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  bias_after_.emplace_back(estimated_frames_, gyro_bias_);
  // The frontend is at most two frames ahead of the estimator.
  while (bias_after_.size() > 4) bias_after_.pop_front();
  ++estimated_frames_;
  estimated_cv_.notify_all();
  return r;
}

}  // namespace mcvio::pipeline
