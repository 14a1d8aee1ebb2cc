#include "mcvio/frontend/track_reidentifier.hpp"

#include <limits>

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

namespace mcvio::frontend {

namespace {
// ORB's sampling pattern covers a 31 px patch; its blur needs a few pixels more.
constexpr int kPatch = 31;
}  // namespace

TrackReidentifier::TrackReidentifier() : TrackReidentifier(Options()) {}

// One level and no detection of its own: ORB only describes the given points.
TrackReidentifier::TrackReidentifier(const Options& options)
    : options_(options), orb_(cv::ORB::create(500, 1.2f, 1, kPatch, 0, 2, cv::ORB::HARRIS_SCORE, kPatch)) {}

void TrackReidentifier::describe(const cv::Mat& image, const std::vector<cv::Point2f>& points, cv::Mat* descriptors,
                                 std::vector<int>* row_of_point) {
  row_of_point->assign(points.size(), -1);
  descriptors->release();
  if (points.empty() || image.empty()) return;
  std::vector<cv::KeyPoint> kps;
  kps.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    // Upright: angle 0 (a provided keypoint's angle is used as given), level 0.
    cv::KeyPoint kp(points[i], static_cast<float>(kPatch), 0.0f, 0.0f, 0, static_cast<int>(i));
    kps.push_back(kp);
  }
  // compute() drops the points too close to the border: each row is mapped back through class_id.
  orb_->compute(image, kps, *descriptors);
  for (std::size_t r = 0; r < kps.size(); ++r) (*row_of_point)[static_cast<std::size_t>(kps[r].class_id)] = static_cast<int>(r);
}

void TrackReidentifier::forgetBefore(Timestamp t) {
  while (!entries_.empty() && (entries_.front().lost < t || entries_.size() > options_.max_entries)) entries_.pop_front();
}

void TrackReidentifier::remember(const cv::Mat& image, const std::vector<std::pair<std::uint64_t, cv::Point2f>>& lost,
                                 Timestamp t) {
  if (lost.empty()) return;
  std::vector<cv::Point2f> points;
  points.reserve(lost.size());
  for (const auto& l : lost) points.push_back(l.second);
  cv::Mat desc;
  std::vector<int> row;
  describe(image, points, &desc, &row);
  for (std::size_t i = 0; i < lost.size(); ++i)
    if (row[i] >= 0) entries_.push_back({lost[i].first, t, desc.row(row[i]).clone()});
  forgetBefore(t - fromSeconds(options_.max_age_s));
}

std::vector<std::uint64_t> TrackReidentifier::recognise(const cv::Mat& image, const std::vector<cv::Point2f>& points,
                                                        Timestamp t) {
  std::vector<std::uint64_t> ids(points.size(), 0);
  forgetBefore(t - fromSeconds(options_.max_age_s));
  if (entries_.empty() || points.empty()) return ids;
  cv::Mat desc;
  std::vector<int> row;
  describe(image, points, &desc, &row);
  std::vector<char> taken(entries_.size(), 0);
  const Timestamp lost_before = t - fromSeconds(options_.min_age_s);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (row[i] < 0) continue;
    const cv::Mat d = desc.row(row[i]);
    int best = std::numeric_limits<int>::max(), second = best;
    std::size_t best_k = 0;
    for (std::size_t k = 0; k < entries_.size() && entries_[k].lost <= lost_before; ++k) {
      const int h = static_cast<int>(cv::norm(d, entries_[k].descriptor, cv::NORM_HAMMING));
      if (h < best) {
        second = best;
        best = h;
        best_k = k;
      } else if (h < second) {
        second = h;
      }
    }
    // Unambiguous and close: a repeated texture gives two similar candidates, and neither is taken.
    if (best > options_.max_hamming || taken[best_k] || static_cast<double>(best) >= options_.ratio * second) continue;
    taken[best_k] = 1;
    ids[i] = entries_[best_k].id;
  }
  std::deque<Entry> left;
  for (std::size_t k = 0; k < entries_.size(); ++k)
    if (!taken[k]) left.push_back(std::move(entries_[k]));
  entries_ = std::move(left);
  return ids;
}

}  // namespace mcvio::frontend
