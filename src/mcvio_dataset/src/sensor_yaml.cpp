#include "mcvio/dataset/sensor_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <fstream>
#include <set>
#include <vector>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/write_failure.hpp"
#include "mcvio/core/yaml_file.hpp"
#include "calibration_checks.hpp"
#include "camera_model_fields.hpp"
#include "number_format.hpp"
#include "yaml_section.hpp"

namespace mcvio::dataset {

namespace {

using detail::appendDouble;
using detail::formatDouble;

// A sensor.yaml being read: the top level of the file, plus EuRoC's form of a transform.
class YamlFile : public detail::YamlSection {
 public:
  explicit YamlFile(const std::string& path) : YamlSection(path, "", load(path)) {}

  Eigen::Isometry3d transform(const std::string& key) const {
    const YAML::Node node = require(key);
    if (!node.IsMap()) fail(node, key, "must be a map with rows, cols and data");
    for (const char* dim : {"rows", "cols"}) {
      if (node[dim] && number(node[dim], key + "." + dim) != 4.0)
        fail(node[dim], key + "." + dim, "must be 4");
    }
    const std::string data_key = key + ".data";
    const std::vector<double> d = numbers(require(node, "data"), data_key, 16, 16);
    Eigen::Matrix4d m;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) m(r, c) = d[4 * r + c];
    const std::string problem = detail::transformProblem(m);
    if (!problem.empty()) fail(node["data"], data_key, problem);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.matrix() = m;
    return T;
  }

 private:
  static YAML::Node load(const std::string& path) {
    YAML::Node root = loadYamlFile(path, "sensor calibration file");
    if (!root.IsMap()) throw InputError(path + ": expected a YAML map of sensor keys");
    return root;
  }
};

void appendTransform(std::string& out, const Eigen::Isometry3d& T) {
  out += "T_BS:\n  cols: 4\n  rows: 4\n  data: [";
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      appendDouble(out, T.matrix()(r, c));
      if (r < 3 || c < 3) out += (c == 3) ? ",\n         " : ", ";
    }
  }
  out += "]\n";
}

// EuRoC's sensor.yaml says what it describes; a camera folder holding an IMU's file (or the
// reverse) is a copy mistake.
void expectSensorType(const YamlFile& yaml, const std::string& path, const std::string& expected) {
  if (!yaml.has("sensor_type")) return;
  const std::string type = yaml.text("sensor_type");
  if (type != expected) {
    throw InputError(path + ": key 'sensor_type': '" + type + "', expected '" + expected + "' for this folder");
  }
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream file(path, std::ios::binary | std::ios::trunc);
  file << text;
  file.close();
  if (!file) throwCannotWrite(path, errno);
}

}  // namespace

CameraCalibration SensorYaml::readCamera(const std::string& path, const std::string& name) {
  const YamlFile yaml(path);
  expectSensorType(yaml, path, "camera");
  CameraCalibration calibration;
  calibration.name = name;
  calibration.T_BC = yaml.transform("T_BS");
  calibration.rate_hz = yaml.positive("rate_hz");
  // Without camera_model the file is EuRoC's pinhole; ds and eucm are written as Kalibr does.
  detail::ProjectionFields projection;
  if (yaml.has("camera_model")) {
    std::string problem;
    if (!detail::projectionNamed(yaml.text("camera_model"), &projection, &problem)) {
      yaml.fail(yaml.require("camera_model"), "camera_model", problem);
    }
  }
  const bool wide = projection.wide_angle != DistortionModel::kNone;
  const YAML::Node res_node = yaml.require("resolution");
  const std::vector<double> res = yaml.numbers(res_node, "resolution", 2, 2);
  for (double v : res) {
    if (v < 1.0 || v != std::floor(v) || v > 1e6) {
      yaml.fail(res_node, "resolution", "must be two positive integers [width, height]");
    }
  }
  const YAML::Node in_node = yaml.require("intrinsics");
  const std::vector<double> in =
      yaml.numbers(in_node, "intrinsics", projection.intrinsics_count, projection.intrinsics_count);
  Eigen::Vector4d intrinsics, coefficients;
  detail::splitIntrinsics(projection, in, &intrinsics, &coefficients);
  const std::string intrinsics_problem =
      detail::intrinsicsProblem(intrinsics, static_cast<int>(res[0]), static_cast<int>(res[1]));
  if (!intrinsics_problem.empty()) yaml.fail(in_node, "intrinsics", intrinsics_problem);
  DistortionModel model;
  const std::string model_name = yaml.has("distortion_model") || !wide ? yaml.text("distortion_model")
                                                                       : std::string("none");
  try {
    model = distortionModelFromString(model_name);
  } catch (const InputError& e) {
    throw InputError(path + ": key 'distortion_model': " + e.what());
  }
  if (wide) {
    if (model != DistortionModel::kNone && model != projection.wide_angle) {
      yaml.fail(yaml.require("distortion_model"), "distortion_model",
                "must be none for camera_model " + yaml.text("camera_model") + ", which models the whole lens");
    }
    model = projection.wide_angle;
  } else if (isProjectionModel(model)) {
    yaml.fail(yaml.require("distortion_model"), "distortion_model",
              "'" + model_name + "' is a camera_model: write camera_model: " +
                  (model == DistortionModel::kDoubleSphere ? "ds" : "eucm") + " with its 6 intrinsics");
  }
  if (!wide && (model != DistortionModel::kNone || yaml.has("distortion_coefficients"))) {
    const YAML::Node node = yaml.require("distortion_coefficients");
    // radial-tangential may carry a fifth coefficient k3 in some calibrations; only zero is
    // representable by this model.
    const std::size_t max_count = model == DistortionModel::kRadialTangential ? 5 : 4;
    const std::size_t min_count = model == DistortionModel::kNone ? 0 : 4;
    const std::vector<double> d =
        yaml.numbers(node, "distortion_coefficients", min_count, max_count);
    if (d.size() == 5 && d[4] != 0.0) {
      yaml.fail(node, "distortion_coefficients",
                "has a non-zero k3, which radial-tangential does not model");
    }
    if (model == DistortionModel::kNone) {
      for (double v : d) {
        if (v != 0.0)
          yaml.fail(node, "distortion_coefficients", "must be zero for distortion_model none");
      }
    } else {
      coefficients = Eigen::Vector4d(d[0], d[1], d[2], d[3]);
    }
  } else if (wide && yaml.has("distortion_coefficients")) {
    const YAML::Node node = yaml.require("distortion_coefficients");
    for (double v : yaml.numbers(node, "distortion_coefficients", 0, 4)) {
      if (v != 0.0) yaml.fail(node, "distortion_coefficients", "must be empty for camera_model " + yaml.text("camera_model"));
    }
  }
  try {
    calibration.model =
        CameraModel(static_cast<int>(res[0]), static_cast<int>(res[1]), intrinsics, model, coefficients);
  } catch (const InputError& e) {
    throw InputError(path + ": " + (wide ? "key 'intrinsics': " : "") + e.what());
  }
  const std::string distortion_problem =
      detail::distortionProblem(calibration.model, wide ? yaml.text("camera_model") : model_name);
  if (!distortion_problem.empty()) {
    const std::string key = wide ? "intrinsics" : "distortion_coefficients";
    yaml.fail(yaml.require(key), key, distortion_problem);
  }
  return calibration;
}

ImuCalibration SensorYaml::readImu(const std::string& path, const std::string& name) {
  const YamlFile yaml(path);
  expectSensorType(yaml, path, "imu");
  ImuCalibration calibration;
  calibration.name = name;
  calibration.T_BS = yaml.transform("T_BS");
  calibration.noise.rate_hz = yaml.positive("rate_hz");
  calibration.noise.gyroscope_noise_density = yaml.positive("gyroscope_noise_density");
  calibration.noise.gyroscope_random_walk = yaml.positive("gyroscope_random_walk");
  calibration.noise.accelerometer_noise_density = yaml.positive("accelerometer_noise_density");
  calibration.noise.accelerometer_random_walk = yaml.positive("accelerometer_random_walk");
  return calibration;
}

std::vector<std::string> SensorYaml::unreadKeys(const std::string& path, bool camera) {
  static const std::set<std::string> kCommon = {"sensor_type", "comment", "T_BS", "rate_hz"};
  static const std::set<std::string> kCamera = {"resolution", "camera_model", "intrinsics", "distortion_model",
                                                "distortion_coefficients"};
  static const std::set<std::string> kImu = {"gyroscope_noise_density", "gyroscope_random_walk",
                                             "accelerometer_noise_density", "accelerometer_random_walk"};
  const YAML::Node root = loadYamlFile(path, "sensor calibration file");
  std::vector<std::string> warnings;
  if (!root.IsMap()) return warnings;
  for (const auto& kv : root) {
    const std::string key = kv.first.Scalar();
    if (kCommon.count(key) || (camera ? kCamera : kImu).count(key)) continue;
    const int line = kv.first.Mark().line;
    warnings.push_back(path + (line >= 0 ? ":" + std::to_string(line + 1) : "") + ": key '" + key +
                       "' is not one mcvio reads from " + (camera ? "a camera's" : "an IMU's") +
                       " sensor.yaml; ignored (misspelt?)");
  }
  return warnings;
}

void SensorYaml::writeCamera(const std::string& path, const CameraCalibration& calibration) {
  const CameraModel& m = calibration.model;
  std::string out = "%YAML:1.0\n# General sensor definitions.\nsensor_type: camera\ncomment: " +
                    calibration.name +
                    " (written by mcvio)\n\n# Sensor extrinsics wrt. the body-frame.\n";
  appendTransform(out, calibration.T_BC);
  out += "\n# Camera specific definitions.\nrate_hz: ";
  appendDouble(out, calibration.rate_hz);
  out += "\nresolution: [" + std::to_string(m.width()) + ", " + std::to_string(m.height()) + "]\n";
  const bool wide = isProjectionModel(m.distortionModel());
  out += std::string("camera_model: ") + detail::cameraModelName(m) + "\nintrinsics: [";
  const std::vector<double> listed = detail::listedIntrinsics(m);
  for (std::size_t i = 0; i < listed.size(); ++i) {
    appendDouble(out, listed[i]);
    if (i + 1 < listed.size()) out += ", ";
  }
  out += m.distortionModel() == DistortionModel::kDoubleSphere      ? "] #xi, alpha, fu, fv, cu, cv\n"
         : m.distortionModel() == DistortionModel::kExtendedUnified ? "] #alpha, beta, fu, fv, cu, cv\n"
                                                                    : "] #fu, fv, cu, cv\n";
  out += std::string("distortion_model: ") + (wide ? "none" : toString(m.distortionModel())) +
         "\ndistortion_coefficients: [";
  if (m.distortionModel() != DistortionModel::kNone && !wide) {
    for (int i = 0; i < 4; ++i) {
      appendDouble(out, m.distortionCoefficients()[i]);
      if (i < 3) out += ", ";
    }
  }
  out += "]\n";
  writeText(path, out);
}

void SensorYaml::writeImu(const std::string& path, const ImuCalibration& calibration) {
  const ImuNoiseParams& n = calibration.noise;
  std::string out = "%YAML:1.0\nsensor_type: imu\ncomment: " + calibration.name +
                    " (written by mcvio)\n\n# Sensor extrinsics wrt. the body-frame.\n";
  appendTransform(out, calibration.T_BS);
  out += "rate_hz: ";
  appendDouble(out, n.rate_hz);
  out += "\n\n# inertial sensor noise model parameters (static)\ngyroscope_noise_density: ";
  appendDouble(out, n.gyroscope_noise_density);
  out += "     # [ rad / s / sqrt(Hz) ]\ngyroscope_random_walk: ";
  appendDouble(out, n.gyroscope_random_walk);
  out += "       # [ rad / s^2 / sqrt(Hz) ]\naccelerometer_noise_density: ";
  appendDouble(out, n.accelerometer_noise_density);
  out += "  # [ m / s^2 / sqrt(Hz) ]\naccelerometer_random_walk: ";
  appendDouble(out, n.accelerometer_random_walk);
  out += "    # [ m / s^3 / sqrt(Hz) ]\n";
  writeText(path, out);
}

void SensorYaml::writePoseSensor(const std::string& path, const std::string& sensor_type,
                                 const std::string& comment, const Eigen::Isometry3d& T_BS) {
  std::string out = "%YAML:1.0\n# General sensor definitions.\nsensor_type: " + sensor_type +
                    "\ncomment: " + comment + "\n\n# Sensor extrinsics wrt. the body-frame.\n";
  appendTransform(out, T_BS);
  writeText(path, out);
}

}  // namespace mcvio::dataset
