#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>

#include <opencv2/imgproc.hpp>

#include "mcvio/dataset/euroc_dataset.hpp"
#include "mcvio/sim/euroc_rig_defaults.hpp"
#include "mcvio/sim/image_injector.hpp"

namespace mcvio::sim {
namespace {

TEST(ImageInjector, ThePlaneAppearsConsistentlyInBothCameras) {
  const StereoRigCalibration rig = eurocRigDefaults();
  InjectOptions o;
  o.pixel_noise_sigma = 0;
  o.spin_rate = 0;
  o.velocity_mps = {0.3, 0.0, 0.0};
  const ImageInjector injector(o, rig);
  for (double s : {0.0, 1.0, 2.0}) {
    cv::Mat left = cv::Mat::zeros(480, 752, CV_8UC1), right = left.clone();
    const Timestamp t = fromSeconds(o.onset_s + s);
    const dataset::ConflictLabel label = injector.overlay(t, t, left, right);
    ASSERT_TRUE(label.in_conflict);
    EXPECT_EQ(label.motion, "injected_image");
    EXPECT_NEAR(label.covered_fraction, cv::countNonZero(left) / (752.0 * 480.0), 1e-3);
    const Eigen::Vector3d centre_c0 = injector.planeInCam0(s).translation();
    const Eigen::Vector3d centre_c1 = rig.cam1.T_BC.inverse() * (rig.cam0.T_BC * centre_c0);
    Eigen::Vector2d p0, p1;
    ASSERT_TRUE(rig.cam0.model.project(centre_c0, &p0));
    ASSERT_TRUE(rig.cam1.model.project(centre_c1, &p1));
    // The plane's centre lands inside the overlay in both images.
    EXPECT_GT(left.at<std::uint8_t>(static_cast<int>(std::lround(p0.y())), static_cast<int>(std::lround(p0.x()))), 0);
    EXPECT_GT(right.at<std::uint8_t>(static_cast<int>(std::lround(p1.y())), static_cast<int>(std::lround(p1.x()))), 0);
    // Every overlay pixel of cam0 shows the same texture point as its stereo correspondence in
    // cam1 (pixel -> ray -> plane -> cam1): the two views agree on the plane's depth.
    const Eigen::Isometry3d T_c0_plane = injector.planeInCam0(s);
    const Eigen::Vector3d n = T_c0_plane.linear().col(2);
    const Eigen::Isometry3d T_c1_c0 = rig.cam1.T_BC.inverse() * rig.cam0.T_BC;
    // Mean grey difference between a cam0 pixel and its cam1 correspondence assuming the plane
    // were `scale` times as far; texture edges make a wrong depth stand out.
    auto medianDifference = [&](double scale) {
      std::vector<double> diffs;
      for (int v = 0; v < 480; v += 7)
        for (int u = 0; u < 752; u += 7) {
          if (left.at<std::uint8_t>(v, u) == 0) continue;
          Eigen::Vector2d xy;
          if (!rig.cam0.model.unproject(Eigen::Vector2d(u, v), &xy)) continue;
          const Eigen::Vector3d ray(xy.x(), xy.y(), 1.0);
          const Eigen::Vector3d p_c0 = scale * ray * (n.dot(T_c0_plane.translation()) / n.dot(ray));
          Eigen::Vector2d q;
          if (!rig.cam1.model.project(T_c1_c0 * p_c0, &q) || !rig.cam1.model.isInImage(q, 2)) continue;
          cv::Mat patch;
          cv::getRectSubPix(right, cv::Size(1, 1), cv::Point2f(static_cast<float>(q.x()), static_cast<float>(q.y())),
                            patch, CV_32F);
          diffs.push_back(std::abs(patch.at<float>(0, 0) - left.at<std::uint8_t>(v, u)));
        }
      EXPECT_GT(diffs.size(), 100u);
      double sum = 0;
      for (double d : diffs) sum += d;
      return diffs.empty() ? 1e9 : sum / diffs.size();
    };
    const double right_depth = medianDifference(1.0), wrong_depth = medianDifference(1.1);
    EXPECT_LT(right_depth, 8.0) << "s=" << s;
    EXPECT_LT(2.0 * right_depth, wrong_depth) << "s=" << s;
    std::cout << "s=" << s << " mean grey difference " << right_depth << " (10% deeper: " << wrong_depth << ")\n";
  }
  // Outside [onset, onset + duration) nothing changes.
  cv::Mat left = cv::Mat::zeros(480, 752, CV_8UC1), right = left.clone();
  EXPECT_FALSE(injector.overlay(0, fromSeconds(o.onset_s + o.duration_s + 0.01), left, right).in_conflict);
  EXPECT_EQ(cv::countNonZero(left), 0);
}

TEST(ImageInjector, InjectsIntoTheRealEurocExcerpt) {
  const char* shared = std::getenv("MCVIO_SHARED_DIR");
  if (!shared) GTEST_SKIP() << "MCVIO_SHARED_DIR not set";
  const std::string input = std::string(shared) + "/data/euroc_V1_01_excerpt";
  if (!std::filesystem::exists(input)) GTEST_SKIP() << input << " absent";
  const std::string out = (std::filesystem::temp_directory_path() / "mcvio_sim_inject_test").string();
  std::filesystem::remove_all(out);
  InjectOptions o;
  o.input_dir = input;
  o.output_dir = out;
  o.onset_s = 1.0;
  o.duration_s = 2.0;
  const InjectSummary summary = runInjection(o);
  EXPECT_EQ(summary.frames, 95u);
  EXPECT_EQ(summary.injected_frames, 40u);
  const auto before = dataset::EurocDataset::open(input);
  const auto after = dataset::EurocDataset::open(out);
  ASSERT_EQ(after.stereoFrames().size(), 95u);
  ASSERT_EQ(after.labels().size(), 95u);
  EXPECT_EQ(after.imu().size(), before.imu().size());
  EXPECT_EQ(after.groundTruth().size(), before.groundTruth().size());
  for (std::size_t k : {0ul, 10ul, 30ul, 50ul, 90ul}) {
    const bool inside = k >= 20 && k < 60;
    EXPECT_EQ(after.labels()[k].in_conflict, inside) << "frame " << k;
    for (int c = 0; c < 2; ++c) {
      const double diff = cv::norm(before.loadImage(before.stereoFrames()[k], c),
                                   after.loadImage(after.stereoFrames()[k], c), cv::NORM_L1);
      if (inside) {
        EXPECT_GT(diff, 0.0) << "frame " << k << " cam" << c;
      } else {
        EXPECT_EQ(diff, 0.0) << "frame " << k << " cam" << c;
      }
    }
  }
  std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace mcvio::sim
