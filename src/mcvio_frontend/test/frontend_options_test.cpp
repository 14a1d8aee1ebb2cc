#include "mcvio/frontend/frontend_options.hpp"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>

#include "mcvio/core/input_error.hpp"

namespace mcvio::frontend {
namespace {

std::string errorOf(const std::string& yaml) {
  try {
    FrontendOptions::fromYaml(YAML::Load(yaml), "test.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(FrontendOptions, DefaultsAreValid) { EXPECT_NO_THROW(FrontendOptions().validate()); }

TEST(FrontendOptions, YamlOverridesDefaults) {
  const FrontendOptions o = FrontendOptions::fromYaml(YAML::Load(
      "max_features: 150\nwindow_size: 15\nexposure_normalization: local\nfb_threshold_px: 0.8"));
  EXPECT_EQ(o.max_features, 150);
  EXPECT_EQ(o.window_size, 15);
  EXPECT_EQ(o.exposure_normalization, "local");
  EXPECT_DOUBLE_EQ(o.fb_threshold_px, 0.8);
  EXPECT_EQ(o.grid_cols, FrontendOptions().grid_cols);
}

TEST(FrontendOptions, ErrorsNameTheKey) {
  EXPECT_NE(errorOf("max_features: -3").find("max_features"), std::string::npos);
  EXPECT_NE(errorOf("moving_track_budget_share: 1.5").find("moving_track_budget_share"), std::string::npos);
  EXPECT_NE(errorOf("moving_track_budget_share: .nan").find("moving_track_budget_share"), std::string::npos);
  EXPECT_EQ(errorOf("moving_track_budget_share: 0.6"), "");
  EXPECT_NE(errorOf("window_size: 20").find("window_size"), std::string::npos);
  EXPECT_NE(errorOf("max_featurez: 100").find("max_featurez"), std::string::npos);
  EXPECT_NE(errorOf("pyramid_levels: many").find("pyramid_levels"), std::string::npos);
  EXPECT_NE(errorOf("min_depth_m: 5\nmax_depth_m: 1").find("max_depth_m"), std::string::npos);
  EXPECT_NE(errorOf("max_features: -3").find("test.yaml"), std::string::npos);
  EXPECT_NE(errorOf("exposure_normalization: auto").find("exposure_normalization"),
            std::string::npos);
  EXPECT_EQ(errorOf("max_features: 100"), "");
  EXPECT_NE(errorOf("pixel_scale: edge").find("test.yaml: key 'pixel_scale': unknown pixel scale 'edge' (expected centre, local or wide_angle)"),
            std::string::npos)
      << errorOf("pixel_scale: edge");
  EXPECT_EQ(FrontendOptions::fromYaml(YAML::Load("pixel_scale: centre")).pixel_scale, PixelScale::kCentre);
}

TEST(FrontendOptions, FileWithFrontendSection) {
  const std::string path = ::testing::TempDir() + "/frontend_opts.yaml";
  std::ofstream(path) << "frontend:\n  grid_cols: 10\n  ransac_threshold_px: 2.5\n";
  const FrontendOptions o = FrontendOptions::fromFile(path);
  EXPECT_EQ(o.grid_cols, 10);
  EXPECT_DOUBLE_EQ(o.ransac_threshold_px, 2.5);
  EXPECT_THROW(FrontendOptions::fromFile("/nonexistent/frontend.yaml"), InputError);
}

// As OpenVINS's mask0 / mask1: a relative path is relative to the file that names it.
TEST(FrontendOptions, MaskPathsAreRelativeToTheirFile) {
  const std::string dir = ::testing::TempDir() + "/frontend_masks_cfg";
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/frontend.yaml";
  std::ofstream(path) << "mask0: masks/left.png\nmask1: /abs/right.png\n";
  const FrontendOptions o = FrontendOptions::fromFile(path);
  EXPECT_EQ(o.mask0, dir + "/masks/left.png");
  EXPECT_EQ(o.mask1, "/abs/right.png");
  EXPECT_EQ(FrontendOptions::fromYaml(YAML::Load("mask0: left.png")).mask0, "left.png");
  EXPECT_TRUE(FrontendOptions().mask0.empty());
  EXPECT_THROW(FrontendOptions::fromYaml(YAML::Load("mask0: [1, 2]")), InputError);
  std::filesystem::remove_all(dir);
}

TEST(FrontendOptions, ShippedConfigLoads) {
  const FrontendOptions o = FrontendOptions::fromFile(MCVIO_FRONTEND_CONFIG_DIR "/frontend.yaml");
  // The shipped file documents the defaults: keep them equal.
  const FrontendOptions d;
  EXPECT_EQ(o.max_features, d.max_features);
  EXPECT_DOUBLE_EQ(o.moving_track_budget_share, d.moving_track_budget_share);
  EXPECT_EQ(o.window_size, d.window_size);
  EXPECT_EQ(o.klt_max_iterations, d.klt_max_iterations);
  EXPECT_DOUBLE_EQ(o.klt_epsilon, d.klt_epsilon);
  EXPECT_EQ(o.exposure_normalization, d.exposure_normalization);
  EXPECT_EQ(o.normalization_block_px, d.normalization_block_px);
  EXPECT_DOUBLE_EQ(o.ransac_threshold_px, d.ransac_threshold_px);
  EXPECT_EQ(o.pixel_scale, d.pixel_scale);
  EXPECT_DOUBLE_EQ(o.stereo_prediction_tolerance_px, d.stereo_prediction_tolerance_px);
  EXPECT_EQ(o.reidentify_lost_tracks, d.reidentify_lost_tracks);
  EXPECT_DOUBLE_EQ(o.reidentify_min_age_s, d.reidentify_min_age_s);
  EXPECT_DOUBLE_EQ(o.reidentify_max_age_s, d.reidentify_max_age_s);
  EXPECT_EQ(o.reidentify_max_hamming, d.reidentify_max_hamming);
  EXPECT_DOUBLE_EQ(o.reidentify_ratio, d.reidentify_ratio);
}

TEST(FrontendOptions, ReidentificationOptionsAreChecked) {
  EXPECT_TRUE(FrontendOptions::fromYaml(YAML::Load("reidentify_lost_tracks: true")).reidentify_lost_tracks);
  EXPECT_THROW(FrontendOptions::fromYaml(YAML::Load("reidentify_min_age_s: 70")), InputError);  // above the max age
  EXPECT_THROW(FrontendOptions::fromYaml(YAML::Load("reidentify_max_age_s: 0")), InputError);
  EXPECT_THROW(FrontendOptions::fromYaml(YAML::Load("reidentify_max_hamming: 300")), InputError);
  EXPECT_THROW(FrontendOptions::fromYaml(YAML::Load("reidentify_ratio: 0")), InputError);
  EXPECT_THROW(FrontendOptions::fromYaml(YAML::Load("reidentify_ratio: .nan")), InputError);
}

}  // namespace
}  // namespace mcvio::frontend
