#pragma once
#include <string>

namespace YAML {
class Node;
}

namespace mcvio::conflict {

/// How the backend answers a detected motion conflict (DESIGN.md "The algorithm").
enum class ResolutionMode {
  kReference,  ///< detect and report only; the reference VIO is unchanged
  kImu,        ///< IMU-dominated: drop conflicting visual residuals, hold the biases
  kSelective,  ///< eliminate the landmarks that move, keep the static ones
  kAuto,       ///< selective while enough static landmarks remain, IMU-dominated otherwise
};

const char* toString(ResolutionMode mode);
/// "reference", "imu", "selective" or "auto"; throws mcvio::InputError naming `context` otherwise.
ResolutionMode resolutionModeFromString(const std::string& text, const std::string& context = "conflict mode");

/// Options of motion-conflict detection and resolution. Every key is optional in YAML (section
/// `conflict:` of the estimator options); unknown keys are errors.
struct ConflictOptions {
  ResolutionMode mode = ResolutionMode::kReference;

  // --- detection -------------------------------------------------------------------------
  /// Frames between the reference frame r and the current frame k. Over a longer horizon a
  /// conflicting acceleration moves the IMU prediction further from vision (grows with dt^2),
  /// while noise grows more slowly.
  int horizon_frames = 10;
  double observation_sigma_px = 1.0;   ///< pixel noise of a tracked feature
  double stereo_sigma_px = 0.5;        ///< disparity noise, for the stereo depth uncertainty
  /// Uncertainty of the estimated velocity and attitude at r and of the biases; they spread the
  /// IMU prediction over the horizon.
  double velocity_sigma_mps = 0.015;
  double attitude_sigma_rad = 0.01;
  /// The attitude uncertainty the landmark detector's prediction carries (0: attitude_sigma_rad).
  /// Through gravity it spreads every landmark's predicted pixel by the same few pixels over the
  /// horizon; a slow object's tracks drift by no more than that.
  double landmark_attitude_sigma_rad = 0.0;
  double accel_bias_sigma = 0.02;      ///< [m/s^2]
  double gyro_bias_sigma = 0.002;      ///< [rad/s]
  /// Propagated-state detector: 6-dof chi-square threshold on IMU-vs-vision relative motion.
  double propagated_chi2_threshold = 20.0;
  /// Landmark detector: 2-dof chi-square threshold on a normalised reprojection residual.
  double landmark_chi2_threshold = 13.8;
  int min_landmarks_tested = 12;       ///< fewer: the landmark detector abstains
  /// A partial conflict needs at least this many disagreeing landmarks, this share of those
  /// tested, and this share of the group explained by one rigid motion.
  int partial_min_count = 8;
  double partial_min_fraction = 0.08;
  double min_coherence = 0.6;
  double coherence_sigma_m = 0.02;     ///< 3D tolerance floor of the rigid-motion fit
  /// Selective and auto: tracks already found moving keep an open partial conflict open while at
  /// least this many of them, and this share of the frame's features, are still in view and have
  /// disagreed (a landmark verdict against the IMU or, once found moving, against the motion the
  /// other tracks give; or the frontend's label) within the last horizon_frames.
  /// Stricter than the detection: a few static tracks misclassified during a large occlusion stay
  /// in view after it and would hold the interval for seconds.
  int hold_moving_min_count = 8;
  double hold_moving_min_fraction = 0.08;
  /// A track the frontend checked on this frame and found consistent leaves the hold's memory
  /// (unless a landmark test disagreed on this frame too). The memory bridges frames on which the
  /// landmark tests cannot run, e.g. before the horizon's reference frame has any static track;
  /// the frontend checks every track on every frame. The rendered laptop's tracks that slid onto
  /// the background as it left the view, labelled consistent from then on, held the
  /// self-occlusion of seed 4 open for 0.5 s after the laptop had gone (online FPR 0.044; 0.015
  /// with the option, the exit hysteresis alone; every other rendered run of seeds 1-5 the same).
  bool frontend_agreement_ends_hold = true;
  /// Frontend detector: the frontend checks every track, stereo or not, against the image motion
  /// the gyro and the dominant translation explain, and labels the rest inconsistent. A close
  /// occluder (a carried laptop 0.3 m in front of the lens, 170 px of disparity) finds no stereo
  /// match, so the landmark detector cannot test its tracks, but the frontend labels them all: a
  /// frame with at least this many labelled tracks, and this share of those checked, is evidence
  /// of a partial conflict, and one with min_landmarks_tested checked tracks counts as tested
  /// (outside IMU-dominated intervals, where a cabin filling the view is the dominant motion).
  /// Frames at 8 tracks / 4 % on the rendered 30 s sequences (image-level bench), with a label:
  /// self-occlusion 238 of 240, pedestrian 132 of 215 (100 at 8 %), elevator 0 of 239; without:
  /// 1 of 361, 0 of 386, 9 of 362 (7 in the elevator's first 1.3 s, before the warm-up ends, 2
  /// single frames); clean office, overlay base (real IMU) and real V1_01 excerpt: 0. From 8 % to
  /// 4 % the image-level pedestrian's online TPR went from 0.48 to 0.65 and its ATE from 0.022 to
  /// 0.021 m; no other figure moved.
  bool frontend_evidence = true;
  int frontend_min_count = 8;
  double frontend_min_fraction = 0.04;
  /// A labelled group under this score (the lesser of its count / frontend_min_count and its
  /// share / frontend_min_fraction) is evidence only from its second frame in a row, so it opens
  /// an interval on its third (inside an open interval it counts from its first). Tracks on an
  /// occluding edge slide along the background, and on clean frames a few of them reach the minima
  /// for a frame or two (the rendered elevators of seeds 5 and 9: 8 of 184-193 tracks on two
  /// frames, then 3-7, opened false intervals of 6-8 frames). A conflicting object's group grows:
  /// a carried laptop's first labelled frame can be marginal (8 of 47 checked), its second scores
  /// 16, so its interval opens one frame later than without this. 1: off.
  double frontend_marginal_score = 1.5;
  /// The frontend's labels need no warm-up after an IMU-dominated interval: they compare tracks
  /// with the gyro and each other, not with the velocity the interval drifted (what the warm-up
  /// waits out for the other tests). A carried laptop held still gives the landmark test nothing
  /// to see: its interval closed on quiet frames with 165 of 230 tracks labelled, and the warm-up
  /// left it undetected for 2 s (anisotropic self-occlusion, seed 8). The warm-up after a
  /// (re)initialisation stays: a moving start's first labels are noise.
  bool frontend_evidence_after_imu_exit = true;
  /// Region-split detector (RegionSplitDetector): the image of frame k cut at the quartiles and
  /// the median of x and y, the two sides' vision-only motions compared (6-dof chi-square). Above
  /// this, the landmarks are also tested against the motion of the side closer to the IMU, which
  /// is far more precise than the IMU prediction, and that test's verdicts are used when it finds
  /// more disagreeing landmarks. A slow object filling half the view (feature level, 0.08 m/s)
  /// moves each track by less than the IMU test's spread but bends the motion of its side: its
  /// landmarks went unnoticed for seconds, the interval closed, reopened whole-view and went
  /// IMU-dominated (auto, seeds 1-3: 0.121 / 0.053 / 0.191 m; with the split at 60: 0.043 / 0.037 /
  /// 0.041 m). Clean feature-level frames (seeds 1-3, 3360):
  /// median 11, 99 % under 34, 4 single frames over 60 (the largest 116), no interval.
  /// 0 turns it off.
  double split_chi2_threshold = 60.0;
  /// The region split firing beside a side that agrees with the IMU on this many frames in a row
  /// is a partial conflict on its own, however few of the group's landmarks fail their test one by
  /// one: a rendered slow object had the split at 60-230 for 18 frames (0.9 s) before 10 of its
  /// tracks did. Clean frames: feature level 4 single frames over 60 in 3360; rendered 30 s
  /// sequences at most 30 outside the conflicts, but three in a row after the vehicle's ride
  /// (seed 2), hence 4. 0: off.
  int split_min_frames = 4;
  /// Above this share of disagreeing landmarks the conflict covers the whole view.
  double whole_view_fraction = 0.6;
  /// Frames after (re)initialisation before the detectors may report evidence: the first
  /// velocity and bias estimates are still settling.
  int warmup_frames = 40;
  /// The IMU prediction uses the biases estimated this many frames before the newest conflict-free
  /// frame: inside a conflict the estimator bends the accelerometer bias to explain the missing
  /// motion, and a prediction with that bias would agree with vision. Outside `reference`, an
  /// estimate also needs this many frames without a conflict after it: the frames just before an
  /// interval bent the bias before it was found.
  int bias_reference_lag_frames = 40;
  /// A bias estimate becomes the reference only once every later estimate (over the lag) stayed
  /// within this many accel_bias_sigma / gyro_bias_sigma of it. Estimates that are still moving
  /// (the first seconds of motion on a real IMU) would otherwise be frozen into the reference at
  /// the next interval and keep it open.
  double bias_reference_max_change_sigmas = 5.0;
  /// Bias-drift detector: a cabin easing into a long ride accelerates too gently for the horizon's
  /// tests, and the estimator explains the acceleration vision does not see by bending its
  /// accelerometer bias. The newest estimate moving this many accel_bias_sigma away from the
  /// reference bias (above) is evidence of a whole-view conflict. 0 turns it off. Clean
  /// feature-level runs stay within 0.03 m/s^2 of it once the detector arms; a 20 / 30 s
  /// elevator ride passes 0.05 m/s^2 (2.5 sigma) 1.3 / 2.3 s after it starts. Inside the
  /// IMU-dominated interval it opens, the conflicting frame accelerating at least as fast
  /// (its velocity changing by that much per second over bias_reference_lag_frames) keeps it open.
  double bias_drift_sigmas = 2.5;
  /// Frames after (re)initialisation before the bias-drift detector arms: the first estimates of
  /// a moving start still converge by more than its limit.
  int bias_drift_arm_frames = 200;
  /// Consecutive frames over the limit before the drift is evidence. A ride the horizon's tests
  /// can see has opened its interval by then; a slow object's pull bends the bias for a moment.
  int bias_drift_min_frames = 20;
  /// A bend this many times the limit is evidence after `bias_drift_fast_frames` frames (0: off),
  /// when at least auto_min_tested_landmarks were tested: a cabin or vehicle starting briskly
  /// bends the bias that far before the horizon's tests fire (feature level: 0.075 m/s^2 reached
  /// 0.15-0.7 s before them), while a slow object's pull stays under 0.06 m/s^2 and clean runs
  /// under 0.03.
  double bias_drift_fast_factor = 1.5;
  int bias_drift_fast_frames = 2;
  /// Slow bias drift: a long ride eases in so gently (a 40 s elevator: 0.126 m/s^2 at its peak,
  /// 10 s after the start) that the bias bends no faster than the reference above follows it.
  /// Against the estimate of this many frames before, with no interval in between, the bend
  /// still shows; over bias_drift_long_sigmas accel_bias_sigma for bias_drift_min_frames frames it
  /// opens a whole-view interval that holds that earlier bias and rewinds to where the bend began.
  /// Feature-level clean runs (seeds 1-9, 60 s) stay within 0.040 m/s^2 over 200 frames; the 40 s
  /// rides of seeds 1-9 pass 0.07 m/s^2 4.3-6 s after they start. A real IMU's estimate wanders
  /// more (see the image pipeline's config). 0 frames: off.
  int bias_drift_long_frames = 200;
  double bias_drift_long_sigmas = 3.5;
  int enter_frames = 2;                ///< consecutive frames with evidence to open an interval
  int exit_frames = 5;                 ///< consecutive clean frames to close it (0.25 s at 20 Hz)
  /// ... or, inside an IMU-dominated interval, this many consecutive clean frames, each with an
  /// evidence score under `exit_quiet_score`: a ride that has plainly ended (0: off; see
  /// ConflictIntervalTracker). Not in selective intervals: a slow object's tracks, out of the
  /// tests once found moving, hold its interval again a frame or two after a quiet pair.
  int exit_quiet_frames = 2;
  double exit_quiet_score = 0.6;
  /// In hindsight an interval starts where its evidence began to build up: back from the first
  /// frame of evidence over the frames whose evidence score (the detector statistics relative to
  /// their thresholds; 1 = a detector fires) stayed at least this high ...
  double onset_min_score = 0.1;
  int onset_lookback_frames = 60;      ///< ... and at most this many frames back

  // --- resolution ------------------------------------------------------------------------
  /// Selective: disagreeing verdicts (net of agreeing ones) before a track is eliminated.
  int selective_strikes = 2;
  /// Selective: the frontend's inconsistent label counts as a disagreeing verdict.
  bool use_frontend_labels = true;
  /// Selective and auto: the frontend's labels eliminate tracks outside conflict intervals too
  /// (the same strikes): a pedestrian's tracks otherwise pull the pose for seconds before enough
  /// of them disagree to open an interval. Rendered 30 s sequences, auto, seeds 1-3: pedestrian
  /// 0.0215 / 0.0137 / 0.0220 -> 0.0190 / 0.0113 / 0.0186 m, clean office 0.0166 / 0.0083 / 0.0157
  /// -> 0.0156 / 0.0070 / 0.0151 m, elevator 0.374 / 0.295 / 0.231 -> 0.304 / 0.235 / 0.276 m,
  /// vehicle 0.670 / 1.497 / 1.883 -> 0.617 / 1.672 / 1.667 m. (Before the region split counted
  /// on the opening frame, it sent the slow object of seed 3 IMU-dominated: 0.053 -> 0.142 m.)
  /// The feature-level simulator has no frontend labels: no change there.
  bool frontend_labels_outside_conflicts = true;
  /// ... on a frame outside an interval only when the frontend labels at least this many tracks
  /// on it (inside an interval every label counts). 1: every label.
  int frontend_labels_outside_min_count = 1;
  /// ... except for this many frames after an interval has closed, when every label counts again:
  /// the tracks a moving object leaves behind as it goes.
  int frontend_labels_after_conflict_frames = 0;
  /// Selective: while a conflict is suspected or open, a landmark created after it began (or on the
  /// frame before: an occluder's tracks appear one frame before they can disagree) stays out
  /// of the estimate until the landmark detector has found it consistent (it needs the horizon to
  /// be tested at all). A walking pedestrian keeps bringing new tracks whose pull on the pose came
  /// before any test could eliminate them.
  bool new_landmark_probation = true;
  /// ... and it is let in after this many consecutive agreeing tests: a pedestrian's track can
  /// agree once while it walks along the line of sight (feature-level pedestrian, seeds 1-3: 1 test
  /// 0.135 / 0.031 / 0.096 m, 3 tests 0.085 / 0.019 / 0.047 m, 5 tests 0.087 / 0.018 / 0.064 m).
  int probation_agreeing_tests = 3;
  /// Auto: selective needs this many landmarks left that agree with the IMU.
  int auto_min_static_landmarks = 15;
  /// Auto: IMU-dominated (which drops every visual residual) needs at least this many landmarks in
  /// the test. With fewer, e.g. behind a close occluder whose own features find no stereo match,
  /// the whole-view evidence rests on a handful of points and selective keeps what vision is left.
  int auto_min_tested_landmarks = 30;
  /// Selective (and auto's selective intervals): once fewer than this many landmarks are in the
  /// test during an open conflict, the biases are held at the reference bias until it ends, as in
  /// an IMU-dominated interval. Behind a close occluder the few static landmarks left cannot tell
  /// the accelerometer bias (a rendered laptop covering 67 % of the view, 6-24 landmarks tested:
  /// the bias moved 0.09 m/s^2 and the track drifted, 0.047 m against a clean 0.008 m). 0: off.
  int thin_view_bias_hold_landmarks = 30;
  /// Selective (and auto's selective intervals): the same hold once fewer than this many tracks in
  /// view are left for the estimate: not found moving, and not born during the conflict unless
  /// confirmed static (new_landmark_probation keeps those out). A large slow object keeps the test
  /// full of its own tracks while the static ones thin out behind it: on the rendered slow object
  /// of a seed not used for tuning (79 % of the view) 120-170 tracks stayed in the test, 9 were
  /// left, and the accelerometer bias swung 0.07 m/s^2 (0.082 m; 0.042 m with the hold). 10, 15 and
  /// 20 measured alike; 25 and 30 held a bias before the object was sorted out (25: seed 3 0.046 ->
  /// 0.072 m; 30: seed 2 0.023 -> 0.093 m). 0: off.
  int thin_view_bias_hold_usable_tracks = 15;
  /// Selective (and auto's selective intervals): the same hold once the region split has found a
  /// group beside a static side for split_min_frames frames in a row. A large slow object's tracks
  /// stay in the solve for the half second or so before their own tests flag them, and pull the
  /// accelerometer bias with them. Feature level, auto, seeds 1-6: slow object 0.038 / 0.029 /
  /// 0.036 / 0.046 / 0.027 / 0.035 -> 0.036 / 0.030 / 0.037 / 0.043 / 0.026 / 0.022 m, pedestrian
  /// of seeds 3 / 5 / 6 0.061 / 0.052 / 0.047 -> 0.040 / 0.041 / 0.019 m, the other 62 runs the
  /// same. Image level with the IMU noise at x3 (shipped): slow object 0.078 / 0.071 / 0.079 ->
  /// 0.039 / 0.024 / 0.036 m (seeds 1-3).
  bool split_bias_hold = true;
  /// Selective (and auto's selective intervals): while only the frontend's labels have found
  /// motion in the open interval (no whole-view test on enter_frames frames in a row, no coherent
  /// landmark group, no region split held for split_min_frames, never IMU-dominated), the
  /// still-tracked landmarks' history goes on into the prior (EstimatorOptions::
  /// marginalize_tracked_landmark_history) for every landmark that has not disagreed within the
  /// horizon. The frontend finds a carried object's tracks at once, so the rest is the static
  /// world; a slow object that only the backend's tests find keeps the pause (its tracks are
  /// confirmed static before they move). Rendered self-occlusion of seed 9, auto: 0.0222 ->
  /// 0.0077 m; image bench, seeds 1 and 4-9: self-occlusions 0.0125 -> 0.0116 m (geometric mean;
  /// seeds 1 and 4 lose 4 and 3 mm), the slow objects unchanged.
  bool frontend_conflict_keeps_history = true;
  /// The vision-only motion weighs each point by its stereo depth uncertainty at the horizon's
  /// reference frame, projected into the newest frame (RelativePoseSolver). Without it a brisk
  /// horizon's far points pulled vision's rotation up to a degree off on a clean feature-level
  /// sequence (seed 7), and the propagated-state test opened a false interval.
  bool vision_depth_weighting = true;
  /// Auto: an interval that opens with at least this share of landmarks disagreeing while
  /// `auto_min_static_landmarks` still agree is a clear split and goes selective.
  double auto_split_fraction = 0.3;
  /// IMU-dominated: at the start of an interval go back to the state before the first evidence
  /// and propagate it with the IMU, so vision seen during the detection delay is undone.
  bool rewind_on_entry = true;
  /// IMU-dominated: keep vision's frame-to-frame rotation while it agrees with the gyro over the
  /// horizon (3-dof chi-square gate), against attitude drift from a held gyro bias. Off: a cabin
  /// that pitches slowly (a vehicle braking) agrees over each horizon yet tilted the estimate by
  /// 1.4 degrees, and gravity leaked into the position (src/mcvio_conflict/README.md).
  bool keep_consistent_rotation = false;
  double rotation_chi2_threshold = 16.3;
  /// IMU-dominated: the horizon's test then starts from r's velocity as vision measures it over
  /// this many frames before r, so it tests the conflicting frame's acceleration over those
  /// frames and the horizon. Fewer frames end the interval sooner after a vehicle stops (its
  /// braking leaves the span sooner), and also sooner in the quiet tail of a gentle ride.
  int exit_velocity_frames = 10;
  /// ... and this many once the speed hold below has engaged and no longer holds (the cabin or
  /// vehicle slowing to its stop): the braking then leaves the test sooner. The long span stays
  /// for the rest of a ride, where a gentle one needs it. Equal to exit_velocity_frames: off.
  int exit_velocity_frames_after_hold = 5;
  /// How far before the first frame of evidence the rewind goes: a smooth onset (a cabin starting
  /// gently) moves vision away from the IMU before the detectors can tell.
  int rewind_frames = 40;
  /// An IMU-dominated interval stays open while the conflicting frame (the secondary motion: the
  /// cabin, the vehicle) still moves at least this fast [m/s] and at least this share of its peak
  /// speed in the interval. The detectors only see acceleration once vision has taken over the
  /// velocity, so a cabin cruising at steady speed would otherwise end the interval mid-ride.
  double hold_min_secondary_speed_mps = 0.5;
  double hold_secondary_speed_fraction = 0.5;
  /// ... and at most this factor above the fastest it was seen while the detectors had evidence:
  /// speed gained without evidence is the inertial estimate drifting, not the frame moving.
  double hold_max_speed_gain = 1.25;
  /// Biases stay held this many frames after an IMU-dominated interval ends: vision pulls the
  /// drifted inertial velocity back then, and a conflicting object may still be in view (the
  /// feature-level slow object's last tracks turned the gyro bias to 0.02 rad/s and the yaw 3.7
  /// degrees within half a second). Off: 40 frames help the feature level (auto, seeds 1-3: slow
  /// object 0.121 / 0.053 / 0.191 -> 0.080 / 0.044 / 0.086 m, elevator, vehicle and self-occlusion
  /// equal or better) but the image-level slow object goes from 0.046 to 0.084 m (20 frames too).
  int exit_bias_hold_frames = 0;
  /// IMU-dominated: when the interval ends with vision's velocity at least
  /// `restart_min_velocity_jump_mps` from the inertial one, restart the window at the current pose
  /// with vision's velocity (measured over the last horizon), the held biases and loose roll and
  /// pitch. Linked by IMU factors to the interval's frames and their drifted velocity, the first
  /// frames with vision again bent the free biases instead: a vehicle ride left a 0.03 rad/s gyro
  /// bias behind that reopened a false interval 4 s later. Smaller jumps are reconciled without
  /// harm, and the window keeps the interval's attitude (the slow object: 0.100 m, 0.140 m with
  /// a restart at a 0.09 m/s jump).
  bool restart_on_exit = true;
  double restart_min_velocity_jump_mps = 0.2;
  /// The conflict window (triple window): after an IMU-dominated interval, once vision has held
  /// the velocity for smoothing_settle_frames, the interval is re-integrated with the world-frame
  /// acceleration correction that matches that velocity (growing over the window as the held
  /// bias's error does, see smoothing_held_acceleration_sigma), and the window is moved onto the
  /// corrected position. Corrections above smoothing_max_acceleration_correction [m/s^2] are
  /// refused.
  bool smoothing_enabled = true;
  int smoothing_settle_frames = 20;
  double smoothing_max_acceleration_correction = 0.2;
  /// How far the held accelerometer bias (and gravity's removal) may be off when the interval
  /// opens [m/s^2]. The true bias keeps walking (the IMU's accelerometer random walk) while the
  /// held one stays, so the correction grows over the window; against this sigma that growth
  /// sets its shape (large: constant). Measured on the feature-level simulator (elevator, vehicle,
  /// self-occlusion, seeds 1-9): 0.011 m/s^2 RMS per axis when the intervals open.
  double smoothing_held_acceleration_sigma = 0.01;
  /// Re-acquiring the map: landmarks the window let go of before the interval and re-identified
  /// by the frontend after it (same track id) give the end position in the frame the interval
  /// started in; with at least this many agreeing, the correction is fitted to it as well
  /// (0: never). The settled velocities are then weighed with
  /// smoothing_settled_velocity_sigma [m/s per axis].
  int smoothing_reidentified_min_landmarks = 8;
  double smoothing_settled_velocity_sigma = 0.02;
  /// Re-acquiring the map without the frontend's help: when too few landmarks came back with
  /// their old ids (a KLT frontend gives a corner seen again a new one), the window's landmarks
  /// are registered against those remembered before the interval by position alone
  /// (mcvio::estimator::LandmarkRegistration): the offset that most of them agree on, within
  /// this radius of where the IMU put them [m] (0: never).
  double smoothing_registration_radius_m = 5.0;
  /// How far a landmark may lie from the offset and still agree [m]: their stereo depth noise.
  /// At least smoothing_registration_radius_m / 2000.
  double smoothing_registration_tolerance_m = 0.08;
  /// Share of the window's landmarks that must agree (at least smoothing_reidentified_min_landmarks).
  double smoothing_registration_min_fraction = 0.4;
  /// A distinct offset (25 cm or 3 tolerances away) agreed with this sharply, relative to the
  /// best, makes the registration ambiguous (a repeated texture), and it is not used.
  double smoothing_registration_max_ambiguity = 0.6;

  void validate() const;
  static ConflictOptions fromYaml(const YAML::Node& node, const std::string& context = "conflict options");
};

}  // namespace mcvio::conflict
