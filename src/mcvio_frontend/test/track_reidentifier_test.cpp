// Unit tests of TrackReidentifier: lost corners recognised again by their descriptor.
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "mcvio/frontend/track_reidentifier.hpp"

using namespace mcvio;
using mcvio::frontend::TrackReidentifier;

namespace {

/// Blurred random blobs: corners everywhere, none alike.
cv::Mat texture(unsigned seed) {
  cv::Mat img(480, 752, CV_8UC1, cv::Scalar(128));
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> x(0, 751), y(0, 479), r(2, 9), g(0, 255);
  for (int i = 0; i < 4000; ++i) cv::circle(img, {x(rng), y(rng)}, r(rng), cv::Scalar(g(rng)), -1);
  cv::GaussianBlur(img, img, cv::Size(3, 3), 0.8);
  return img;
}

/// The image moved by (dx, dy) pixels: the view come back a little off.
cv::Mat shifted(const cv::Mat& img, int dx, int dy) {
  cv::Mat out(img.size(), img.type(), cv::Scalar(128));
  img(cv::Rect(0, 0, img.cols - dx, img.rows - dy)).copyTo(out(cv::Rect(dx, dy, img.cols - dx, img.rows - dy)));
  return out;
}

std::vector<cv::Point2f> grid() {
  std::vector<cv::Point2f> pts;
  for (int y = 60; y < 420; y += 45)
    for (int x = 60; x < 690; x += 60) pts.emplace_back(static_cast<float>(x) + 0.3f, static_cast<float>(y) + 0.6f);
  return pts;
}

}  // namespace

TEST(TrackReidentifier, GivesReturningCornersTheirOldIds) {
  TrackReidentifier reid;
  const cv::Mat before = texture(1);
  const auto pts = grid();
  std::vector<std::pair<std::uint64_t, cv::Point2f>> lost;
  for (std::size_t i = 0; i < pts.size(); ++i) lost.emplace_back(100 + i, pts[i]);
  reid.remember(before, lost, {}, fromSeconds(1.0));
  EXPECT_EQ(reid.size(), pts.size());

  std::vector<cv::Point2f> again;
  for (const auto& p : pts) again.emplace_back(p.x + 12.0f, p.y + 7.0f);
  const auto ids = reid.recognise(shifted(before, 12, 7), again, {}, fromSeconds(20.0));
  ASSERT_EQ(ids.size(), pts.size());
  int right = 0, wrong = 0;
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] == 100 + i) ++right;
    else if (ids[i] != 0) ++wrong;
  }
  EXPECT_GE(right, static_cast<int>(0.9 * pts.size())) << right << " of " << pts.size();
  EXPECT_EQ(wrong, 0);
  // Each comes back once.
  EXPECT_EQ(reid.size(), pts.size() - static_cast<std::size_t>(right));
  const auto twice = reid.recognise(shifted(before, 12, 7), again, {}, fromSeconds(20.1));
  for (std::size_t i = 0; i < twice.size(); ++i) {
    if (ids[i] != 0) {
      EXPECT_EQ(twice[i], 0u);
    }
  }
}

TEST(TrackReidentifier, AnotherViewIsNotRecognised) {
  TrackReidentifier reid;
  const auto pts = grid();
  std::vector<std::pair<std::uint64_t, cv::Point2f>> lost;
  for (std::size_t i = 0; i < pts.size(); ++i) lost.emplace_back(1 + i, pts[i]);
  reid.remember(texture(1), lost, {}, fromSeconds(1.0));
  const auto ids = reid.recognise(texture(2), pts, {}, fromSeconds(2.0));
  int recognised = 0;
  for (auto id : ids) recognised += id != 0 ? 1 : 0;
  EXPECT_LE(recognised, 1) << "random patches matched";
}

TEST(TrackReidentifier, ForgetsOldAndBorderCorners) {
  TrackReidentifier::Options o;
  o.max_age_s = 5.0;
  TrackReidentifier reid(o);
  const cv::Mat img = texture(3);
  reid.remember(img, {{1, {200.f, 200.f}}, {2, {3.f, 3.f}}}, {}, fromSeconds(1.0));
  EXPECT_EQ(reid.size(), 1u) << "no descriptor 3 px from the corner of the image";
  EXPECT_EQ(reid.recognise(img, {{200.f, 200.f}}, {}, fromSeconds(7.0))[0], 0u) << "lost 6 s ago, max_age_s 5";
  EXPECT_EQ(reid.size(), 0u);
  reid.remember(img, {{4, {300.f, 250.f}}}, {}, fromSeconds(8.0));
  EXPECT_EQ(reid.recognise(img, {{300.f, 250.f}}, {}, fromSeconds(9.0))[0], 0u) << "lost 1 s ago, min_age_s 3";
  EXPECT_EQ(reid.recognise(img, {{300.f, 250.f}}, {}, fromSeconds(11.0))[0], 4u);
  EXPECT_TRUE(reid.recognise(cv::Mat(), {}, {}, fromSeconds(9.0)).empty());
  reid.remember(img, {{5, {300.f, 250.f}}}, {}, fromSeconds(9.0));
  reid.clear();
  EXPECT_EQ(reid.size(), 0u);
}

TEST(TrackReidentifier, ARepeatedPatchIsNeitherRememberedNorRecognised) {
  // The same texture twice side by side: a corner in one copy has its twin 300 px away.
  cv::Mat tile = texture(4)(cv::Rect(0, 0, 300, 480)).clone();
  cv::Mat img(480, 752, CV_8UC1, cv::Scalar(128));
  tile.copyTo(img(cv::Rect(50, 0, 300, 480)));
  tile.copyTo(img(cv::Rect(350, 0, 300, 480)));
  const cv::Point2f corner(150.3f, 200.6f), twin(450.3f, 200.6f), unique(700.2f, 300.4f);
  TrackReidentifier reid;
  reid.remember(img, {{1, corner}}, {twin}, fromSeconds(1.0));
  EXPECT_EQ(reid.size(), 0u) << "its twin is in the same image";
  reid.remember(img, {{1, corner}}, {unique}, fromSeconds(1.0));
  ASSERT_EQ(reid.size(), 1u);
  // Detected again, but so is its twin: either could be the one that was lost.
  EXPECT_EQ(reid.recognise(img, {corner, twin}, {}, fromSeconds(5.0)), (std::vector<std::uint64_t>{0, 0}));
  EXPECT_EQ(reid.recognise(img, {corner}, {unique}, fromSeconds(5.0)), (std::vector<std::uint64_t>{1}));
}
