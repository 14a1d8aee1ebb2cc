#include "mcvio/frontend/feature_tracker.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <filesystem>
#include <opencv2/features2d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <string>

#include "mcvio/core/input_error.hpp"

namespace mcvio::frontend {
namespace {

std::string describeMat(const cv::Mat& m) {
  return std::to_string(m.cols) + "x" + std::to_string(m.rows) + " " + cv::typeToString(m.type());
}

// Thread CPU time [ms]: stage costs that do not include time the scheduler gave to others.
double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

Eigen::Vector2d toEigen(const cv::Point2f& p) { return {p.x, p.y}; }
cv::Point2f toCv(const Eigen::Vector2d& p) {
  return {static_cast<float>(p.x()), static_cast<float>(p.y())};
}

// dst = src * gain + offset with gain/offset blended between two block rows (weight wy).
// Cloned for AVX2 where the compiler supports it: this loop touches every pixel of both images.
#if defined(__GNUC__) && defined(__x86_64__) && !defined(__clang__)
__attribute__((target_clones("avx2", "default")))
#endif
void blendGainRow(const uchar* src, const float* ga, const float* gb, const float* oa, const float* ob,
                  float wy, uchar* dst, int w) {
  for (int x = 0; x < w; ++x) {
    const float g = ga[x] + wy * (gb[x] - ga[x]);
    const float o = oa[x] + wy * (ob[x] - oa[x]);
    const float v = static_cast<float>(src[x]) * g + o + 0.5f;
    dst[x] = static_cast<uchar>(v < 0.0f ? 0.0f : (v > 255.0f ? 255.0f : v));
  }
}

}  // namespace

const char* toString(FrameStatus status) {
  switch (status) {
    case FrameStatus::kOk:
      return "ok";
    case FrameStatus::kNoCalibration:
      return "no calibration";
    case FrameStatus::kBadImage:
      return "bad image";
    case FrameStatus::kMissingRight:
      return "missing right image";
    case FrameStatus::kOutOfOrder:
      return "out of order";
  }
  return "unknown";
}

namespace {
TrackReidentifier::Options reidentifierOptions(const FrontendOptions& o) {
  TrackReidentifier::Options r;
  r.min_age_s = o.reidentify_min_age_s;
  r.max_age_s = o.reidentify_max_age_s;
  r.max_hamming = o.reidentify_max_hamming;
  r.ratio = o.reidentify_ratio;
  return r;
}
}  // namespace

FeatureTracker::FeatureTracker(const FrontendOptions& options)
    : options_(options), gyro_(options.max_imu_gap_ns), reidentifier_(reidentifierOptions(options)) {
  options_.validate();
  for (int i = 0; i < 2; ++i) {
    const std::string& path = i == 0 ? options_.mask0 : options_.mask1;
    if (path.empty()) continue;
    const std::string key = "frontend option 'mask" + std::to_string(i) + "'";
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) throw InputError(key + ": no mask image at '" + path + "'");
    const cv::Mat image = cv::imread(path, cv::IMREAD_GRAYSCALE);
    if (image.empty()) throw InputError(key + ": cannot read the mask image '" + path + "' (not an image OpenCV decodes)");
    cv::Mat& mask = masks_[static_cast<std::size_t>(i)];
    cv::threshold(image, mask, 127, 255, cv::THRESH_BINARY);
  }
}

bool FeatureTracker::masked(int camera, const cv::Point2f& px) const {
  const cv::Mat& mask = masks_[static_cast<std::size_t>(camera)];
  if (mask.empty()) return false;
  const int x = std::clamp(cvRound(px.x), 0, mask.cols - 1), y = std::clamp(cvRound(px.y), 0, mask.rows - 1);
  return mask.at<uchar>(y, x) != 0;
}

void FeatureTracker::setCalibration(const StereoRigCalibration& calibration) {
  for (int i = 0; i < 2; ++i) {
    const CameraCalibration& cam = calibration.camera(i);
    const Eigen::Matrix3d r = cam.T_BC.linear();
    if (!cam.T_BC.matrix().allFinite() ||
        (r * r.transpose() - Eigen::Matrix3d::Identity()).norm() > 1e-6) {
      throw InputError("frontend calibration: T_BC of " + cam.name + " is not a rigid transform");
    }
    if (cam.model.width() < 32 || cam.model.height() < 32) {
      throw InputError("frontend calibration: " + cam.name + " has no usable camera model (" +
                       std::to_string(cam.model.width()) + "x" +
                       std::to_string(cam.model.height()) + ")");
    }
  }
  if (calibration.cam0.model.width() != calibration.cam1.model.width() ||
      calibration.cam0.model.height() != calibration.cam1.model.height()) {
    throw InputError("frontend calibration: cam0 and cam1 resolutions differ");
  }
  if (calibration.baseline() < 1e-3) {
    throw InputError("frontend calibration: stereo baseline is " +
                     std::to_string(calibration.baseline()) + " m; cam0 and cam1 must be apart");
  }
  for (int i = 0; i < 2; ++i) {
    const cv::Mat& mask = masks_[static_cast<std::size_t>(i)];
    const CameraModel& model = calibration.camera(i).model;
    if (!mask.empty() && (mask.cols != model.width() || mask.rows != model.height())) {
      throw InputError("frontend option 'mask" + std::to_string(i) + "': the mask '" + (i == 0 ? options_.mask0 : options_.mask1) +
                       "' is " + std::to_string(mask.cols) + "x" + std::to_string(mask.rows) + ", " +
                       calibration.camera(i).name + " is " + std::to_string(model.width()) + "x" +
                       std::to_string(model.height()));
    }
  }
  calibration_ = calibration;
  const CameraModel& cam0 = calibration.cam0.model;
  checker_ = std::make_unique<MotionConsistencyChecker>(
      options_.ransac_threshold_px, cam0.focalLengthAtCentre(), options_.ransac_iterations,
      options_.min_tracks_for_check, options_.ransac_seed, options_.min_depth_m);
  reset();
}

void FeatureTracker::reset() {
  has_prev_ = false;
  prev_left_pyr_.clear();
  prev_left_.release();
  tracks_.clear();
  reidentifier_.clear();
}

std::vector<TrackHistory> FeatureTracker::trackHistories() const {
  std::vector<TrackHistory> out;
  out.reserve(tracks_.size());
  for (const Track& t : tracks_) {
    out.push_back({t.id, t.label, t.stereo, {t.history.begin(), t.history.end()}});
  }
  return out;
}

void FeatureTracker::prepareImage(const cv::Mat& raw, cv::Mat* out) const {
  if (options_.exposure_normalization == "none") {
    *out = raw;
    return;
  }
  constexpr double kContrast = 48.0;  // target standard deviation in grey levels
  if (options_.exposure_normalization == "global") {
    // Gain/offset invariance: map every image to the same mean and contrast before KLT.
    cv::Scalar mean, stddev;
    cv::meanStdDev(raw, mean, stddev);
    const double alpha = kContrast / std::max(stddev[0], 1.0);
    raw.convertTo(*out, CV_8U, alpha, 128.0 - alpha * mean[0]);
    return;
  }
  // Local: gain and offset per block from its mean and std, blended bilinearly between block
  // centres, so each region is normalised on its own (saturated areas, vignetting, the two
  // cameras' different responses). One pass for the statistics, one for the output.
  const int block = options_.normalization_block_px;
  const int w = raw.cols, h = raw.rows;
  const int gw = (w + block - 1) / block, gh = (h + block - 1) / block;
  std::vector<double> sum(static_cast<std::size_t>(gw * gh), 0.0), sum2(sum.size(), 0.0);
  std::vector<int> count(sum.size(), 0);
  for (int y = 0; y < h; ++y) {
    const uchar* row = raw.ptr<uchar>(y);
    const int by = y / block;
    for (int bx = 0; bx < gw; ++bx) {
      const int x0 = bx * block, x1 = std::min(w, x0 + block);
      std::uint32_t s1 = 0, s2 = 0;
      for (int x = x0; x < x1; ++x) {
        s1 += row[x];
        s2 += static_cast<std::uint32_t>(row[x]) * row[x];
      }
      const std::size_t k = static_cast<std::size_t>(by * gw + bx);
      sum[k] += s1;
      sum2[k] += s2;
      count[k] += x1 - x0;
    }
  }
  std::vector<float> gain(sum.size()), offset(sum.size());
  for (std::size_t k = 0; k < sum.size(); ++k) {
    const double m = sum[k] / count[k];
    const double var = std::max(sum2[k] / count[k] - m * m, 0.0);
    // The floor keeps flat, dark regions from turning sensor noise into texture.
    const double g = kContrast / std::sqrt(var + 16.0);
    gain[k] = static_cast<float>(g);
    offset[k] = static_cast<float>(128.0 - g * m);
  }
  // Gain and offset blended horizontally at every column, once per block row; each image row
  // then blends two of these rows: contiguous loops the compiler vectorises.
  std::vector<float> gx(static_cast<std::size_t>(gh * w)), ox(gx.size());
  for (int x = 0; x < w; ++x) {
    const float f = std::clamp((x + 0.5f) / block - 0.5f, 0.0f, static_cast<float>(gw - 1));
    const int ca = std::min(static_cast<int>(f), std::max(gw - 2, 0));
    const int cb = std::min(ca + 1, gw - 1);
    const float wx = f - static_cast<float>(ca);
    for (int r = 0; r < gh; ++r) {
      const std::size_t a = static_cast<std::size_t>(r * gw + ca),
                        b = static_cast<std::size_t>(r * gw + cb);
      const std::size_t o = static_cast<std::size_t>(r * w + x);
      gx[o] = gain[a] + wx * (gain[b] - gain[a]);
      ox[o] = offset[a] + wx * (offset[b] - offset[a]);
    }
  }
  out->create(h, w, CV_8UC1);
  for (int y = 0; y < h; ++y) {
    const float f = std::clamp((y + 0.5f) / block - 0.5f, 0.0f, static_cast<float>(gh - 1));
    const int r0 = std::min(static_cast<int>(f), std::max(gh - 2, 0));
    const int r1 = std::min(r0 + 1, gh - 1);
    const float wy = f - static_cast<float>(r0);
    const float* ga = gx.data() + static_cast<std::size_t>(r0 * w);
    const float* gb = gx.data() + static_cast<std::size_t>(r1 * w);
    const float* oa = ox.data() + static_cast<std::size_t>(r0 * w);
    const float* ob = ox.data() + static_cast<std::size_t>(r1 * w);
    blendGainRow(raw.ptr<uchar>(y), ga, gb, oa, ob, wy, out->ptr<uchar>(y), w);
  }
}

void FeatureTracker::buildPyramid(const cv::Mat& image, std::vector<cv::Mat>* pyramid) const {
  cv::buildOpticalFlowPyramid(image, *pyramid, cv::Size(options_.window_size, options_.window_size),
                              options_.pyramid_levels, true);
}

TrackingResult FeatureTracker::track(const StereoInput& input) {
  TrackingResult result;
  // On the IMU's clock (Kalibr's timeshift_cam_imu), as the estimator integrates between frames.
  const Timestamp frame_t = input.t + (calibration_ ? calibration_->camera_time_offset_ns : 0);
  result.features.t = frame_t;
  int imu_rejected = 0;
  for (const ImuSample& s : input.imu) imu_rejected += gyro_.add(s) ? 0 : 1;
  result.stats.imu_rejected = imu_rejected;
  if (imu_rejected > 0) {
    result.message = "frontend: frame t=" + std::to_string(frame_t) + ": ignored " +
                     std::to_string(imu_rejected) +
                     " IMU sample(s) that were non-finite or not newer than the last";
  }

  auto skip = [&](FrameStatus status, const std::string& why) {
    result.status = status;
    result.message = "frontend: frame t=" + std::to_string(frame_t) + " skipped: " + why;
    return result;
  };
  if (!calibration_) return skip(FrameStatus::kNoCalibration, "no stereo calibration received yet");
  const char* names[2] = {"left", "right"};
  const cv::Mat* images[2] = {&input.left, &input.right};
  for (int i = 0; i < 2; ++i) {
    const cv::Mat& m = *images[i];
    if (m.empty()) {
      return skip(i == 0 ? FrameStatus::kBadImage : FrameStatus::kMissingRight,
                  std::string(names[i]) + " image is missing");
    }
    if (m.type() != CV_8UC1) {
      return skip(
          FrameStatus::kBadImage,
          std::string(names[i]) + " image encoding must be mono8 (CV_8UC1), got " + describeMat(m));
    }
    const CameraModel& cam = calibration_->camera(i).model;
    if (m.cols != cam.width() || m.rows != cam.height()) {
      return skip(FrameStatus::kBadImage,
                  std::string(names[i]) + " image is " + describeMat(m) + ", calibration expects " +
                      std::to_string(cam.width()) + "x" + std::to_string(cam.height()));
    }
  }
  if (has_prev_ && frame_t <= prev_t_) {
    return skip(FrameStatus::kOutOfOrder,
                "timestamp not after the previous frame t=" + std::to_string(prev_t_));
  }

  TrackingStats& stats = result.stats;
  const double t_start = threadCpuMs();
  cv::Mat left, right;
  prepareImage(input.left, &left);
  prepareImage(input.right, &right);
  std::vector<cv::Mat> left_pyr, right_pyr;
  buildPyramid(left, &left_pyr);
  buildPyramid(right, &right_pyr);
  double t_mark = threadCpuMs();
  stats.cpu_ms_prepare = t_mark - t_start;
  auto lap = [&t_mark]() {
    const double now = threadCpuMs();
    const double d = now - t_mark;
    t_mark = now;
    return d;
  };
  if (has_prev_ && !tracks_.empty()) {
    Eigen::Matrix3d R_b_prev_cur;
    Eigen::Matrix3d R_cur_prev;
    bool have_rotation = false;
    if (options_.use_gyro_prediction &&
        gyro_.rotation(prev_t_, frame_t, gyro_bias_, &R_b_prev_cur)) {
      const Eigen::Matrix3d R_bc = calibration_->cam0.T_BC.linear();
      R_cur_prev = (R_bc.transpose() * R_b_prev_cur * R_bc).transpose();
      have_rotation = true;
    }
    stats.gyro_prediction = have_rotation;
    trackTemporal(left_pyr, have_rotation ? &R_cur_prev : nullptr, &stats);
    if (options_.reidentify_lost_tracks) reidentifier_.remember(prev_left_, lost_, kept_prev_, prev_t_);
  } else {
    for (Track& t : tracks_) t.label = TrackLabel::kUnknown;
  }
  stats.cpu_ms_temporal = lap();
  detectNew(left, frame_t, &stats);
  stats.cpu_ms_detect = lap();
  matchStereo(left_pyr, right_pyr, &stats);
  stats.cpu_ms_stereo = lap();

  FeatureFrame& ff = result.features;
  ff.frame_index = frame_index_;
  ff.features.reserve(tracks_.size() * 2);
  for (Track& t : tracks_) {
    t.history.push_back(t.left);
    while (static_cast<int>(t.history.size()) > options_.history_length) t.history.pop_front();
    FeatureObservation o;
    o.track_id = t.id;
    o.camera_index = 0;
    o.pixel = toEigen(t.left);
    o.normalized = t.left_norm;
    o.label = t.label;
    ff.features.push_back(o);
    if (t.stereo) {
      o.camera_index = 1;
      o.pixel = toEigen(t.right);
      o.normalized = t.right_norm;
      ff.features.push_back(o);
    }
    if (t.label == TrackLabel::kConsistent) ++stats.consistent;
    if (t.label == TrackLabel::kInconsistent) ++stats.inconsistent;
  }
  stats.cpu_ms_total = threadCpuMs() - t_start;
  prev_left_pyr_ = std::move(left_pyr);
  if (options_.reidentify_lost_tracks) prev_left_ = left;
  prev_t_ = frame_t;
  has_prev_ = true;
  ++frame_index_;
  gyro_.dropBefore(frame_t);
  return result;
}

void FeatureTracker::trackTemporal(const std::vector<cv::Mat>& cur_pyr,
                                   const Eigen::Matrix3d* R_cur_prev, TrackingStats* stats) {
  const CameraModel& cam0 = calibration_->cam0.model;
  const std::size_t n = tracks_.size();
  std::vector<cv::Point2f> prev_pts(n), cur_pts(n), back_pts(n);
  for (std::size_t i = 0; i < n; ++i) {
    prev_pts[i] = tracks_[i].left;
    cur_pts[i] = tracks_[i].left;
    if (R_cur_prev) {
      Eigen::Vector2d px;
      if (cam0.projectAnywhere(Eigen::Vector3d(*R_cur_prev * tracks_[i].left_norm.homogeneous()),
                               &px) &&
          cam0.isInImage(px)) {
        cur_pts[i] = toCv(px);
      }
    }
  }
  const cv::Size win(options_.window_size, options_.window_size);
  const cv::TermCriteria crit(cv::TermCriteria::COUNT | cv::TermCriteria::EPS,
                              options_.klt_max_iterations, options_.klt_epsilon);
  std::vector<uchar> st_fwd, st_bwd;
  std::vector<float> err;
  cv::calcOpticalFlowPyrLK(prev_left_pyr_, cur_pyr, prev_pts, cur_pts, st_fwd, err, win,
                           options_.pyramid_levels, crit, cv::OPTFLOW_USE_INITIAL_FLOW);
  // The backward run starts where a good track must end: few levels suffice.
  back_pts = prev_pts;
  cv::calcOpticalFlowPyrLK(cur_pyr, prev_left_pyr_, cur_pts, back_pts, st_bwd, err, win,
                           std::min(options_.check_pyramid_levels, options_.pyramid_levels), crit,
                           cv::OPTFLOW_USE_INITIAL_FLOW);

  std::vector<Track> kept;
  std::vector<MotionConsistencyChecker::Correspondence> corr;
  kept.reserve(n);
  corr.reserve(n);
  const double fb2 = options_.fb_threshold_px * options_.fb_threshold_px;
  lost_.clear();
  kept_prev_.clear();
  const bool reidentify = options_.reidentify_lost_tracks;
  for (std::size_t i = 0; i < n; ++i) {
    const cv::Point2f d = back_pts[i] - prev_pts[i];
    Eigen::Vector2d norm;
    if (!st_fwd[i] || !st_bwd[i] || d.dot(d) > fb2 ||
        !cam0.isInImage(toEigen(cur_pts[i]), options_.border_px) || masked(0, cur_pts[i]) ||
        !cam0.unproject(toEigen(cur_pts[i]), &norm)) {
      ++stats->lost;
      if (reidentify) lost_.emplace_back(tracks_[i].id, prev_pts[i]);
      continue;
    }
    Track t = std::move(tracks_[i]);
    if (reidentify) kept_prev_.push_back(prev_pts[i]);
    MotionConsistencyChecker::Correspondence c;
    c.prev_normalized = t.left_norm;
    c.cur_normalized = norm;
    if (usesLocalPixelScale(options_.pixel_scale, cam0.distortionModel()))
      c.to_centre = cam0.pixelJacobianAt(norm) / cam0.focalLengthAtCentre();
    c.has_point = t.has_point;
    c.point_prev = t.point;
    corr.push_back(c);
    t.left = cur_pts[i];
    t.left_norm = norm;
    kept.push_back(std::move(t));
  }
  tracks_ = std::move(kept);
  stats->tracked = static_cast<int>(tracks_.size());

  const MotionConsistencyChecker::Result check = checker_->check(corr, R_cur_prev);
  stats->metric_check = check.valid && check.metric;
  for (std::size_t i = 0; i < tracks_.size(); ++i) tracks_[i].label = check.labels[i];
}

void FeatureTracker::detectNew(const cv::Mat& image, Timestamp t_frame, TrackingStats* stats) {
  const int max_features = options_.max_features;
  // Tracks labelled moving count only up to their share (FrontendOptions::moving_track_budget_share).
  int counted = 0, moving = 0;
  for (const Track& t : tracks_) ++(t.label == TrackLabel::kInconsistent ? moving : counted);
  counted += std::min(moving, static_cast<int>(options_.moving_track_budget_share * max_features));
  if (counted >= max_features) return;
  const int w = image.cols, h = image.rows;
  const int radius = static_cast<int>(std::ceil(options_.min_distance_px));
  if (!masks_[0].empty()) {  // its size is the calibration's, and so the image's (setCalibration, track)
    masks_[0].copyTo(occupancy_);
  } else {
    occupancy_.create(h, w, CV_8UC1);
    occupancy_.setTo(0);
  }
  const int cols = options_.grid_cols, rows = options_.grid_rows;
  std::vector<int> cell_count(static_cast<std::size_t>(cols * rows), 0);
  const int b = options_.border_px;
  const double cell_w = static_cast<double>(w - 2 * b) / cols;
  const double cell_h = static_cast<double>(h - 2 * b) / rows;
  auto cellOf = [&](const cv::Point2f& p) {
    const int cx = std::clamp(static_cast<int>((p.x - b) / cell_w), 0, cols - 1);
    const int cy = std::clamp(static_cast<int>((p.y - b) / cell_h), 0, rows - 1);
    return cy * cols + cx;
  };
  for (const Track& t : tracks_) {
    cv::circle(occupancy_, t.left, radius, 255, -1);
    ++cell_count[static_cast<std::size_t>(cellOf(t.left))];
  }
  const int quota = (max_features + cols * rows - 1) / (cols * rows);
  std::vector<cv::KeyPoint> pool;  // leftovers from under-filled cells
  std::vector<cv::Point2f> fresh;
  int total = counted;
  auto take = [&](const cv::KeyPoint& kp) {
    const int x = cvRound(kp.pt.x), y = cvRound(kp.pt.y);
    if (x < b || y < b || x >= w - b || y >= h - b) return false;
    if (occupancy_.at<uchar>(y, x)) return false;
    cv::circle(occupancy_, kp.pt, radius, 255, -1);
    fresh.push_back(kp.pt);
    ++total;
    return true;
  };
  std::vector<cv::KeyPoint> kps;
  for (int cy = 0; cy < rows && total < max_features; ++cy) {
    for (int cx = 0; cx < cols && total < max_features; ++cx) {
      int need = quota - cell_count[static_cast<std::size_t>(cy * cols + cx)];
      if (need <= 0) continue;
      // FAST needs 3 px around each pixel: widen the ROI so corners at cell edges are seen.
      const int x0 = std::max(0, static_cast<int>(b + cx * cell_w) - 3);
      const int y0 = std::max(0, static_cast<int>(b + cy * cell_h) - 3);
      const int x1 = std::min(w, static_cast<int>(b + (cx + 1) * cell_w) + 3);
      const int y1 = std::min(h, static_cast<int>(b + (cy + 1) * cell_h) + 3);
      const cv::Rect roi(x0, y0, x1 - x0, y1 - y0);
      for (int thr = options_.fast_threshold; need > 0;
           thr = std::max(options_.fast_min_threshold, thr / 2)) {
        kps.clear();
        cv::FAST(image(roi), kps, thr, true);
        std::sort(kps.begin(), kps.end(), [](const cv::KeyPoint& a, const cv::KeyPoint& c) {
          return a.response > c.response;
        });
        std::size_t k = 0;
        for (; k < kps.size() && need > 0 && total < max_features; ++k) {
          kps[k].pt.x += static_cast<float>(x0);
          kps[k].pt.y += static_cast<float>(y0);
          if (take(kps[k])) --need;
        }
        if (need <= 0 || thr == options_.fast_min_threshold) {
          for (; k < kps.size(); ++k) {
            kps[k].pt.x += static_cast<float>(x0);
            kps[k].pt.y += static_cast<float>(y0);
            pool.push_back(kps[k]);
          }
          break;
        }
      }
    }
  }
  if (total < max_features && !pool.empty()) {
    std::sort(pool.begin(), pool.end(),
              [](const cv::KeyPoint& a, const cv::KeyPoint& c) { return a.response > c.response; });
    for (const cv::KeyPoint& kp : pool) {
      if (total >= max_features) break;
      take(kp);
    }
  }
  if (fresh.empty()) return;
  if (options_.subpixel_refinement) {
    cv::cornerSubPix(image, fresh, cv::Size(3, 3), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 10, 0.01));
  }
  const CameraModel& cam0 = calibration_->cam0.model;
  std::vector<std::uint64_t> known(fresh.size(), 0);
  if (options_.reidentify_lost_tracks) {
    std::vector<cv::Point2f> tracked;
    tracked.reserve(tracks_.size());
    for (const Track& tr : tracks_) tracked.push_back(tr.left);
    known = reidentifier_.recognise(image, fresh, tracked, t_frame);
  }
  for (std::size_t k = 0; k < fresh.size(); ++k) {
    const cv::Point2f& p = fresh[k];
    Track t;
    // Sub-pixel refinement may have moved a corner over the border or into the mask.
    if (!cam0.isInImage(toEigen(p), b) || masked(0, p) || !cam0.unproject(toEigen(p), &t.left_norm)) continue;
    t.id = known[k] != 0 ? known[k] : next_id_++;
    stats->reidentified += known[k] != 0 ? 1 : 0;
    t.left = p;
    tracks_.push_back(std::move(t));
    ++stats->detected;
  }
}

void FeatureTracker::matchStereo(const std::vector<cv::Mat>& left_pyr,
                                 const std::vector<cv::Mat>& right_pyr, TrackingStats* stats) {
  const std::size_t n = tracks_.size();
  if (n == 0) return;
  const CameraModel& cam1 = calibration_->cam1.model;
  const Eigen::Isometry3d T10 = calibration_->T_C0C1().inverse();
  const Eigen::Matrix3d R10 = T10.linear();
  const Eigen::Vector3d t10 = T10.translation();
  Eigen::Matrix3d tx;
  tx << 0, -t10.z(), t10.y(), t10.z(), 0, -t10.x(), -t10.y(), t10.x(), 0;
  const Eigen::Matrix3d E = tx * R10;

  // New tracks start at the median depth of the current stereo points (infinity if none).
  std::vector<double> depths;
  for (const Track& t : tracks_) {
    if (t.has_point) depths.push_back(t.point.z());
  }
  double guess_depth = 0.0;
  if (!depths.empty()) {
    std::nth_element(depths.begin(), depths.begin() + static_cast<long>(depths.size() / 2),
                     depths.end());
    guess_depth = depths[depths.size() / 2];
  }
  std::vector<cv::Point2f> lpts(n), rpts(n), back(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Track& t = tracks_[i];
    lpts[i] = t.left;
    if (t.stereo) {
      // Disparity changes slowly: carry last frame's left-right offset (stored in history).
      rpts[i] = t.left + (t.right - (t.history.empty() ? t.left : t.history.back()));
    } else {
      const Eigen::Vector3d ray = t.left_norm.homogeneous();
      const Eigen::Vector3d p1 =
          guess_depth > 0 ? Eigen::Vector3d(T10 * (ray * guess_depth)) : Eigen::Vector3d(R10 * ray);
      Eigen::Vector2d px;
      rpts[i] = (cam1.projectAnywhere(p1, &px) && cam1.isInImage(px)) ? toCv(px) : t.left;
    }
  }
  const cv::Size win(options_.window_size, options_.window_size);
  const cv::TermCriteria crit(cv::TermCriteria::COUNT | cv::TermCriteria::EPS,
                              options_.klt_max_iterations, options_.klt_epsilon);
  const std::vector<cv::Point2f> predicted = rpts;
  std::vector<uchar> st_fwd(n, 0);
  std::vector<float> err;
  {
    // Tracks matched last frame start at their carried disparity and need few pyramid levels;
    // new ones may be far from their guess and get the full pyramid.
    const int check_levels = std::min(options_.check_pyramid_levels, options_.pyramid_levels);
    for (const bool carried : {true, false}) {
      std::vector<int> idx;
      std::vector<cv::Point2f> l, r;
      for (std::size_t i = 0; i < n; ++i) {
        if (tracks_[i].stereo != carried) continue;
        idx.push_back(static_cast<int>(i));
        l.push_back(lpts[i]);
        r.push_back(rpts[i]);
      }
      if (idx.empty()) continue;
      std::vector<uchar> st;
      cv::calcOpticalFlowPyrLK(left_pyr, right_pyr, l, r, st, err, win,
                               carried ? check_levels : options_.pyramid_levels, crit,
                               cv::OPTFLOW_USE_INITIAL_FLOW);
      for (std::size_t k = 0; k < idx.size(); ++k) {
        st_fwd[static_cast<std::size_t>(idx[k])] = st[k];
        rpts[static_cast<std::size_t>(idx[k])] = r[k];
      }
    }
  }
  // Left-right-left check, skipped for a track whose match lands within
  // stereo_prediction_tolerance_px of where last frame's verified disparity put it: that match is
  // already confirmed by the previous frame's check and this frame's temporal tracks.
  std::vector<int> verify;
  std::vector<bool> confirmed(n, false);
  const double tol2 =
      options_.stereo_prediction_tolerance_px * options_.stereo_prediction_tolerance_px;
  for (std::size_t i = 0; i < n; ++i) {
    if (!st_fwd[i]) continue;
    const cv::Point2f d = rpts[i] - predicted[i];
    if (tracks_[i].stereo && d.dot(d) <= tol2) {
      confirmed[i] = true;
    } else {
      verify.push_back(static_cast<int>(i));
    }
  }
  std::vector<uchar> st_bwd(n, 0);
  back = lpts;
  if (!verify.empty()) {
    std::vector<cv::Point2f> vr, vl;
    for (int i : verify) {
      vr.push_back(rpts[static_cast<std::size_t>(i)]);
      vl.push_back(lpts[static_cast<std::size_t>(i)]);
    }
    std::vector<uchar> vst;
    cv::calcOpticalFlowPyrLK(right_pyr, left_pyr, vr, vl, vst, err, win,
                             std::min(options_.check_pyramid_levels, options_.pyramid_levels), crit,
                             cv::OPTFLOW_USE_INITIAL_FLOW);
    for (std::size_t k = 0; k < verify.size(); ++k) {
      st_bwd[static_cast<std::size_t>(verify[k])] = vst[k];
      back[static_cast<std::size_t>(verify[k])] = vl[k];
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (confirmed[i]) st_bwd[i] = 1;
  }
  const double fb2 = options_.stereo_fb_threshold_px * options_.stereo_fb_threshold_px;
  const double f1 = cam1.focalLengthAtCentre();
  const bool local_scale = usesLocalPixelScale(options_.pixel_scale, cam1.distortionModel());
  for (std::size_t i = 0; i < n; ++i) {
    Track& t = tracks_[i];
    t.stereo = false;
    t.has_point = false;
    const cv::Point2f d = back[i] - lpts[i];
    Eigen::Vector2d rn;
    if (!st_fwd[i] || !st_bwd[i] || d.dot(d) > fb2 || !cam1.isInImage(toEigen(rpts[i]), 1.0) ||
        masked(1, rpts[i]) || !cam1.unproject(toEigen(rpts[i]), &rn)) {
      continue;
    }
    const Eigen::Vector3d x0 = t.left_norm.homogeneous();
    const Eigen::Vector3d x1 = rn.homogeneous();
    const Eigen::Vector3d line = E * x0;
    const double epi_norm = std::abs(x1.dot(line)) / line.head<2>().norm();
    // In the lens's own pixels the line keeps its shape locally, with normal J^-T n.
    const double epi_px =
        local_scale ? epi_norm / (cam1.pixelJacobianAt(rn).inverse().transpose() * line.head<2>().normalized()).norm()
                    : epi_norm * f1;
    if (!(epi_px <= options_.stereo_epipolar_threshold_px)) continue;
    // Depths along both rays: d1 x1 = d0 R x0 + t, least squares.
    Eigen::Matrix<double, 3, 2> a;
    a.col(0) = R10 * x0;
    a.col(1) = -x1;
    const Eigen::Vector2d depth = (a.transpose() * a).ldlt().solve(-a.transpose() * t10);
    if (!(depth[0] >= options_.min_depth_m && depth[0] <= options_.max_depth_m && depth[1] > 0))
      continue;
    t.stereo = true;
    t.right = rpts[i];
    t.right_norm = rn;
    t.has_point = true;
    t.point = x0 * depth[0];
    ++stats->stereo_matched;
  }
}

}  // namespace mcvio::frontend
