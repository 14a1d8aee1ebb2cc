#include "mcvio/dataset/sensor_yaml.hpp"

#include <gtest/gtest.h>

#include <iterator>

#include "mcvio/core/input_error.hpp"
#include "test_sequence.hpp"

namespace mcvio::dataset {
namespace {

const char* kCameraYaml = R"(%YAML:1.0
sensor_type: camera
T_BS:
  cols: 4
  rows: 4
  data: [1, 0, 0, 0.5,
         0, 1, 0, 0,
         0, 0, 1, 0,
         0, 0, 0, 1]
rate_hz: 30
resolution: [640, 480]
camera_model: pinhole
intrinsics: [400, 401, 320, 240]
distortion_model: radtan
distortion_coefficients: [-0.1, 0.01, 0.001, -0.002, 0.0]
)";

TEST(SensorYaml, ReadsFiveCoefficientRadtanWithZeroK3) {
  const std::string path = test::freshDir("yaml_k3") + "/sensor.yaml";
  test::writeText(path, kCameraYaml);
  const CameraCalibration cam = SensorYaml::readCamera(path, "left");
  EXPECT_EQ(cam.name, "left");
  EXPECT_EQ(cam.rate_hz, 30.0);
  EXPECT_EQ(cam.model.width(), 640);
  EXPECT_EQ(cam.model.distortionModel(), DistortionModel::kRadialTangential);
  EXPECT_EQ(cam.model.distortionCoefficients(), Eigen::Vector4d(-0.1, 0.01, 0.001, -0.002));
  EXPECT_EQ(cam.T_BC.translation().x(), 0.5);

  std::string text = kCameraYaml;
  text.replace(text.find("-0.002, 0.0]"), 12, "-0.002, 0.3]");
  test::writeText(path, text);
  try {
    SensorYaml::readCamera(path, "left");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("k3"), std::string::npos) << e.what();
  }
}

TEST(SensorYaml, PinholeWithoutDistortionRoundTrips) {
  const std::string path = test::freshDir("yaml_none") + "/sensor.yaml";
  CameraCalibration cam;
  cam.name = "cam0";
  cam.model = CameraModel(320, 240, {300.1, 300.2, 160.3, 120.4}, DistortionModel::kNone);
  cam.rate_hz = 1.0 / 3.0;
  cam.T_BC.translation() = Eigen::Vector3d(0.1, 0.2, 0.3);
  SensorYaml::writeCamera(path, cam);
  const CameraCalibration back = SensorYaml::readCamera(path, "cam0");
  EXPECT_EQ(back.model.distortionModel(), DistortionModel::kNone);
  EXPECT_EQ(back.model.intrinsics(), cam.model.intrinsics());
  EXPECT_EQ(back.rate_hz, cam.rate_hz);
  EXPECT_EQ(back.T_BC.matrix(), cam.T_BC.matrix());
}

TEST(SensorYaml, WideAngleModelsAreWrittenAsKalibrNamesThem) {
  const std::string path = test::freshDir("yaml_ds") + "/sensor.yaml";
  CameraCalibration cam;
  cam.name = "cam0";
  cam.model = CameraModel(752, 480, {349.7, 348.7, 365.8, 249.3}, DistortionModel::kDoubleSphere, {-0.28, 0.57, 0, 0});
  SensorYaml::writeCamera(path, cam);
  const std::string text = test::readText(path);
  EXPECT_NE(text.find("camera_model: ds\nintrinsics: [-0.28, 0.57, 349.7, 348.7, 365.8, 249.3] #xi, alpha, fu, fv, cu, cv\n"
                      "distortion_model: none\ndistortion_coefficients: []"),
            std::string::npos)
      << text;
  CameraCalibration back = SensorYaml::readCamera(path, "cam0");
  EXPECT_EQ(back.model.distortionModel(), DistortionModel::kDoubleSphere);
  EXPECT_EQ(back.model.intrinsics(), cam.model.intrinsics());
  EXPECT_EQ(back.model.distortionCoefficients(), cam.model.distortionCoefficients());
  cam.model = CameraModel(752, 480, {460.1, 459.3, 365.8, 249.3}, DistortionModel::kExtendedUnified, {0.61, 1.12, 0, 0});
  SensorYaml::writeCamera(path, cam);
  back = SensorYaml::readCamera(path, "cam0");
  EXPECT_EQ(back.model.distortionModel(), DistortionModel::kExtendedUnified);
  EXPECT_EQ(back.model.distortionCoefficients(), cam.model.distortionCoefficients());

  const auto error = [&path](const std::string& from, const std::string& to) {
    std::string t = kCameraYaml;
    t.replace(t.find(from), from.size(), to);
    test::writeText(path, t);
    try {
      SensorYaml::readCamera(path, "cam0");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error("camera_model: pinhole", "camera_model: ds").find("key 'intrinsics' must have 6 values, got 4"), std::string::npos);
  EXPECT_NE(error("camera_model: pinhole\nintrinsics: [", "camera_model: ds\nintrinsics: [0.1, 0.6, ")
                .find("key 'distortion_model' must be none for camera_model ds"),
            std::string::npos);
  EXPECT_NE(error("distortion_model: radtan", "distortion_model: ds").find("key 'distortion_model' 'ds' is a camera_model: write camera_model: ds with its 6 intrinsics"),
            std::string::npos)
      << error("distortion_model: radtan", "distortion_model: ds");
}

// Values that parse but cannot describe a real camera would run and lose every feature.
TEST(SensorYaml, RejectsImplausibleIntrinsicsAndTheWrongSensorType) {
  const std::string path = test::freshDir("yaml_implausible") + "/sensor.yaml";
  const std::pair<std::string, std::string> cases[] = {
      {"[400, 401, 320, 240]", "[400, 401, 5000, -3000]"},  // principal point outside the image
      {"[400, 401, 320, 240]", "[1e300, 1e300, 320, 240]"},  // focal length
      {"sensor_type: camera", "sensor_type: imu"},
      {"[-0.1, 0.01,", "[1e6, 0.01,"},                     // k1 folds the model near the centre
      {"[-0.1, 0.01,", "[-0.1, -40,"},                     // k2 folds it inside the central half
      {"rate_hz: 30\n", "rate_hz: 30\nrate_hz: 20\n"},  // the second would be ignored
  };
  const char* expected[] = {"principal point", "focal length", "expected 'camera'",
                            "distortion_coefficients' scale the ray through pixel",
                            "distortion_coefficients' cannot be inverted",
                            ":11: key 'rate_hz' appears twice (first at line 10)"};
  for (std::size_t i = 0; i < std::size(cases); ++i) {
    std::string text = kCameraYaml;
    text.replace(text.find(cases[i].first), cases[i].first.size(), cases[i].second);
    test::writeText(path, text);
    try {
      SensorYaml::readCamera(path, "left");
      ADD_FAILURE() << "accepted " << cases[i].second;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(expected[i]), std::string::npos) << e.what();
    }
  }
}

TEST(SensorYaml, AcceptsAWideFisheyeWhoseCornersLieBeyondNinetyDegrees) {
  // TUM-VI-like: 512x512 equidistant, about 195 degrees across the diagonal.
  const std::string path = test::freshDir("yaml_fisheye") + "/sensor.yaml";
  std::string text = kCameraYaml;
  text.replace(text.find("[640, 480]"), 10, "[512, 512]");
  text.replace(text.find("[400, 401, 320, 240]"), 20, "[190.98, 190.97, 254.93, 256.90]");
  text.replace(text.find("radtan"), 6, "equidistant");
  text.replace(text.find("[-0.1, 0.01, 0.001, -0.002, 0.0]"), 32, "[0.00348, 0.000715, -0.00205, 0.000203]");
  test::writeText(path, text);
  EXPECT_EQ(SensorYaml::readCamera(path, "cam0").model.distortionModel(), DistortionModel::kEquidistant);
}

TEST(SensorYaml, RejectsNonIntegerResolution) {
  const std::string path = test::freshDir("yaml_resolution") + "/sensor.yaml";
  std::string text = kCameraYaml;
  text.replace(text.find("[640, 480]"), 10, "[640.5, 480]");
  test::writeText(path, text);
  try {
    SensorYaml::readCamera(path, "cam0");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":11: key 'resolution'"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mcvio::dataset
