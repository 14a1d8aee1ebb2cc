#pragma once
#include <string>

#include "mcvio/conflict/conflict_options.hpp"
#include "mcvio/core/camera_model.hpp"

namespace YAML {
class Node;
}

namespace mcvio::estimator {

/// Robust loss on the visual residuals.
enum class RobustLoss { kNone, kHuber, kCauchy };

/// Options of SlidingWindowEstimator. Defaults suit a EuRoC-like stereo rig at 20 Hz with a
/// 200 Hz IMU and a feature-level input (about 150 tracked features per frame).
/// Every field can be set from YAML under the same key; validate() names the offending key.
struct EstimatorOptions {
  // Windows.
  int imu_window_size = 5;        ///< N: newest frames with full state (pose, speed, biases)
  int keyframe_window_size = 5;   ///< M: older keyframes kept with pose only
  double keyframe_parallax_px = 10.0;        ///< mean parallax to the last keyframe that makes a keyframe
  double keyframe_tracked_fraction = 0.5;    ///< fewer landmarks of the last keyframe still tracked -> keyframe

  // Visual measurements.
  double observation_sigma_px = 1.0;         ///< pixel noise of a feature (whitening)
  /// How pixels whiten each visual residual (which lives on the normalised plane): the focal
  /// length at the centre, or the lens's own 2x2 pixel Jacobian where the feature was seen
  /// (CameraModel::pixelJacobianAt; needs the estimator built from the rig's calibration). A wide
  /// lens's edge pixel covers much more of the normalised plane than its centre pixel, and more
  /// radially than across (a 140-degree double sphere's at 60 degrees 2.6x), so one scale trusts
  /// its edges too much; on EuRoC's 77-degree radtan lens (0.68x in the corners) a local scale
  /// measured no better, so wide_angle keeps the centre's for pinhole lenses.
  PixelScale pixel_scale = PixelScale::kWideAngle;
  RobustLoss robust_loss = RobustLoss::kHuber;
  double robust_loss_scale_px = 3.0;         ///< where the robust loss starts to bend [px] (about 3 sigma)
  double outlier_threshold_px = 4.0;         ///< observations with larger error after a solve are dropped
  /// ... and with them their landmark (it starts again from the track's next stereo pair). A
  /// track that slid off its corner, or onto something that moves, gives such an observation
  /// frame after frame, and each pulls one solve before it is dropped.
  bool outlier_drops_landmark = false;
  double min_depth_m = 0.1;                  ///< landmarks closer than this are rejected
  double max_depth_m = 40.0;                 ///< landmarks farther than this are rejected
  double min_stereo_disparity_px = 0.5;      ///< stereo pairs with less disparity give no depth
  /// Right-camera observations enter in every frame (true) or only in a landmark's anchor frame,
  /// where they fix its depth (false: about half the visual residuals, faster).
  bool right_camera_in_all_frames = true;
  /// When the oldest keyframe leaves, a landmark anchored in it that the IMU window still tracks
  /// is split: its observations in the keyframe window go into the prior with the keyframe, and it
  /// goes on from its current estimate, anchored in the IMU window. Off: those observations are
  /// dropped and only the estimate goes on. With a keyframe every frame or two (fast motion, a
  /// close view) the window otherwise forgets everything older than its own half second. Not
  /// while a conflict is resolved: a moving landmark's history, once in the prior, could not be
  /// eliminated with it (a rendered slow object, seed 4: 0.130 m splitting through, 0.034 m pausing);
  /// unless only the frontend found the motion (ConflictOptions::frontend_conflict_keeps_history).
  bool marginalize_tracked_landmark_history = false;

  // IMU. Multiplying the datasheet densities absorbs unmodelled effects on real sensors.
  double gravity_magnitude = 9.81;           ///< [m/s^2], world z up
  double imu_noise_inflation = 1.0;          ///< factor on the white-noise densities
  double imu_random_walk_inflation = 1.0;    ///< factor on the bias random walks
  double repropagate_gyro_bias_change = 0.01;   ///< [rad/s] re-integrate beyond this bias change
  double repropagate_accel_bias_change = 0.1;   ///< [m/s^2]
  double max_imu_gap_s = 0.1;                ///< larger holes in the IMU stream reset the estimator

  // Solver.
  int max_iterations = 8;
  double function_tolerance = 1e-4;          ///< Ceres stops when the relative cost change is below this
  /// The same while a motion conflict is suspected or open: eliminated landmarks and an inertial
  /// state moving away from vision take the solution further than one iteration goes. Not in
  /// `reference` mode, which stays the plain VIO whatever the detectors report.
  double conflict_function_tolerance = 1e-4;
  /// Stop right after an accepted step whose actual cost decrease matched the linearised model's
  /// prediction to within the function tolerance (times the cost). Ceres' own test solves once more
  /// to find the next step tiny; in a settled window started from the IMU prediction that second
  /// linear solve is nearly always wasted.
  bool stop_on_model_agreement = true;
  /// Seconds after (re)initialisation during which the solve runs to Ceres' own convergence: with
  /// velocity, gravity and biases still weakly determined, LM damping slows convergence while each
  /// damped step still matches its model.
  double model_agreement_settle_s = 3.0;
  /// Wall-clock budget per solve. A guard only by default: when it cuts a solve the result depends
  /// on machine load, so offline and live runs of the same input would differ.
  double max_solver_time_s = 1.0;
  int num_threads = 1;
  bool compute_covariance = true;            ///< pose covariance of the newest frame in the output

  // Initialisation.
  double init_window_s = 1.0;                ///< IMU history examined at start
  double static_gyro_std_max = 0.02;         ///< [rad/s] below: the device is still
  double static_accel_std_max = 0.15;        ///< [m/s^2]
  double init_position_sigma = 1e-3;         ///< [m] prior on the first position (gauge)
  double init_yaw_sigma = 1e-3;              ///< [rad] prior on the first yaw (gauge)
  double init_roll_pitch_sigma = 0.02;       ///< [rad] gravity alignment uncertainty, static start
  double init_roll_pitch_sigma_moving = 0.1; ///< [rad] moving start (mean accel includes motion)
  double init_velocity_sigma_static = 0.01;  ///< [m/s] static start
  double init_velocity_sigma_moving = 2.0;   ///< [m/s] moving start
  double init_gyro_bias_sigma_static = 0.005;  ///< [rad/s] bias from stillness
  double init_gyro_bias_sigma_moving = 0.05;   ///< [rad/s]
  double init_accel_bias_sigma = 0.2;        ///< [m/s^2]

  // Zero-velocity detection.
  bool zero_velocity_enabled = true;
  double zero_velocity_max_disparity_px = 0.5;  ///< mean feature motion between consecutive frames
  double zero_velocity_gyro_std_max = 0.01;     ///< [rad/s] over the inter-frame IMU samples
  double zero_velocity_accel_std_max = 0.1;     ///< [m/s^2]
  double zero_velocity_sigma = 0.01;            ///< [m/s] constraint strength

  // Failure detection (any violation resets with a log line).
  double max_speed_mps = 30.0;
  double max_gyro_bias = 0.5;                ///< [rad/s]
  double max_accel_bias = 2.0;               ///< [m/s^2]
  double max_position_jump_m = 1.0;          ///< optimised vs IMU-predicted position of the newest frame
  double max_time_without_vision_s = 3.0;    ///< IMU-only propagation longer than this resets
                                             ///< (not inside an IMU-dominated conflict interval)

  /// Motion-conflict detection and resolution (YAML section `conflict:`; mode `reference` by default).
  conflict::ConflictOptions conflict;

  /// Throws mcvio::InputError naming the key when a value is out of range.
  void validate() const;
  /// Reads the keys present in `node` (others keep their value) and validates. `context` names the
  /// source (file path) in error messages.
  static EstimatorOptions fromYaml(const YAML::Node& node, const std::string& context = "estimator options");
  /// Loads a YAML file; the options may sit at the top level or under a key `estimator`.
  static EstimatorOptions fromYamlFile(const std::string& path);
};

}  // namespace mcvio::estimator
