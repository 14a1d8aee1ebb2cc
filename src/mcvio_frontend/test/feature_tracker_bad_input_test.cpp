// Bad frames are skipped with a clear status and message; the tracker keeps its tracks.
#include <gtest/gtest.h>

#include <limits>
#include <opencv2/core.hpp>
#include <set>
#include <vector>

#include "mcvio/core/input_error.hpp"
#include "mcvio/frontend/feature_tracker.hpp"
#include "synthetic_stereo_scene.hpp"

namespace mcvio::frontend {
namespace {

using testing::SyntheticStereoScene;

class FeatureTrackerBadInputTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new SyntheticStereoScene({});
    frames_ = new std::vector<StereoInput>();
    for (int k = 0; k < 4; ++k) frames_->push_back(scene_->render(k));
  }
  static void TearDownTestSuite() {
    delete scene_;
    delete frames_;
  }
  void SetUp() override { tracker_.setCalibration(scene_->calibration()); }

  static std::set<std::uint64_t> ids(const TrackingResult& r) {
    std::set<std::uint64_t> s;
    for (const auto& o : r.features.features) s.insert(o.track_id);
    return s;
  }
  // After a rejected frame the next good one must continue the same tracks.
  void expectRecovers(const TrackingResult& before, int next) {
    const TrackingResult r = tracker_.track((*frames_)[static_cast<std::size_t>(next)]);
    ASSERT_TRUE(r.ok()) << r.message;
    const auto a = ids(before), b = ids(r);
    int kept = 0;
    for (auto id : a) kept += b.count(id) ? 1 : 0;
    EXPECT_GE(kept, 0.9 * static_cast<double>(a.size()));
  }

  static SyntheticStereoScene* scene_;
  static std::vector<StereoInput>* frames_;
  FeatureTracker tracker_;
};
SyntheticStereoScene* FeatureTrackerBadInputTest::scene_ = nullptr;
std::vector<StereoInput>* FeatureTrackerBadInputTest::frames_ = nullptr;

TEST_F(FeatureTrackerBadInputTest, NoCalibrationSkipsUntilItArrives) {
  FeatureTracker fresh;
  const TrackingResult r = fresh.track((*frames_)[0]);
  EXPECT_EQ(r.status, FrameStatus::kNoCalibration);
  EXPECT_NE(r.message.find("calibration"), std::string::npos) << r.message;
  EXPECT_TRUE(r.features.features.empty());
  fresh.setCalibration(scene_->calibration());
  EXPECT_TRUE(fresh.track((*frames_)[1]).ok());
}

TEST_F(FeatureTrackerBadInputTest, WrongImageSizeIsSkipped) {
  const TrackingResult first = tracker_.track((*frames_)[0]);
  ASSERT_TRUE(first.ok());
  StereoInput bad = (*frames_)[1];
  bad.left = cv::Mat(480, 640, CV_8UC1, cv::Scalar(100));
  const TrackingResult r = tracker_.track(bad);
  EXPECT_EQ(r.status, FrameStatus::kBadImage);
  EXPECT_NE(r.message.find("640x480"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("752x480"), std::string::npos) << r.message;
  expectRecovers(first, 1);
}

TEST_F(FeatureTrackerBadInputTest, WrongEncodingIsSkipped) {
  const TrackingResult first = tracker_.track((*frames_)[0]);
  ASSERT_TRUE(first.ok());
  StereoInput bad = (*frames_)[1];
  cv::Mat rgb;
  cv::merge(std::vector<cv::Mat>{bad.right, bad.right, bad.right}, rgb);
  bad.right = rgb;
  TrackingResult r = tracker_.track(bad);
  EXPECT_EQ(r.status, FrameStatus::kBadImage);
  EXPECT_NE(r.message.find("mono8"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("right"), std::string::npos) << r.message;
  bad = (*frames_)[1];
  bad.left.convertTo(bad.left, CV_16U, 256.0);
  r = tracker_.track(bad);
  EXPECT_EQ(r.status, FrameStatus::kBadImage);
  EXPECT_NE(r.message.find("CV_16UC1"), std::string::npos) << r.message;
  expectRecovers(first, 1);
}

TEST_F(FeatureTrackerBadInputTest, MissingRightImageIsSkipped) {
  const TrackingResult first = tracker_.track((*frames_)[0]);
  ASSERT_TRUE(first.ok());
  StereoInput bad = (*frames_)[1];
  bad.right = cv::Mat();
  const TrackingResult r = tracker_.track(bad);
  EXPECT_EQ(r.status, FrameStatus::kMissingRight);
  EXPECT_NE(r.message.find("right image is missing"), std::string::npos) << r.message;
  expectRecovers(first, 1);
}

TEST_F(FeatureTrackerBadInputTest, OutOfOrderFramesAreSkipped) {
  ASSERT_TRUE(tracker_.track((*frames_)[0]).ok());
  const TrackingResult second = tracker_.track((*frames_)[2]);
  ASSERT_TRUE(second.ok());
  EXPECT_EQ(tracker_.track((*frames_)[1]).status, FrameStatus::kOutOfOrder);
  const TrackingResult same = tracker_.track((*frames_)[2]);
  EXPECT_EQ(same.status, FrameStatus::kOutOfOrder);
  EXPECT_NE(same.message.find("not after"), std::string::npos) << same.message;
  EXPECT_EQ(tracker_.framesProcessed(), 2u);
  expectRecovers(second, 3);
}

TEST_F(FeatureTrackerBadInputTest, NonFiniteImuSamplesAreIgnored) {
  ASSERT_TRUE(tracker_.track((*frames_)[0]).ok());
  StereoInput in = (*frames_)[1];
  in.imu.front().gyro.x() = std::numeric_limits<double>::quiet_NaN();
  in.imu.push_back(in.imu.front());  // and one sample back in time
  in.imu.back().gyro.x() = 0.0;
  const TrackingResult r = tracker_.track(in);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_EQ(r.stats.imu_rejected, 2);
  EXPECT_NE(r.message.find("ignored 2 IMU"), std::string::npos) << r.message;
  for (const auto& o : r.features.features)
    ASSERT_TRUE(o.pixel.allFinite() && o.normalized.allFinite());
}

TEST_F(FeatureTrackerBadInputTest, FlatFrameLosesTracksThenTrackingRecovers) {
  ASSERT_TRUE(tracker_.track((*frames_)[0]).ok());
  StereoInput flat = (*frames_)[1];
  flat.left = cv::Mat(flat.left.size(), CV_8UC1, cv::Scalar(0));
  flat.right = cv::Mat(flat.right.size(), CV_8UC1, cv::Scalar(0));
  const TrackingResult dark = tracker_.track(flat);
  ASSERT_TRUE(dark.ok()) << dark.message;  // a valid if useless image
  EXPECT_LT(dark.stats.tracked, 20);
  EXPECT_EQ(dark.stats.stereo_matched, 0);
  const TrackingResult again = tracker_.track((*frames_)[2]);
  ASSERT_TRUE(again.ok()) << again.message;
  EXPECT_GE(again.stats.stereo_matched, 150);
}

TEST_F(FeatureTrackerBadInputTest, MissingImuOnlyDisablesThePrediction) {
  ASSERT_TRUE(tracker_.track((*frames_)[0]).ok());
  StereoInput in = (*frames_)[1];
  ASSERT_TRUE(tracker_.track(in).stats.gyro_prediction);
  in = (*frames_)[3];  // frame 2's samples never arrive: a 50 ms hole in the IMU stream
  const TrackingResult r = tracker_.track(in);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_FALSE(r.stats.gyro_prediction);
  EXPECT_GE(r.stats.tracked, 150);
  EXPECT_TRUE(r.stats.metric_check);
}

TEST_F(FeatureTrackerBadInputTest, UnusableCalibrationThrows) {
  StereoRigCalibration c = scene_->calibration();
  c.cam1.T_BC = c.cam0.T_BC;
  EXPECT_THROW(tracker_.setCalibration(c), InputError);
  c = scene_->calibration();
  c.cam1.model = CameraModel(640, 480, {400, 400, 320, 240}, DistortionModel::kNone);
  EXPECT_THROW(tracker_.setCalibration(c), InputError);
  c = scene_->calibration();
  c.cam0.model = CameraModel();  // the default 1x1 camera: no calibration was read
  EXPECT_THROW(tracker_.setCalibration(c), InputError);
  c = scene_->calibration();
  c.cam0.T_BC.linear() *= 1.5;
  EXPECT_THROW(tracker_.setCalibration(c), InputError);
}

}  // namespace
}  // namespace mcvio::frontend
