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

std::vector<char> TrackReidentifier::ambiguous(const cv::Mat& descriptors, int n) const {
  std::vector<char> out(static_cast<std::size_t>(n), 0);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < descriptors.rows && !out[static_cast<std::size_t>(i)]; ++j)
      if (j != i && cv::norm(descriptors.row(i), descriptors.row(j), cv::NORM_HAMMING) <= options_.max_hamming)
        out[static_cast<std::size_t>(i)] = 1;
  return out;
}

void TrackReidentifier::remember(const cv::Mat& image, const std::vector<std::pair<std::uint64_t, cv::Point2f>>& lost,
                                 const std::vector<cv::Point2f>& others, Timestamp t) {
  if (lost.empty()) return;
  std::vector<cv::Point2f> points;
  points.reserve(lost.size() + others.size());
  for (const auto& l : lost) points.push_back(l.second);
  points.insert(points.end(), others.begin(), others.end());
  cv::Mat desc;
  std::vector<int> row;
  describe(image, points, &desc, &row);
  // Rows of the lost points first, so ambiguous() sees them as the first rows.
  cv::Mat ordered(0, desc.cols, desc.type());
  std::vector<std::uint64_t> ids;
  for (std::size_t i = 0; i < lost.size(); ++i)
    if (row[i] >= 0) {
      ordered.push_back(desc.row(row[i]));
      ids.push_back(lost[i].first);
    }
  const int n = ordered.rows;
  for (std::size_t i = lost.size(); i < points.size(); ++i)
    if (row[i] >= 0) ordered.push_back(desc.row(row[i]));
  const std::vector<char> repeated = ambiguous(ordered, n);
  for (int i = 0; i < n; ++i)
    if (!repeated[static_cast<std::size_t>(i)]) entries_.push_back({ids[static_cast<std::size_t>(i)], t, ordered.row(i).clone()});
  forgetBefore(t - fromSeconds(options_.max_age_s));
}

std::vector<std::uint64_t> TrackReidentifier::recognise(const cv::Mat& image, const std::vector<cv::Point2f>& points,
                                                        const std::vector<cv::Point2f>& others, Timestamp t) {
  std::vector<std::uint64_t> ids(points.size(), 0);
  forgetBefore(t - fromSeconds(options_.max_age_s));
  if (entries_.empty() || points.empty()) return ids;
  std::vector<cv::Point2f> all(points);
  all.insert(all.end(), others.begin(), others.end());
  cv::Mat desc;
  std::vector<int> row;
  describe(image, all, &desc, &row);
  // The new points' rows first, so ambiguous() sees them as the first rows.
  cv::Mat ordered(0, desc.cols, desc.type());
  std::vector<int> ordered_row(points.size(), -1);
  for (std::size_t i = 0; i < points.size(); ++i)
    if (row[i] >= 0) {
      ordered_row[i] = ordered.rows;
      ordered.push_back(desc.row(row[i]));
    }
  const int n = ordered.rows;
  for (std::size_t i = points.size(); i < all.size(); ++i)
    if (row[i] >= 0) ordered.push_back(desc.row(row[i]));
  const std::vector<char> repeated = ambiguous(ordered, n);
  std::vector<char> taken(entries_.size(), 0);
  const Timestamp lost_before = t - fromSeconds(options_.min_age_s);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (ordered_row[i] < 0 || repeated[static_cast<std::size_t>(ordered_row[i])]) continue;
    const cv::Mat d = ordered.row(ordered_row[i]);
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
