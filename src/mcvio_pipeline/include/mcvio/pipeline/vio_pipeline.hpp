#pragma once
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <string>
#include <utility>
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
  /// Track frame k with the gyro bias the estimator had after frame k-2 (key
  /// `frontend_gyro_bias_feedback`). Off by default: the DDS frontend has no bias topic, and the
  /// DDS and offline paths must see the same input; the bias moves the KLT prediction by well
  /// under a pixel per frame.
  bool frontend_gyro_bias_feedback = false;
  static VioPipelineOptions fromYamlFile(const std::string& path);
  /// The shipped configuration, config/vio_pipeline.yaml of this package, compiled in: the
  /// built-in defaults with the settings measured best on EuRoC-like data (IMU noise inflation,
  /// right camera only in anchor frames). What `mcvio run`, `mcvio backend` and `mcvio demo` use
  /// without --config.
  static VioPipelineOptions shipped();
};

/// What one stereo frame produced.
struct VioFrameResult {
  frontend::TrackingResult tracking;
  estimator::EstimatorOutput estimate;
  bool estimated = false;  ///< false when the frontend skipped the frame
};

/// The frontend's result for one frame on its way to the estimator (two-stage use).
struct TrackedFrame {
  std::size_t index = 0;             ///< frame number, 0 for the first frame given to the pipeline
  std::vector<ImuSample> imu;        ///< IMU samples the estimator takes before this frame
  frontend::TrackingResult tracking;
};

/// Frontend and estimator for one stereo stream, fed in time order. The offline `mcvio run` and
/// the DDS components use these same classes, in the same order, so both give the same answer.
///
/// The frontend subtracts the estimator's gyro bias before it integrates the gyro. Frame k is
/// tracked with the bias estimated at frame k-2 (zero until the estimator tracks), so frame k can
/// be tracked while the estimator still solves frame k-1 and both ways of use below give
/// bit-identical estimator input:
///  - sequential, one thread: addImu() for each sample, addFrame() for each stereo pair;
///  - two stages on two threads: trackFrame() on one, estimateFrame() on the other, each in frame
///    order. trackFrame(k) waits until estimateFrame(k-2) has returned.
/// Do not mix the two ways on one instance.
class VioPipeline {
 public:
  VioPipeline(const StereoRigCalibration& rig, const VioPipelineOptions& options);
  /// An IMU sample; it goes to the estimator now and to the frontend with the next frame.
  void addImu(const ImuSample& sample);
  /// A stereo pair (mono8, calibrated size); returns the tracking result and the estimate.
  VioFrameResult addFrame(Timestamp t, const cv::Mat& left, const cv::Mat& right);

  /// Frontend stage: tracks the next frame with `imu`, the samples after the previous frame up to
  /// `t` (time order). The result carries them on to estimateFrame(). Blocks until the estimate of
  /// two frames back is done; throws std::runtime_error once cancel() was called.
  TrackedFrame trackFrame(Timestamp t, const cv::Mat& left, const cv::Mat& right, std::vector<ImuSample> imu);
  /// Estimator stage: feeds the frame's IMU samples, then its features (when the frontend kept
  /// the frame) to the estimator. Frames must come in trackFrame() order.
  VioFrameResult estimateFrame(TrackedFrame frame);
  /// Wakes and fails a trackFrame() waiting for an estimate that will not come (the estimator
  /// thread stopped).
  void cancel();

 private:
  frontend::TrackingResult track(Timestamp t, const cv::Mat& left, const cv::Mat& right,
                                 std::vector<ImuSample> imu);
  VioFrameResult estimate(frontend::TrackingResult tracking);

  frontend::FeatureTracker tracker_;
  estimator::SlidingWindowEstimator estimator_;
  std::vector<ImuSample> imu_since_frame_;
  std::size_t next_track_index_ = 0;  ///< frontend side
  std::size_t estimated_frames_ = 0;  ///< estimator side; guarded by mutex_ for the frontend's reads
  Eigen::Vector3d gyro_bias_ = Eigen::Vector3d::Zero();  ///< estimator side: latest tracking estimate
  bool bias_feedback_ = false;
  /// (frame index, gyro bias after that frame), the last few, for the frontend.
  std::deque<std::pair<std::size_t, Eigen::Vector3d>> bias_after_;
  bool cancelled_ = false;
  std::mutex mutex_;
  std::condition_variable estimated_cv_;
};

}  // namespace mcvio::pipeline
