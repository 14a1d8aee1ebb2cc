#include "mcvio/evaluation/ate.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

#include "mcvio/core/input_error.hpp"

namespace mcvio::evaluation {

namespace {

double rotationAngleDeg(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return Eigen::AngleAxisd(a.conjugate() * b).angle() * 180.0 / M_PI;
}

ErrorStatistics subset(const std::vector<StampedPose>& poses, const std::vector<double>& errors,
                       const std::function<bool(Timestamp)>& select) {
  std::vector<double> kept;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (select(poses[i].t)) kept.push_back(errors[i]);
  }
  return ErrorStatistics::of(kept);
}

}  // namespace

ErrorStatistics AteResult::translationWithin(const std::function<bool(Timestamp)>& select) const {
  return subset(aligned_estimate, translation_errors, select);
}

ErrorStatistics AteResult::rotationWithin(const std::function<bool(Timestamp)>& select) const {
  return subset(aligned_estimate, rotation_errors_deg, select);
}

AteResult computeAte(const Trajectory& estimate, const Trajectory& ground_truth,
                     Alignment alignment, const AteOptions& options) {
  const AssociatedPoses pairs = associate(estimate, ground_truth, options.association);
  if (pairs.size() == 0) {
    std::ostringstream msg;
    msg << std::fixed << std::setprecision(3) << "estimate " << (estimate.source().empty() ? "(unnamed)" : estimate.source())
        << " and ground truth " << (ground_truth.source().empty() ? "(unnamed)" : ground_truth.source())
        << " share no time: estimate " << estimate.size() << " poses " << toSeconds(estimate.startTime())
        << ".." << toSeconds(estimate.endTime()) << " s, ground truth " << ground_truth.size()
        << " poses " << toSeconds(ground_truth.startTime()) << ".." << toSeconds(ground_truth.endTime())
        << " s";
    throw InputError(msg.str());
  }
  AteResult r;
  r.alignment = alignment;
  r.unmatched = pairs.unmatched;
  const AlignmentResult fit = alignPoses(alignment, pairs.estimate, pairs.ground_truth, options.alignment);
  r.T_gt_est = fit.T_gt_est;
  r.rotation_from_orientations = fit.rotation_from_orientations;
  r.position_spread_m = fit.position_spread_m;
  const Eigen::Quaterniond q_align(r.T_gt_est.linear());
  r.ground_truth = pairs.ground_truth;
  r.aligned_estimate.reserve(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    StampedPose a = pairs.estimate[i];
    a.p = r.T_gt_est * a.p;
    a.q = (q_align * a.q).normalized();
    r.aligned_estimate.push_back(a);
    r.translation_errors.push_back((pairs.ground_truth[i].p - a.p).norm());
    r.rotation_errors_deg.push_back(rotationAngleDeg(pairs.ground_truth[i].q, a.q));
  }
  r.translation = ErrorStatistics::of(r.translation_errors);
  r.rotation = ErrorStatistics::of(r.rotation_errors_deg);
  return r;
}

}  // namespace mcvio::evaluation
