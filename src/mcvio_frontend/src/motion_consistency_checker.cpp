#include "mcvio/frontend/motion_consistency_checker.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

namespace mcvio::frontend {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Eigen::Matrix3d expSO3(const Eigen::Vector3d& phi) {
  const double a = phi.norm();
  if (a < 1e-12) return Eigen::Matrix3d::Identity() + skew(phi);
  return Eigen::AngleAxisd(a, phi / a).toRotationMatrix();
}

// Every error below is a distance in normalised coordinates, or, given the track's
// `to_centre` (d pixel / d normalised over the centre's focal length), the same distance measured
// in the lens's pixels there, in units of the centre's pixels.
double lengthOf(const Eigen::Vector2d& v, const Eigen::Matrix2d* to_centre) {
  return to_centre ? (*to_centre * v).norm() : v.norm();
}

double reprojectionError(const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                         const Eigen::Vector3d& X, const Eigen::Vector2d& c,
                         const Eigen::Matrix2d* to_centre = nullptr) {
  const Eigen::Vector3d y = R * X + t;
  if (y.z() < 1e-6) return kInf;
  return lengthOf(y.head<2>() / y.z() - c, to_centre);
}

// Distance of c to the epipolar line of p; with no translation, the rotation-compensated motion.
double epipolarError(const Eigen::Matrix3d& R, const Eigen::Vector3d& t, const Eigen::Vector2d& p,
                     const Eigen::Vector2d& c, const Eigen::Matrix2d* to_centre = nullptr) {
  const Eigen::Vector3d rp = R * p.homogeneous();
  const double tn = t.norm();
  if (tn < 1e-9) {
    if (rp.z() < 1e-9) return kInf;
    return lengthOf(rp.head<2>() / rp.z() - c, to_centre);
  }
  const Eigen::Vector3d line = (t / tn).cross(rp);
  const double den = line.head<2>().norm();
  if (den < 1e-12) return 0.0;
  const double d = std::abs(c.homogeneous().dot(line)) / den;
  if (!to_centre) return d;
  // Under the local map the line stays a line, with normal to_centre^-T n: the distance of c
  // from it is d / |to_centre^-T n|.
  const Eigen::Vector2d n = line.head<2>() / den;
  const double stretch = (to_centre->inverse().transpose() * n).norm();
  return stretch > 0.0 && std::isfinite(stretch) ? d / stretch : kInf;
}

// A track without depth under a metric (R, t): its point lies somewhere on the ray of p between
// min_depth and infinity, whose image is a segment of the epipolar line (inverse depth rho in
// [0, rho_max]). Distance of c to that segment: unlike the full epipolar line, it rejects flow
// that only a point behind the camera or nearer than min_depth could make.
double depthBoundedError(const Eigen::Matrix3d& R, const Eigen::Vector3d& t,
                         const Eigen::Vector2d& p, const Eigen::Vector2d& c, double rho_max,
                         const Eigen::Matrix2d* to_centre = nullptr) {
  const Eigen::Vector3d far = R * p.homogeneous();
  if (far.z() < 1e-6) return kInf;
  if (t.z() < 0.0) rho_max = std::min(rho_max, 0.99 * (far.z() - 1e-6) / -t.z());
  const Eigen::Vector3d near = far + rho_max * t;
  const Eigen::Vector2d a = far.head<2>() / far.z(), b = near.head<2>() / near.z();
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double s = len2 < 1e-18 ? 0.0 : std::clamp((c - a).dot(ab) / len2, 0.0, 1.0);
  return lengthOf(a + s * ab - c, to_centre);
}

// Translation given the rotation, least squares over the listed 3D-2D pairs.
bool solveTranslation(const Eigen::Matrix3d& R,
                      const std::vector<MotionConsistencyChecker::Correspondence>& tracks,
                      const int* idx, int count, Eigen::Vector3d* t) {
  Eigen::Matrix3d ata = Eigen::Matrix3d::Zero();
  Eigen::Vector3d atb = Eigen::Vector3d::Zero();
  for (int k = 0; k < count; ++k) {
    const auto& tr = tracks[static_cast<std::size_t>(idx[k])];
    const Eigen::Vector3d y = R * tr.point_prev;
    const double u = tr.cur_normalized.x(), v = tr.cur_normalized.y();
    const Eigen::Vector3d a1(1, 0, -u), a2(0, 1, -v);
    const double b1 = -(y.x() - u * y.z()), b2 = -(y.y() - v * y.z());
    ata += a1 * a1.transpose() + a2 * a2.transpose();
    atb += a1 * b1 + a2 * b2;
  }
  Eigen::LDLT<Eigen::Matrix3d> ldlt(ata);
  if (ldlt.info() != Eigen::Success) return false;
  *t = ldlt.solve(atb);
  return t->allFinite();
}

// Gauss-Newton on the reprojection error of the listed pairs, R and t updated in place.
void refinePose(const std::vector<MotionConsistencyChecker::Correspondence>& tracks,
                const std::vector<int>& idx, int iterations, Eigen::Matrix3d* R,
                Eigen::Vector3d* t) {
  for (int it = 0; it < iterations; ++it) {
    Eigen::Matrix<double, 6, 6> h = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    for (int i : idx) {
      const auto& tr = tracks[static_cast<std::size_t>(i)];
      const Eigen::Vector3d rx = *R * tr.point_prev;
      const Eigen::Vector3d y = rx + *t;
      if (y.z() < 1e-6) continue;
      const double iz = 1.0 / y.z();
      const Eigen::Vector2d r = y.head<2>() * iz - tr.cur_normalized;
      Eigen::Matrix<double, 2, 3> dproj;
      dproj << iz, 0, -y.x() * iz * iz, 0, iz, -y.y() * iz * iz;
      Eigen::Matrix<double, 2, 6> j;
      j.leftCols<3>() = -dproj * skew(rx);
      j.rightCols<3>() = dproj;
      h += j.transpose() * j;
      g += j.transpose() * r;
    }
    h.diagonal().array() += 1e-9;
    const Eigen::Matrix<double, 6, 1> dx = h.ldlt().solve(-g);
    if (!dx.allFinite()) return;
    *R = expSO3(dx.head<3>()) * *R;
    *t += dx.tail<3>();
    if (dx.norm() < 1e-10) return;
  }
}

}  // namespace

MotionConsistencyChecker::MotionConsistencyChecker(double threshold_px, double focal_px,
                                                   int iterations, int min_tracks, unsigned seed,
                                                   double min_depth_m)
    : threshold_(threshold_px / focal_px),
      focal_px_(focal_px),
      iterations_(iterations),
      min_tracks_(min_tracks),
      min_depth_m_(min_depth_m),
      rng_(seed) {}

MotionConsistencyChecker::Result MotionConsistencyChecker::check(
    const std::vector<Correspondence>& tracks, const Eigen::Matrix3d* prior) {
  if (static_cast<int>(tracks.size()) < min_tracks_) {
    Result r;
    r.labels.assign(tracks.size(), TrackLabel::kUnknown);
    r.residual_px.assign(tracks.size(), 0.0);
    return r;
  }
  std::vector<int> with_point;
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    if (tracks[i].has_point && tracks[i].point_prev.allFinite())
      with_point.push_back(static_cast<int>(i));
  }
  if (static_cast<int>(with_point.size()) >= min_tracks_)
    return checkMetric(tracks, with_point, prior);
  return checkEpipolar(tracks, prior);
}

void MotionConsistencyChecker::labelAll(const std::vector<Correspondence>& tracks,
                                        Result* r) const {
  r->labels.resize(tracks.size());
  r->residual_px.resize(tracks.size());
  r->inliers = 0;
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    const auto& tr = tracks[i];
    double e = 0.0;
    if (r->metric && tr.has_point) {
      e = reprojectionError(r->R_cur_prev, r->t_cur_prev, tr.point_prev, tr.cur_normalized, toCentre(tr));
    } else if (r->metric) {
      e = depthBoundedError(r->R_cur_prev, r->t_cur_prev, tr.prev_normalized, tr.cur_normalized,
                            1.0 / min_depth_m_, toCentre(tr));
    } else {
      e = epipolarError(r->R_cur_prev, r->t_cur_prev, tr.prev_normalized, tr.cur_normalized, toCentre(tr));
    }
    r->residual_px[i] = e * focal_px_;
    const bool ok = e < threshold_;
    r->labels[i] = ok ? TrackLabel::kConsistent : TrackLabel::kInconsistent;
    r->inliers += ok ? 1 : 0;
  }
}

MotionConsistencyChecker::Result MotionConsistencyChecker::checkMetric(
    const std::vector<Correspondence>& tracks, const std::vector<int>& with_point,
    const Eigen::Matrix3d* prior) {
  const int n = static_cast<int>(with_point.size());
  std::uniform_int_distribution<int> pick(0, n - 1);
  // MSAC: truncated squared error, so among hypotheses that explain about as many tracks the
  // one that explains them best wins (not one bent to also catch a few moving points).
  const double thr2 = threshold_ * threshold_;
  auto cost = [&](const Eigen::Matrix3d& R, const Eigen::Vector3d& t, int* count) {
    double c = 0.0;
    *count = 0;
    for (int i : with_point) {
      const auto& tr = tracks[static_cast<std::size_t>(i)];
      const double e = reprojectionError(R, t, tr.point_prev, tr.cur_normalized, toCentre(tr));
      if (e < threshold_) {
        c += e * e;
        ++*count;
      } else {
        c += thr2;
      }
    }
    return c;
  };
  bool found = false;
  double best_cost = 0.0;
  Eigen::Matrix3d best_R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d best_t = Eigen::Vector3d::Zero();
  // With a gyro rotation, every other hypothesis still comes from 3 points alone: the largest
  // consensus wins even when it does not turn like the IMU (a turning vehicle's interior).
  for (int it = 0; it < iterations_; ++it) {
    const bool use_prior = prior != nullptr && it % 2 == 0;
    const int sample_size = use_prior ? 2 : 3;
    int s[3];
    for (int k = 0; k < sample_size; ++k) {
      bool fresh = false;
      while (!fresh) {
        s[k] = with_point[static_cast<std::size_t>(pick(rng_))];
        fresh = true;
        for (int m = 0; m < k; ++m) fresh = fresh && s[m] != s[k];
      }
    }
    Eigen::Matrix3d R = prior ? *prior : Eigen::Matrix3d::Identity();
    Eigen::Vector3d t = Eigen::Vector3d::Zero();
    if (use_prior) {
      if (!solveTranslation(R, tracks, s, 2, &t)) continue;
    } else {
      refinePose(tracks, std::vector<int>(s, s + 3), 8, &R, &t);
      if (!R.allFinite() || !t.allFinite()) continue;
    }
    int count = 0;
    const double c = cost(R, t, &count);
    if (!found || c < best_cost) {
      found = true;
      best_cost = c;
      best_R = R;
      best_t = t;
    }
    if (count == n) break;  // everything agrees: the refinement below polishes the fit
  }
  Result r;
  r.valid = found;
  r.metric = true;
  r.R_cur_prev = best_R;
  r.t_cur_prev = best_t;
  // Two refine-relabel rounds absorb gyro bias and sampling noise in the best hypothesis.
  for (int round = 0; round < 2 && r.valid; ++round) {
    std::vector<int> inliers;
    for (int i : with_point) {
      const auto& tr = tracks[static_cast<std::size_t>(i)];
      if (reprojectionError(r.R_cur_prev, r.t_cur_prev, tr.point_prev, tr.cur_normalized, toCentre(tr)) <
          threshold_) {
        inliers.push_back(i);
      }
    }
    if (inliers.size() < 6) break;
    Eigen::Matrix3d R = r.R_cur_prev;
    Eigen::Vector3d t = r.t_cur_prev;
    refinePose(tracks, inliers, 5, &R, &t);
    int count = 0;
    const double c = cost(R, t, &count);
    if (c <= best_cost) {
      best_cost = c;
      r.R_cur_prev = R;
      r.t_cur_prev = t;
    }
  }
  labelAll(tracks, &r);
  return r;
}

MotionConsistencyChecker::Result MotionConsistencyChecker::checkEpipolar(
    const std::vector<Correspondence>& tracks, const Eigen::Matrix3d* prior) {
  Result r;
  r.metric = false;
  const int n = static_cast<int>(tracks.size());
  if (prior) {
    auto score = [&](const Eigen::Vector3d& t) {
      int count = 0;
      for (const auto& tr : tracks) {
        if (epipolarError(*prior, t, tr.prev_normalized, tr.cur_normalized, toCentre(tr)) < threshold_) ++count;
      }
      return count;
    };
    // Pure rotation first: a translation hypothesis must explain strictly more tracks.
    Eigen::Vector3d best_t = Eigen::Vector3d::Zero();
    int best = score(best_t);
    std::uniform_int_distribution<int> pick(0, n - 1);
    for (int it = 0; it < iterations_ && best < n; ++it) {
      const int a = pick(rng_);
      int b = pick(rng_);
      while (b == a) b = pick(rng_);
      const auto& ta = tracks[static_cast<std::size_t>(a)];
      const auto& tb = tracks[static_cast<std::size_t>(b)];
      const Eigen::Vector3d na =
          (*prior * ta.prev_normalized.homogeneous()).cross(ta.cur_normalized.homogeneous());
      const Eigen::Vector3d nb =
          (*prior * tb.prev_normalized.homogeneous()).cross(tb.cur_normalized.homogeneous());
      Eigen::Vector3d t = na.cross(nb);
      if (t.norm() < 1e-12) continue;
      t.normalize();
      const int c = score(t);
      if (c > best) {
        best = c;
        best_t = t;
      }
    }
    r.valid = true;
    r.R_cur_prev = *prior;
    r.t_cur_prev = best_t;
    labelAll(tracks, &r);
    return r;
  }
  std::vector<cv::Point2d> p0, p1;
  for (const auto& tr : tracks) {
    p0.emplace_back(tr.prev_normalized.x(), tr.prev_normalized.y());
    p1.emplace_back(tr.cur_normalized.x(), tr.cur_normalized.y());
  }
  cv::Mat mask;
  cv::Mat e =
      cv::findEssentialMat(p0, p1, cv::Mat::eye(3, 3, CV_64F), cv::RANSAC, 0.999, threshold_, mask);
  // Several solutions come stacked; the first is the one with most inliers.
  if (e.rows > 3 && e.cols == 3) e = e.rowRange(0, 3).clone();
  if (e.rows != 3 || e.cols != 3) {
    // Degenerate (e.g. no motion at all): treat the motion as a pure rotation by identity.
    r.valid = true;
    labelAll(tracks, &r);
    return r;
  }
  cv::Mat R_cv, t_cv;
  cv::recoverPose(e, p0, p1, cv::Mat::eye(3, 3, CV_64F), R_cv, t_cv, mask);
  cv::cv2eigen(R_cv, r.R_cur_prev);
  cv::cv2eigen(t_cv, r.t_cur_prev);
  r.valid = true;
  labelAll(tracks, &r);
  return r;
}

}  // namespace mcvio::frontend
