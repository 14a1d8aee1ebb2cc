#include "mcvio/dataset/kalibr_calibration.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <functional>

#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/euroc_writer.hpp"
#include "mcvio/dataset/rig_calibration_reader.hpp"
#include "test_sequence.hpp"

namespace mcvio::dataset {
namespace {

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof(b), "%.17g", v);
  return b;
}

std::string rows(const Eigen::Isometry3d& T) {
  std::string s;
  for (int r = 0; r < 4; ++r) {
    s += "  - [";
    for (int c = 0; c < 4; ++c) s += num(T.matrix()(r, c)) + (c < 3 ? ", " : "]\n");
  }
  return s;
}

std::string vec(const Eigen::Vector4d& v) { return "[" + num(v[0]) + ", " + num(v[1]) + ", " + num(v[2]) + ", " + num(v[3]) + "]"; }

// The camchain Kalibr would write for `rig` (cam1 with T_cam_imu and, if asked, T_cn_cnm1).
std::string camchainOf(const StereoRigCalibration& rig, bool cam1_imu = true, bool cam1_chain = true) {
  std::string s;
  for (int i = 0; i < 2; ++i) {
    const CameraCalibration& c = rig.camera(i);
    const char* model = c.model.distortionModel() == DistortionModel::kEquidistant ? "equidistant" : "radtan";
    s += "cam" + std::to_string(i) + ":\n  camera_model: pinhole\n  intrinsics: " + vec(c.model.intrinsics()) +
         "\n  distortion_model: " + model + "\n  distortion_coeffs: " + vec(c.model.distortionCoefficients()) +
         "\n  resolution: [" + std::to_string(c.model.width()) + ", " + std::to_string(c.model.height()) + "]\n" +
         "  rostopic: /cam" + std::to_string(i) + "/image_raw\n  timeshift_cam_imu: -8.121e-05\n  cam_overlaps: [" +
         std::to_string(1 - i) + "]\n";
    if (i == 0 || cam1_imu) s += "  T_cam_imu:\n" + rows(c.T_BC.inverse());
    if (i == 1 && cam1_chain) s += "  T_cn_cnm1:\n" + rows(rig.cam1.T_BC.inverse() * rig.cam0.T_BC);
  }
  return s;
}

const char* kImuYaml =
    "#Accelerometers\naccelerometer_noise_density: 2.0e-3\naccelerometer_random_walk: 3.0e-3\n"
    "#Gyroscopes\ngyroscope_noise_density: 1.6968e-04\ngyroscope_random_walk: 1.9393e-05\n"
    "rostopic: /imu0\nupdate_rate: 200.0\n";

void expectRig(const StereoRigCalibration& got, const StereoRigCalibration& want) {
  for (int i = 0; i < 2; ++i) {
    EXPECT_EQ(got.camera(i).name, want.camera(i).name);
    EXPECT_EQ(got.camera(i).model.intrinsics(), want.camera(i).model.intrinsics());
    EXPECT_EQ(got.camera(i).model.distortionModel(), want.camera(i).model.distortionModel());
    EXPECT_EQ(got.camera(i).model.distortionCoefficients(), want.camera(i).model.distortionCoefficients());
    EXPECT_EQ(got.camera(i).model.width(), want.camera(i).model.width());
    EXPECT_LT((got.camera(i).T_BC.matrix() - want.camera(i).T_BC.matrix()).norm(), 1e-12) << "cam" << i;
  }
  EXPECT_EQ(got.imu.noise.accelerometer_noise_density, want.imu.noise.accelerometer_noise_density);
  EXPECT_EQ(got.imu.noise.accelerometer_random_walk, want.imu.noise.accelerometer_random_walk);
  EXPECT_EQ(got.imu.noise.gyroscope_noise_density, want.imu.noise.gyroscope_noise_density);
  EXPECT_EQ(got.imu.noise.gyroscope_random_walk, want.imu.noise.gyroscope_random_walk);
  EXPECT_EQ(got.imu.noise.rate_hz, want.imu.noise.rate_hz);
}

TEST(KalibrCalibration, GivesTheRigOfTheEurocFilesWithTheTimeShift) {
  const StereoRigCalibration rig = test::makeRig();
  const std::string dir = test::freshDir("kalibr_rig");
  test::writeText(dir + "/camchain-imucam-run1.yaml", camchainOf(rig));
  test::writeText(dir + "/imu.yaml", kImuYaml);
  for (const std::string& path : {dir, dir + "/camchain-imucam-run1.yaml"}) {
    const StereoRigCalibration got = RigCalibrationReader::read(path);
    expectRig(got, rig);
    EXPECT_EQ(got.camera_time_offset_ns, -81210) << path;
    EXPECT_EQ(got.cam0.topic, "/cam0/image_raw");
    EXPECT_EQ(got.cam1.topic, "/cam1/image_raw");
    EXPECT_EQ(got.imu.topic, "/imu0");
  }
  // cam1 located from cam0 alone (T_cn_cnm1), and Kalibr's results file for the IMU.
  const std::string chained = test::freshDir("kalibr_chained");
  test::writeText(chained + "/camchain-imucam.yaml", camchainOf(rig, false, true));
  test::writeText(chained + "/imu-run1.yaml", "imu0:\n  T_i_b:\n" + rows(Eigen::Isometry3d::Identity()) + "  " +
                                                 [] {
                                                   std::string s = kImuYaml;
                                                   std::string out;
                                                   for (char c : s) out += c == '\n' ? std::string("\n  ") : std::string(1, c);
                                                   return out;
                                                 }() + "model: calibrated\n  time_offset: 0.0\n");
  expectRig(RigCalibrationReader::read(chained), rig);
  // A EuRoC folder still reads as one.
  const std::string euroc = test::freshDir("kalibr_euroc");
  EurocWriter writer(euroc, rig);
  writer.close();
  expectRig(RigCalibrationReader::read(euroc), rig);
  EXPECT_EQ(RigCalibrationReader::read(euroc).camera_time_offset_ns, 0);
  EXPECT_EQ(RigCalibrationReader::read(euroc).cam0.topic, "");  // EuRoC names no topics
  EXPECT_EQ(RigCalibrationReader::read(euroc).imu.topic, "");
}

TEST(KalibrCalibration, WrittenFilesReadBackAsTheRig) {
  StereoRigCalibration rig = test::makeRig();
  rig.camera_time_offset_ns = 2500000;
  const std::string dir = test::freshDir("kalibr_written") + "/calib";
  KalibrCalibration::write(rig, dir);
  StereoRigCalibration got = RigCalibrationReader::read(dir);
  expectRig(got, rig);
  EXPECT_EQ(got.camera_time_offset_ns, rig.camera_time_offset_ns);
  EXPECT_EQ(got.cam0.topic, "/cam0/image_raw");  // the rig named none: mcvio's own
  EXPECT_EQ(got.cam1.topic, "/cam1/image_raw");
  EXPECT_EQ(got.imu.topic, "/imu0");
  rig.cam0.topic = "/left/image_raw";
  rig.cam1.topic = "/right/image_raw";
  rig.imu.topic = "/imu/data_raw";
  rig.cam1.model = CameraModel(rig.cam1.model.width(), rig.cam1.model.height(), rig.cam1.model.intrinsics(),
                               DistortionModel::kNone, Eigen::Vector4d::Zero());
  KalibrCalibration::write(rig, dir);
  got = RigCalibrationReader::read(dir + "/camchain-imucam.yaml");
  expectRig(got, rig);
  EXPECT_EQ(got.cam0.topic, "/left/image_raw");
  EXPECT_EQ(got.cam1.topic, "/right/image_raw");
  EXPECT_EQ(got.imu.topic, "/imu/data_raw");
  // A file where the folder should be.
  test::writeText(dir + "/file", "x");
  EXPECT_THROW(KalibrCalibration::write(rig, dir + "/file"), InputError);
}

TEST(KalibrCalibration, ReadsAndWritesTheWideAngleModels) {
  // Kalibr's ds and eucm as kalibr_calibrate_cameras writes them: the two shape parameters
  // first, distortion_model none.
  const StereoRigCalibration rig = test::makeRig();
  std::string chain = camchainOf(rig);
  const auto camera = [&chain](int i, const std::string& model, const std::string& intrinsics) {
    const std::string name = "cam" + std::to_string(i) + ":\n";
    const auto from = chain.find("  camera_model:", chain.find(name));
    const auto to = chain.find("  resolution:", from);
    chain.replace(from, to - from,
                  "  camera_model: " + model + "\n  distortion_coeffs: []\n  distortion_model: none\n  intrinsics: " + intrinsics + "\n");
  };
  camera(0, "ds", "[-0.19963086018860057, 0.5924590037637837, 31.7552559595926, 31.61745713358917, 31.5, 23.6]");
  camera(1, "eucm", "[0.61, 1.12, 46.1, 45.9, 32.2, 24.1]");
  const std::string dir = test::freshDir("kalibr_wide");
  test::writeText(dir + "/camchain-imucam.yaml", chain);
  test::writeText(dir + "/imu.yaml", kImuYaml);
  StereoRigCalibration got = RigCalibrationReader::read(dir);
  EXPECT_EQ(got.cam0.model.distortionModel(), DistortionModel::kDoubleSphere);
  EXPECT_EQ(got.cam0.model.distortionCoefficients(), Eigen::Vector4d(-0.19963086018860057, 0.5924590037637837, 0, 0));
  EXPECT_EQ(got.cam0.model.intrinsics(), Eigen::Vector4d(31.7552559595926, 31.61745713358917, 31.5, 23.6));
  EXPECT_EQ(got.cam1.model.distortionModel(), DistortionModel::kExtendedUnified);
  EXPECT_EQ(got.cam1.model.distortionCoefficients(), Eigen::Vector4d(0.61, 1.12, 0, 0));
  EXPECT_EQ(got.cam1.model.intrinsics(), Eigen::Vector4d(46.1, 45.9, 32.2, 24.1));
  // Without the distortion keys, as some tools write ds.
  for (std::size_t at; (at = chain.find("  distortion_")) != std::string::npos;) chain.erase(at, chain.find('\n', at) - at + 1);
  test::writeText(dir + "/camchain-imucam.yaml", chain);
  EXPECT_EQ(RigCalibrationReader::read(dir).cam0.model.distortionCoefficients(), got.cam0.model.distortionCoefficients());
  // Written and read again; and as EuRoC sensor.yaml files.
  KalibrCalibration::write(got, dir + "/written");
  expectRig(RigCalibrationReader::read(dir + "/written"), got);
  EurocWriter(dir + "/euroc", got).close();
  expectRig(RigCalibrationReader::read(dir + "/euroc"), got);
}

TEST(KalibrCalibration, RostopicNamesTheTopicsTheSensorsWereCalibratedOn) {
  const StereoRigCalibration rig = test::makeRig();
  std::string chain = camchainOf(rig);
  const auto swap = [&chain](const std::string& from, const std::string& to) { chain.replace(chain.find(from), from.size(), to); };
  // A driver's names, one relative (Kalibr takes them as ROS 1 did).
  swap("rostopic: /cam0/image_raw", "rostopic: /camera/infra1/image_rect_raw");
  swap("rostopic: /cam1/image_raw", "rostopic: camera/infra2/image_rect_raw");
  const std::string dir = test::freshDir("kalibr_topics");
  test::writeText(dir + "/camchain-imucam.yaml", chain);
  std::string imu = kImuYaml;
  imu.replace(imu.find("rostopic: /imu0"), 15, "rostopic: /camera/imu");
  test::writeText(dir + "/imu.yaml", imu);
  StereoRigCalibration got = RigCalibrationReader::read(dir);
  EXPECT_EQ(got.cam0.topic, "/camera/infra1/image_rect_raw");
  EXPECT_EQ(got.cam1.topic, "/camera/infra2/image_rect_raw");
  EXPECT_EQ(got.imu.topic, "/camera/imu");
  // Without rostopic: not named.
  std::string bare = camchainOf(rig);
  for (std::size_t at; (at = bare.find("  rostopic:")) != std::string::npos;) bare.erase(at, bare.find('\n', at) - at + 1);
  test::writeText(dir + "/camchain-imucam.yaml", bare);
  test::writeText(dir + "/imu.yaml", "accelerometer_noise_density: 2.0e-3\naccelerometer_random_walk: 3.0e-3\n"
                                     "gyroscope_noise_density: 1.6968e-04\ngyroscope_random_walk: 1.9393e-05\nupdate_rate: 200.0\n");
  got = RigCalibrationReader::read(dir);
  EXPECT_EQ(got.cam0.topic, "");
  EXPECT_EQ(got.cam1.topic, "");
  EXPECT_EQ(got.imu.topic, "");
}

TEST(KalibrCalibration, BadFilesAreNamedWithTheCameraAndKey) {
  const StereoRigCalibration rig = test::makeRig();
  const std::string good = camchainOf(rig);
  auto error = [](const std::string& camchain, const std::string& imu = kImuYaml) {
    const std::string dir = test::freshDir("kalibr_bad");
    test::writeText(dir + "/camchain-imucam.yaml", camchain);
    if (!imu.empty()) test::writeText(dir + "/imu.yaml", imu);
    try {
      RigCalibrationReader::read(dir);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  auto replaced = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    const auto at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  };
  EXPECT_NE(error(replaced("camera_model: pinhole", "camera_model: omni")).find("cam0: key 'camera_model' 'omni' is not supported (pinhole, ds or eucm; omni, the unified model with a distortion on top, is not"), std::string::npos)
      << error(replaced("camera_model: pinhole", "camera_model: omni"));
  EXPECT_NE(error(replaced("camera_model: pinhole", "camera_model: fov")).find("cam0: key 'camera_model' 'fov' is not supported (pinhole, ds or eucm)"), std::string::npos);
  // A double sphere lists six intrinsics and no distortion.
  EXPECT_NE(error(replaced("camera_model: pinhole", "camera_model: ds")).find("cam0: key 'intrinsics' must have 6 values, got 4"), std::string::npos);
  {
    const std::string ds = replaced("camera_model: pinhole\n  intrinsics: [", "camera_model: ds\n  intrinsics: [-0.2, 0.6, ");
    EXPECT_NE(error(ds).find("cam0: key 'distortion_model' must be none for camera_model ds, which models the whole lens"), std::string::npos) << error(ds);
    std::string bad_alpha = good;
    bad_alpha.replace(bad_alpha.find("camera_model: pinhole\n  intrinsics: ["), 37, "camera_model: ds\n  intrinsics: [-0.2, 1.6, ");
    const auto at = bad_alpha.find("distortion_model: radtan");
    bad_alpha.replace(at, bad_alpha.find('\n', bad_alpha.find("distortion_coeffs", at)) - at, "distortion_model: none\n  distortion_coeffs: []");
    EXPECT_NE(error(bad_alpha).find("camchain-imucam.yaml: cam0: key 'intrinsics': double sphere alpha = 1.6 is outside [0, 1]"), std::string::npos) << error(bad_alpha);
  }
  EXPECT_NE(error(replaced("distortion_model: radtan", "distortion_model: fov")).find("cam0: key 'distortion_model' 'fov' is not supported"), std::string::npos);
  EXPECT_NE(error(camchainOf(rig, false, false)).find("cam1: missing key 'T_cam_imu' (or 'T_cn_cnm1'"), std::string::npos);
  {
    // A camera-only camchain (no T_cam_imu at all).
    std::string s = good;
    const auto at = s.find("  T_cam_imu:\n");
    s.erase(at, s.find("cam1:") - at);
    EXPECT_NE(error(s).find("cam0: missing key 'T_cam_imu': this is a camera-only camchain"), std::string::npos) << error(s);
  }
  {
    // T_cn_cnm1 of another rig.
    StereoRigCalibration other = rig;
    other.cam1.T_BC.translation().x() += 0.01;
    std::string s = camchainOf(rig, true, false) + "  T_cn_cnm1:\n" + rows(other.cam1.T_BC.inverse() * other.cam0.T_BC);
    EXPECT_NE(error(s).find("cam1: key 'T_cn_cnm1' disagrees with the two T_cam_imu by 10.00 mm and 0.000 degrees"), std::string::npos) << error(s);
  }
  {
    std::string s = good;
    const auto at = s.rfind("timeshift_cam_imu: -8.121e-05");
    s.replace(at, 29, "timeshift_cam_imu: 0.01");
    EXPECT_NE(error(s).find("cam1: key 'timeshift_cam_imu' is 0.01 s against cam0's -8.121e-05 s: mcvio needs a synchronised stereo pair"), std::string::npos) << error(s);
  }
  EXPECT_NE(error(replaced("intrinsics: [", "intrinsics: [1e9, ")).find("cam0: key 'intrinsics' must have 4 values, got 5"), std::string::npos);
  EXPECT_NE(error(good, "").find("its IMU noise comes from Kalibr's imu*.yaml beside it"), std::string::npos);
  EXPECT_NE(error(good, "accelerometer_noise_density: 2.0e-3\n").find("imu.yaml: missing key 'accelerometer_random_walk'"), std::string::npos);
  EXPECT_NE(error(good, std::string(kImuYaml) + "update_rate: -1\n").find("imu.yaml"), std::string::npos);
  EXPECT_NE(error(replaced("rostopic: /cam1/image_raw", "rostopic: /cam1/image raw")).find("cam1: key 'rostopic' '/cam1/image raw' is not a ROS topic name"), std::string::npos)
      << error(replaced("rostopic: /cam1/image_raw", "rostopic: /cam1/image raw"));
  EXPECT_NE(error(replaced("rostopic: /cam1/image_raw", "rostopic: /cam0/image_raw")).find("cam1: key 'rostopic' is cam0's too (/cam0/image_raw)"), std::string::npos);
  {
    std::string imu = kImuYaml;
    imu.replace(imu.find("rostopic: /imu0"), 15, "rostopic: 7imu");
    EXPECT_NE(error(good, imu).find("imu.yaml:7: key 'rostopic' '7imu' is not a ROS topic name: a topic name token must not start with a digit"), std::string::npos) << error(good, imu);
  }
  EXPECT_NE(error("cam0: [1, 2]\n").find("'cam0' must be a map of camera keys"), std::string::npos);
  {
    // Not a rotation.
    std::string s = good;
    const auto at = s.find("  T_cam_imu:\n  - [") + std::string("  T_cam_imu:\n  - [").size();
    s.replace(at, s.find(',', at) - at, "2");
    EXPECT_NE(error(s).find("cam0: key 'T_cam_imu' rotation part is not a rotation matrix"), std::string::npos) << error(s);
  }
  // Neither format, and two IMU files.
  const std::string empty = test::freshDir("kalibr_empty");
  test::writeText(empty + "/camchain.yaml", "cam0: {}\n");
  try {
    RigCalibrationReader::read(empty);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("neither a EuRoC folder"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("camchain.yaml is a camera-only camchain"), std::string::npos);
  }
  const std::string two = test::freshDir("kalibr_two_imu");
  test::writeText(two + "/camchain-imucam.yaml", good);
  test::writeText(two + "/imu.yaml", kImuYaml);
  test::writeText(two + "/imu-run1.yaml", kImuYaml);
  try {
    RigCalibrationReader::read(two);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("holds several IMU files (imu-run1.yaml, imu.yaml)"), std::string::npos) << e.what();
  }
  EXPECT_THROW(RigCalibrationReader::read(two + "/missing"), InputError);
}

}  // namespace
}  // namespace mcvio::dataset
