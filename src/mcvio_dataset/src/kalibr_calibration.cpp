#include "mcvio/dataset/kalibr_calibration.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

#include "calibration_checks.hpp"
#include "camera_model_fields.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/core/ros_topic_name.hpp"
#include "mcvio/core/yaml_file.hpp"
#include "mcvio/core/write_failure.hpp"
#include "number_format.hpp"
#include "yaml_section.hpp"

namespace mcvio::dataset {
namespace {

// A camera or IMU section of a Kalibr file, plus Kalibr's form of a transform.
class Section : public detail::YamlSection {
 public:
  using YamlSection::YamlSection;

  // Kalibr writes a transform as four rows of four numbers.
  Eigen::Isometry3d transform(const std::string& key) const {
    const YAML::Node n = require(key);
    if (!n.IsSequence() || n.size() != 4) fail(n, key, "must be 4 rows of 4 numbers");
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r) {
      const YAML::Node row = n[r];
      if (!row.IsSequence() || row.size() != 4) fail(row, key, "row " + std::to_string(r + 1) + " must have 4 numbers");
      for (int c = 0; c < 4; ++c) m(r, c) = number(row[c], key);
    }
    const std::string problem = detail::transformProblem(m);
    if (!problem.empty()) fail(n, key, problem);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.matrix() = m;
    return T;
  }
};

CameraCalibration readCamera(const Section& cam, const std::string& name) {
  CameraCalibration calibration;
  calibration.name = name;
  detail::ProjectionFields projection;
  std::string problem;
  if (!detail::projectionNamed(cam.text("camera_model"), &projection, &problem)) {
    cam.fail(cam.require("camera_model"), "camera_model", problem);
  }
  const std::vector<double> res = cam.numbers("resolution", 2, 2);
  for (double v : res) {
    if (v < 1.0 || v != std::floor(v) || v > 1e6) cam.fail(cam.require("resolution"), "resolution", "must be two positive integers [width, height]");
  }
  const std::size_t count = projection.intrinsics_count;
  const std::vector<double> in = cam.numbers("intrinsics", count, count);
  Eigen::Vector4d intrinsics, coefficients;
  detail::splitIntrinsics(projection, in, &intrinsics, &coefficients);
  const std::string intrinsics_problem = detail::intrinsicsProblem(intrinsics, static_cast<int>(res[0]), static_cast<int>(res[1]));
  if (!intrinsics_problem.empty()) cam.fail(cam.require("intrinsics"), "intrinsics", intrinsics_problem);
  // ds and eucm model the whole lens; Kalibr writes distortion_model none for them.
  const std::string model_name = cam.has("distortion_model") || projection.wide_angle == DistortionModel::kNone
                                     ? cam.text("distortion_model")
                                     : std::string("none");
  DistortionModel distortion = projection.wide_angle;
  if (model_name == "radtan") distortion = DistortionModel::kRadialTangential;
  else if (model_name == "equidistant") distortion = DistortionModel::kEquidistant;
  else if (model_name != "none")
    cam.fail(cam.require("distortion_model"), "distortion_model", "'" + model_name + "' is not supported (radtan, equidistant or none)");
  if (projection.wide_angle != DistortionModel::kNone && distortion != projection.wide_angle) {
    cam.fail(cam.require("distortion_model"), "distortion_model",
             "must be none for camera_model " + cam.text("camera_model") + ", which models the whole lens");
  }
  if (distortion == DistortionModel::kRadialTangential || distortion == DistortionModel::kEquidistant) {
    const std::vector<double> d = cam.numbers("distortion_coeffs", 4, 4);
    coefficients = Eigen::Vector4d(d[0], d[1], d[2], d[3]);
  } else if (cam.has("distortion_coeffs")) {
    for (double v : cam.numbers("distortion_coeffs", 0, 4))
      if (v != 0.0) cam.fail(cam.require("distortion_coeffs"), "distortion_coeffs", "must be empty or zero for distortion_model none");
  }
  try {
    calibration.model = CameraModel(static_cast<int>(res[0]), static_cast<int>(res[1]), intrinsics, distortion, coefficients);
  } catch (const InputError& e) {
    throw InputError(cam.path() + ": " + cam.prefix() + (projection.wide_angle != DistortionModel::kNone ? "key 'intrinsics': " : "") +
                     e.what());
  }
  const bool wide = projection.wide_angle != DistortionModel::kNone;
  const std::string distortion_problem = detail::distortionProblem(calibration.model, wide ? cam.text("camera_model") : model_name);
  if (!distortion_problem.empty()) {
    const std::string key = wide ? "intrinsics" : "distortion_coeffs";
    cam.fail(cam.require(key), key, distortion_problem);
  }
  return calibration;
}

// Kalibr's rostopic: the topic the sensor was calibrated on (absolute), or "" when not given.
std::string topicOf(const Section& section) {
  if (!section.has("rostopic")) return {};
  const std::string name = section.text("rostopic");
  const std::string problem = rosTopicNameError(name);
  if (!problem.empty()) section.fail(section.require("rostopic"), "rostopic", "'" + name + "' is not a ROS topic name: " + problem);
  return absoluteTopicName(name);
}

Section sectionOf(const std::string& path, const YAML::Node& root, const std::string& name) {
  const YAML::Node n = root[name];
  if (!n) throw InputError(path + ": no '" + name + "' (a Kalibr camchain lists cam0 and cam1)");
  if (!n.IsMap()) throw InputError(path + ": '" + name + "' must be a map of camera keys");
  return Section(path, name, n);
}

}  // namespace

StereoRigCalibration KalibrCalibration::read(const std::string& camchain_path, const std::string& imu_path) {
  const YAML::Node chain = loadYamlFile(camchain_path, "Kalibr camchain");
  if (!chain.IsMap()) throw InputError(camchain_path + ": expected a YAML map with cam0 and cam1");
  StereoRigCalibration rig;
  const Section cam0 = sectionOf(camchain_path, chain, "cam0"), cam1 = sectionOf(camchain_path, chain, "cam1");
  rig.cam0 = readCamera(cam0, "cam0");
  rig.cam1 = readCamera(cam1, "cam1");
  rig.cam0.topic = topicOf(cam0);
  rig.cam1.topic = topicOf(cam1);
  if (!rig.cam0.topic.empty() && rig.cam0.topic == rig.cam1.topic)
    cam1.fail(cam1.require("rostopic"), "rostopic", "is cam0's too (" + rig.cam0.topic + "): the left and right images need a topic each");
  if (!cam0.has("T_cam_imu")) {
    throw InputError(camchain_path + ": cam0: missing key 'T_cam_imu': this is a camera-only camchain; mcvio needs the "
                     "camera-IMU one (kalibr_calibrate_imu_camera's camchain-imucam.yaml)");
  }
  const Eigen::Isometry3d T_c0_imu = cam0.transform("T_cam_imu");
  Eigen::Isometry3d T_c1_imu;
  if (cam1.has("T_cam_imu")) {
    T_c1_imu = cam1.transform("T_cam_imu");
    if (cam1.has("T_cn_cnm1")) {
      // Both given: they must describe the same rig (Kalibr writes them consistently).
      const Eigen::Isometry3d chained = cam1.transform("T_cn_cnm1") * T_c0_imu;
      const Eigen::Isometry3d diff = chained.inverse() * T_c1_imu;
      const double dt = diff.translation().norm(), dr = Eigen::AngleAxisd(diff.rotation()).angle() * 180.0 / M_PI;
      if (dt > 1e-3 || dr > 0.1) {
        char by[64];
        std::snprintf(by, sizeof(by), "%.2f mm and %.3f degrees", dt * 1000, dr);
        cam1.fail(cam1.require("T_cn_cnm1"), "T_cn_cnm1", std::string("disagrees with the two T_cam_imu by ") + by);
      }
    }
  } else if (cam1.has("T_cn_cnm1")) {
    T_c1_imu = cam1.transform("T_cn_cnm1") * T_c0_imu;
  } else {
    throw InputError(camchain_path + ": cam1: missing key 'T_cam_imu' (or 'T_cn_cnm1', its pose from cam0)");
  }
  rig.cam0.T_BC = T_c0_imu.inverse();
  rig.cam1.T_BC = T_c1_imu.inverse();
  // Kalibr estimates the shift per camera; a stereo pair mcvio tracks shares one clock.
  const double shift0 = cam0.has("timeshift_cam_imu") ? cam0.number("timeshift_cam_imu") : 0.0;
  const double shift1 = cam1.has("timeshift_cam_imu") ? cam1.number("timeshift_cam_imu") : shift0;
  if (std::abs(shift0 - shift1) > 1e-3) {
    cam1.fail(cam1.require("timeshift_cam_imu"), "timeshift_cam_imu",
              "is " + detail::formatDouble(shift1) + " s against cam0's " + detail::formatDouble(shift0) +
                  " s: mcvio needs a synchronised stereo pair (one stamp per pair)");
  }
  if (std::abs(shift0) > 1.0) {
    cam0.fail(cam0.require("timeshift_cam_imu"), "timeshift_cam_imu",
              "is " + detail::formatDouble(shift0) + " s; a camera-IMU time shift is milliseconds (seconds, not ms?)");
  }
  rig.camera_time_offset_ns = static_cast<Timestamp>(std::llround(shift0 * 1e9));

  const YAML::Node imu_root = loadYamlFile(imu_path, "Kalibr IMU file");
  if (!imu_root.IsMap()) throw InputError(imu_path + ": expected a YAML map of IMU keys");
  // Kalibr's input imu.yaml has the keys at the top; its results file under imu0.
  const bool nested = imu_root["imu0"] && imu_root["imu0"].IsMap() && !imu_root["accelerometer_noise_density"];
  const Section imu(imu_path, nested ? "imu0" : "", nested ? imu_root["imu0"] : imu_root);
  rig.imu.name = "imu0";
  rig.imu.noise.accelerometer_noise_density = imu.positive("accelerometer_noise_density");
  rig.imu.noise.accelerometer_random_walk = imu.positive("accelerometer_random_walk");
  rig.imu.noise.gyroscope_noise_density = imu.positive("gyroscope_noise_density");
  rig.imu.noise.gyroscope_random_walk = imu.positive("gyroscope_random_walk");
  rig.imu.noise.rate_hz = imu.positive("update_rate");
  rig.imu.topic = topicOf(imu);
  return rig;
}

namespace {

std::string numberList(const double* values, int count) {
  std::string s = "[";
  for (int i = 0; i < count; ++i) {
    if (i) s += ", ";
    detail::appendDouble(s, values[i]);
  }
  return s + "]";
}

std::string rowsOf(const Eigen::Isometry3d& T) {
  std::string s;
  for (int r = 0; r < 4; ++r) {
    const double row[4] = {T.matrix()(r, 0), T.matrix()(r, 1), T.matrix()(r, 2), T.matrix()(r, 3)};
    s += "  - " + numberList(row, 4) + "\n";
  }
  return s;
}

void writeFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) throwCannotWrite(path, errno);
}

}  // namespace

void KalibrCalibration::write(const StereoRigCalibration& rig, const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir, ec)) throw InputError(dir + ": cannot create the folder for Kalibr's files");
  const double shift_s = static_cast<double>(rig.camera_time_offset_ns) * 1e-9;
  std::string chain;
  for (int i = 0; i < 2; ++i) {
    const CameraCalibration& c = rig.camera(i);
    const CameraModel& m = c.model;
    const char* model = m.distortionModel() == DistortionModel::kEquidistant       ? "equidistant"
                        : m.distortionModel() == DistortionModel::kRadialTangential ? "radtan"
                                                                                     : "none";
    const bool distorted = std::string(model) != "none";
    const std::vector<double> intrinsics = detail::listedIntrinsics(m);
    const std::string name = "cam" + std::to_string(i);
    chain += name + ":\n  camera_model: " + detail::cameraModelName(m) +
             "\n  intrinsics: " + numberList(intrinsics.data(), static_cast<int>(intrinsics.size())) +
             "\n  distortion_model: " + model + "\n  distortion_coeffs: " +
             numberList(m.distortionCoefficients().data(), distorted ? 4 : 0) +
             "\n  resolution: [" + std::to_string(m.width()) + ", " + std::to_string(m.height()) + "]\n  rostopic: " +
             (c.topic.empty() ? "/" + name + "/image_raw" : c.topic) + "\n  timeshift_cam_imu: " + detail::formatDouble(shift_s) +
             "\n  cam_overlaps: [" + std::to_string(1 - i) + "]\n  T_cam_imu:\n" + rowsOf(c.T_BC.inverse());
    if (i == 1) chain += "  T_cn_cnm1:\n" + rowsOf(rig.T_C0C1().inverse());
  }
  const ImuNoiseParams& n = rig.imu.noise;
  std::string imu = "accelerometer_noise_density: " + detail::formatDouble(n.accelerometer_noise_density) +
                    "\naccelerometer_random_walk: " + detail::formatDouble(n.accelerometer_random_walk) +
                    "\ngyroscope_noise_density: " + detail::formatDouble(n.gyroscope_noise_density) +
                    "\ngyroscope_random_walk: " + detail::formatDouble(n.gyroscope_random_walk) +
                    "\nrostopic: " + (rig.imu.topic.empty() ? std::string("/imu0") : rig.imu.topic) +
                    "\nupdate_rate: " + detail::formatDouble(n.rate_hz) + "\n";
  writeFile(fs::path(dir) / "camchain-imucam.yaml", chain);
  writeFile(fs::path(dir) / "imu.yaml", imu);
}

}  // namespace mcvio::dataset
