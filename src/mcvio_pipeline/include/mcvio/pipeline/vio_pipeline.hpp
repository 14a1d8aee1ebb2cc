#pragma once
#include <string>
#include <vector>

#include "mcvio/core/stereo_rig_calibration.hpp"
#include "mcvio/estimator/estimator_options.hpp"
#include "mcvio/estimator/estimator_output.hpp"
#include "mcvio/estimator/sliding_window_estimator.hpp"
#include "mcvio/frontend/feature_tracker.hpp"
#include "mcvio/frontend/frontend_options.hpp"

namespace mcvio::pipeline {

/// Options of the whole VIO: one YAML file with a `frontend:` and an `estimator:` section, each
/// holding that stage's options (every key optional; unknown keys are errors).
struct VioPipelineOptions {
  frontend::FrontendOptions frontend;
  estimator::EstimatorOptions estimator;
  static VioPipelineOptions fromYamlFile(const std::string& path);
};

/// What one stereo frame produced.
struct VioFrameResult {
  frontend::TrackingResult tracking;
  estimator::EstimatorOutput estimate;
  bool estimated = false;  ///< false when the frontend skipped the frame
};

/// Frontend and estimator for one stereo stream, fed in time order. The offline `mcvio run` and
/// the DDS components use these same classes, in the same order, so both give the same answer.
class VioPipeline {
 public:
  VioPipeline(const StereoRigCalibration& rig, const VioPipelineOptions& options);
  /// An IMU sample; it goes to the estimator now and to the frontend with the next frame.
  void addImu(const ImuSample& sample);
  /// A stereo pair (mono8, calibrated size); returns the tracking result and the estimate.
  VioFrameResult addFrame(Timestamp t, const cv::Mat& left, const cv::Mat& right);

 private:
  frontend::FeatureTracker tracker_;
  estimator::SlidingWindowEstimator estimator_;
  std::vector<ImuSample> imu_since_frame_;
};

}  // namespace mcvio::pipeline
