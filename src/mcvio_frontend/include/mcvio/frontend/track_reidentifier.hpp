#pragma once
#include <cstdint>
#include <deque>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "mcvio/core/time.hpp"

namespace cv {
class Feature2D;
}

namespace mcvio::frontend {

/// Recognises corners the tracker lost (they left the view, or went behind an occluder) when
/// they are detected again, by an ORB descriptor of the patch around them, so they come back
/// with their old track id. KLT alone gives every returning corner a new id; with the old one
/// the backend can tell how far it drifted while it could not see them (the conflict window
/// after an occlusion, mcvio::estimator::MapMemory). Descriptors are upright (no orientation)
/// and at the image's own scale: the view must come back at a similar distance and roll.
class TrackReidentifier {
 public:
  struct Options {
    double max_age_s = 60.0;   ///< lost tracks older than this are forgotten
    /// Lost for less than this, a track is not a candidate: the backend may still hold its
    /// landmark, and a wrong match there would pull it (a right one adds little).
    double min_age_s = 3.0;
    int max_hamming = 40;      ///< of 256 bits, for a match
    double ratio = 0.8;        ///< best distance below this x the second best
    std::size_t max_entries = 4000;  ///< the oldest go first
  };

  TrackReidentifier();
  explicit TrackReidentifier(const Options& options);

  /// Remembers tracks lost at time t, each by its id and last position in `image` (mono8).
  /// Points too close to the border for a descriptor are skipped, and so are patches that
  /// another corner of the same image (`others`, or another lost one) also matches: a repeated
  /// texture, whose copies elsewhere the patch could not tell apart either.
  void remember(const cv::Mat& image, const std::vector<std::pair<std::uint64_t, cv::Point2f>>& lost,
                const std::vector<cv::Point2f>& others, Timestamp t);
  /// For each point newly detected in `image` at time t, the id of the lost track it is (0: none);
  /// points that another of them or of `others` (the corners tracked in that image) matches are
  /// not recognised. A recognised track is forgotten, so no id comes back twice.
  std::vector<std::uint64_t> recognise(const cv::Mat& image, const std::vector<cv::Point2f>& points,
                                       const std::vector<cv::Point2f>& others, Timestamp t);
  void clear() { entries_.clear(); }
  std::size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    std::uint64_t id = 0;
    Timestamp lost = 0;
    cv::Mat descriptor;  ///< 1 x 32, CV_8U
  };
  /// Descriptors of the points; row_of_point[i] is point i's row, -1 where none could be made.
  void describe(const cv::Mat& image, const std::vector<cv::Point2f>& points, cv::Mat* descriptors,
                std::vector<int>* row_of_point);
  void forgetBefore(Timestamp t);
  /// For the first `n` rows of `descriptors`, whether another row is within max_hamming.
  std::vector<char> ambiguous(const cv::Mat& descriptors, int n) const;

  Options options_;
  cv::Ptr<cv::Feature2D> orb_;
  std::deque<Entry> entries_;  ///< oldest first
};

}  // namespace mcvio::frontend
