// Masks (FrontendOptions::mask0 / mask1): no feature where a camera's mask is white.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include <opencv2/imgcodecs.hpp>

#include "mcvio/core/input_error.hpp"
#include "mcvio/frontend/feature_tracker.hpp"
#include "synthetic_stereo_scene.hpp"

namespace mcvio::frontend {
namespace {

using testing::SyntheticStereoScene;

constexpr int kMaskedColumns = 250;  // cam0's mask: the left third of the 752 px image

class FeatureTrackerMaskTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ::testing::TempDir() + "/mcvio_masks_" + std::to_string(getpid());
    std::filesystem::create_directories(dir_);
    SyntheticStereoScene::Config c;
    scene_ = std::make_unique<SyntheticStereoScene>(c);
    for (int k = 0; k < 25; ++k) frames_.push_back(scene_->render(k));
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::string writeMask(const std::string& name, int w, int h, int masked_columns) const {
    cv::Mat m(h, w, CV_8UC1, cv::Scalar(0));
    m.colRange(0, masked_columns).setTo(255);
    const std::string path = dir_ + "/" + name;
    EXPECT_TRUE(cv::imwrite(path, m));
    return path;
  }

  struct Counts {
    int left_in_masked_columns = 0, left = 0, right = 0, stereo_matched = 0;
  };
  Counts run(const FrontendOptions& o) const {
    FeatureTracker tracker(o);
    tracker.setCalibration(scene_->calibration());
    Counts n;
    for (const StereoInput& in : frames_) {
      const TrackingResult r = tracker.track(in);
      EXPECT_TRUE(r.ok()) << r.message;
      n.stereo_matched += r.stats.stereo_matched;
      for (const FeatureObservation& f : r.features.features) {
        if (f.camera_index == 1) {
          ++n.right;
          continue;
        }
        ++n.left;
        if (f.pixel.x() < kMaskedColumns - 0.5) ++n.left_in_masked_columns;
      }
    }
    return n;
  }

  std::string dir_;
  std::unique_ptr<SyntheticStereoScene> scene_;
  std::vector<StereoInput> frames_;
};

TEST_F(FeatureTrackerMaskTest, NoFeatureWhereTheMaskIsWhite) {
  const Counts plain = run(FrontendOptions());
  ASSERT_GT(plain.left_in_masked_columns, 500) << "the scene has texture under the mask";

  FrontendOptions o;
  o.mask0 = writeMask("mask0.png", 752, 480, kMaskedColumns);
  const Counts masked = run(o);
  EXPECT_EQ(masked.left_in_masked_columns, 0);
  EXPECT_GT(masked.left, plain.left / 2) << "the rest of the image is tracked as before";
  EXPECT_GT(masked.stereo_matched, masked.left / 2);

  // A white cam1 mask leaves the left tracks but refuses every stereo match.
  o.mask1 = writeMask("mask1.png", 752, 480, 752);
  const Counts no_right = run(o);
  EXPECT_GT(no_right.left, 0);
  EXPECT_EQ(no_right.stereo_matched, 0);
  EXPECT_EQ(no_right.right, 0);
}

TEST_F(FeatureTrackerMaskTest, BadMasksAreNamed) {
  FrontendOptions o;
  o.mask0 = dir_ + "/missing.png";
  try {
    FeatureTracker t(o);
    FAIL() << "a missing mask must throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'mask0'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("missing.png"), std::string::npos) << e.what();
  }
  o.mask0.clear();
  o.mask1 = dir_ + "/not_an_image.png";
  std::ofstream(o.mask1) << "mask: none\n";
  EXPECT_THROW(FeatureTracker{o}, InputError);

  o.mask1 = writeMask("small.png", 640, 480, 10);
  FeatureTracker t(o);
  try {
    t.setCalibration(scene_->calibration());
    FAIL() << "a mask of another size must throw";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("'mask1'"), std::string::npos) << m;
    EXPECT_NE(m.find("640x480"), std::string::npos) << m;
    EXPECT_NE(m.find("752x480"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace mcvio::frontend
