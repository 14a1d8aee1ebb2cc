#include "mcvio/pipeline/vio_pipeline.hpp"

#include <yaml-cpp/yaml.h>

#include "mcvio/core/input_error.hpp"

namespace mcvio::pipeline {

VioPipelineOptions VioPipelineOptions::fromYamlFile(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw InputError(path + ": " + e.what());
  }
  VioPipelineOptions o;
  for (const auto& kv : root) {
    const auto key = kv.first.as<std::string>();
    if (key == "frontend") {
      o.frontend = frontend::FrontendOptions::fromYaml(kv.second, path + ": frontend");
    } else if (key == "estimator") {
      o.estimator = estimator::EstimatorOptions::fromYaml(kv.second, path + ": estimator");
    } else {
      throw InputError(path + ": unknown section '" + key + "' (expected frontend, estimator)");
    }
  }
  return o;
}

VioPipeline::VioPipeline(const StereoRigCalibration& rig, const VioPipelineOptions& options)
    : tracker_(options.frontend), estimator_(options.estimator, rig) {
  tracker_.setCalibration(rig);
}

void VioPipeline::addImu(const ImuSample& sample) {
  estimator_.addImu(sample);
  imu_since_frame_.push_back(sample);
}

VioFrameResult VioPipeline::addFrame(Timestamp t, const cv::Mat& left, const cv::Mat& right) {
  VioFrameResult r;
  frontend::StereoInput in;
  in.t = t;
  in.left = left;
  in.right = right;
  in.imu.swap(imu_since_frame_);
  r.tracking = tracker_.track(in);
  if (!r.tracking.ok()) return r;
  r.estimate = estimator_.addFrame(r.tracking.features);
  r.estimated = true;
  // The frontend predicts flow with the gyro: give it the estimator's bias once it has one.
  if (r.estimate.status == estimator::EstimatorStatus::kTracking) tracker_.setGyroBias(r.estimate.bias.gyro);
  return r;
}

}  // namespace mcvio::pipeline
