#pragma once
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <deque>
#include <memory>
#include <opencv2/core/mat.hpp>
#include <optional>
#include <vector>

#include "mcvio/core/stereo_rig_calibration.hpp"
#include "mcvio/frontend/frontend_options.hpp"
#include "mcvio/frontend/gyro_integrator.hpp"
#include "mcvio/frontend/motion_consistency_checker.hpp"
#include "mcvio/frontend/stereo_input.hpp"
#include "mcvio/frontend/track_reidentifier.hpp"
#include "mcvio/frontend/tracking_result.hpp"

namespace mcvio::frontend {

/// Stereo KLT feature tracker: grid-bucketed FAST corners in the left image, pyramidal KLT
/// between frames with gyro-predicted initial flow and a forward-backward check, left-right
/// KLT with an epipolar check, and a RANSAC motion check that labels every track
/// kConsistent / kInconsistent with the dominant camera motion.
///
/// Photometric failures (KLT lost, forward-backward error, leaving the image) drop a track;
/// geometric disagreement does not: inconsistent tracks stay and are published with their
/// label, so the backend sees motion-conflict evidence. A new id is given to every new track,
/// except, with FrontendOptions::reidentify_lost_tracks, a lost one the TrackReidentifier
/// recognises: it gets its old id back.
/// Bad frames are skipped with a status and message; the tracker keeps its state.
///
/// Usage (one instance per stereo stream; not thread-safe, call from one thread):
///   mcvio::frontend::FeatureTracker tracker(FrontendOptions::fromFile("config/frontend.yaml"));
///   tracker.setCalibration(rig);                  // mcvio::StereoRigCalibration
///   TrackingResult r = tracker.track({t, left, right, imu_since_last_frame});
///   if (!r.ok()) log(r.message); else publish(r.features);
///   cv::Mat vis = drawTracks(left, tracker.trackHistories());
class FeatureTracker {
 public:
  /// Throws mcvio::InputError if the options are invalid or a mask image cannot be read.
  explicit FeatureTracker(const FrontendOptions& options = FrontendOptions());

  /// Sets (or replaces) the stereo calibration (cam0 = left, cam1 = right, T_BC of each).
  /// Throws mcvio::InputError if it is unusable (different resolutions, no baseline, non-rigid
  /// extrinsics, a mask of another size than its camera). Replacing it resets the tracks.
  void setCalibration(const StereoRigCalibration& calibration);
  bool hasCalibration() const { return calibration_.has_value(); }

  /// Gyro bias subtracted before integration (the backend's estimate) [rad/s].
  void setGyroBias(const Eigen::Vector3d& bias) { gyro_bias_ = bias; }

  /// Processes one stereo frame. Never throws on bad input: see TrackingResult::status.
  TrackingResult track(const StereoInput& input);

  /// Recent positions of the live tracks, for drawing.
  std::vector<TrackHistory> trackHistories() const;

  /// Forgets all tracks and the previous frame (ids keep increasing).
  void reset();

  const FrontendOptions& options() const { return options_; }
  /// Camera `camera`'s mask (255 where no feature is tracked), empty without one; for drawTracks.
  const cv::Mat& mask(int camera) const { return masks_[static_cast<std::size_t>(camera)]; }
  std::uint32_t framesProcessed() const { return frame_index_; }

 private:
  struct Track {
    std::uint64_t id = 0;
    cv::Point2f left;
    Eigen::Vector2d left_norm{0, 0};
    bool stereo = false;
    cv::Point2f right;
    Eigen::Vector2d right_norm{0, 0};
    bool has_point = false;
    Eigen::Vector3d point{0, 0, 1};  // cam0 coordinates, this frame
    TrackLabel label = TrackLabel::kUnknown;
    std::deque<cv::Point2f> history;
  };

  void prepareImage(const cv::Mat& raw, cv::Mat* out) const;
  /// True where camera `camera`'s mask (FrontendOptions::mask0 / mask1) holds no feature.
  bool masked(int camera, const cv::Point2f& px) const;
  void buildPyramid(const cv::Mat& image, std::vector<cv::Mat>* pyramid) const;
  void trackTemporal(const std::vector<cv::Mat>& cur_pyr, const Eigen::Matrix3d* R_cur_prev,
                     TrackingStats* stats);
  void detectNew(const cv::Mat& image, Timestamp t, TrackingStats* stats);
  void matchStereo(const std::vector<cv::Mat>& left_pyr, const std::vector<cv::Mat>& right_pyr,
                   TrackingStats* stats);

  FrontendOptions options_;
  std::optional<StereoRigCalibration> calibration_;
  std::unique_ptr<MotionConsistencyChecker> checker_;
  GyroIntegrator gyro_;
  Eigen::Vector3d gyro_bias_ = Eigen::Vector3d::Zero();

  bool has_prev_ = false;
  Timestamp prev_t_ = 0;
  std::vector<cv::Mat> prev_left_pyr_;
  cv::Mat prev_left_;  ///< the prepared image, where lost tracks are described
  TrackReidentifier reidentifier_;
  std::vector<std::pair<std::uint64_t, cv::Point2f>> lost_;  ///< this frame's, at their last position
  std::vector<cv::Point2f> kept_prev_;  ///< the tracks kept this frame, at their previous position
  std::vector<Track> tracks_;
  std::uint64_t next_id_ = 1;
  std::uint32_t frame_index_ = 0;
  cv::Mat occupancy_;  // detection mask buffer, reused
  std::array<cv::Mat, 2> masks_;  ///< 255 where no feature may be; empty = no mask
};

}  // namespace mcvio::frontend
