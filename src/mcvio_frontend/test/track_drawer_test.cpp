#include "mcvio/frontend/track_drawer.hpp"

#include <gtest/gtest.h>

#include "mcvio/core/input_error.hpp"

namespace mcvio::frontend {
namespace {

TEST(TrackDrawer, ColoursByLabelInRgbOrder) {
  const cv::Mat grey(100, 200, CV_8UC1, cv::Scalar(50));
  std::vector<TrackHistory> tracks;
  tracks.push_back({1, TrackLabel::kConsistent, true, {{20, 20}, {30, 30}, {40, 40}}});
  tracks.push_back({2, TrackLabel::kInconsistent, true, {{150, 50}}});
  const cv::Mat out = drawTracks(grey, tracks);
  ASSERT_EQ(out.type(), CV_8UC3);
  ASSERT_EQ(out.size(), grey.size());
  const cv::Vec3b green = out.at<cv::Vec3b>(40, 40);
  EXPECT_EQ(green[0], 0);
  EXPECT_EQ(green[1], 220);
  const cv::Vec3b red = out.at<cv::Vec3b>(50, 150);
  EXPECT_EQ(red[0], 255);
  EXPECT_EQ(red[1], 0);
  // History line between the older positions.
  const cv::Vec3b mid = out.at<cv::Vec3b>(25, 25);
  EXPECT_GT(mid[1], 100);
  EXPECT_EQ(out.at<cv::Vec3b>(90, 10), cv::Vec3b(50, 50, 50));
  // Dark outline just outside the red dot (whose green and blue are 0 like the outline's), so
  // marks stay visible on bright texture; the grey background has 50 there.
  const cv::Vec3b rim = out.at<cv::Vec3b>(50, 154);
  EXPECT_LT(rim[1], 30);
  EXPECT_LT(rim[2], 30);
}

TEST(TrackDrawer, DarkensTheMask) {
  const cv::Mat grey(100, 200, CV_8UC1, cv::Scalar(200));
  cv::Mat mask(100, 200, CV_8UC1, cv::Scalar(0));
  mask.colRange(0, 50).setTo(255);
  const cv::Mat out = drawTracks(grey, {}, mask);
  EXPECT_EQ(out.at<cv::Vec3b>(50, 100), cv::Vec3b(200, 200, 200));
  EXPECT_EQ(out.at<cv::Vec3b>(50, 10), cv::Vec3b(70, 70, 70));
  EXPECT_THROW(drawTracks(grey, {}, cv::Mat(100, 100, CV_8UC1, cv::Scalar(0))), InputError);
}

TEST(TrackDrawer, RejectsOtherImageTypes) {
  EXPECT_THROW(drawTracks(cv::Mat(10, 10, CV_16UC1), {}), InputError);
}

}  // namespace
}  // namespace mcvio::frontend
