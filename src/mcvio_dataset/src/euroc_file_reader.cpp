#include "mcvio/dataset/euroc_file_reader.hpp"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <string>

#include "folder_layout.hpp"
#include "mcvio/dataset/csv_reader.hpp"
#include "mcvio/dataset/sensor_yaml.hpp"
#include "row_parsing.hpp"

namespace mcvio::dataset {

namespace fs = std::filesystem;
using detail::forEachRow;
using detail::IncreasingTime;

namespace {
constexpr double kMaxGyroRadPerS = 1000.0;
constexpr double kMaxAccelMPerS2 = 10000.0;

/// "1e+300", not the 300 digits std::to_string prints.
std::string shortNumber(double v) {
  std::ostringstream os;
  os << std::setprecision(6) << v;
  return os.str();
}
}  // namespace

std::vector<ImuSample> EurocFileReader::readImu(const std::string& path, bool skip_bad_rows,
                                                std::vector<std::string>* warnings) {
  CsvReader csv(path);
  IncreasingTime time;
  std::vector<ImuSample> imu;
  imu.reserve(32768);
  forEachRow(csv, skip_bad_rows, warnings, [&](CsvReader& row) {
    row.expectFieldCount(7, "IMU");
    ImuSample s;
    s.t = row.int64At(0, "timestamp");
    s.gyro = {row.doubleAt(1, "w_RS_S_x"), row.doubleAt(2, "w_RS_S_y"),
              row.doubleAt(3, "w_RS_S_z")};
    s.accel = {row.doubleAt(4, "a_RS_S_x"), row.doubleAt(5, "a_RS_S_y"),
               row.doubleAt(6, "a_RS_S_z")};
    // Far beyond any MEMS range (16 g, 35 rad/s): a unit mix-up or a corrupt row, which would
    // only surface later as a failed solve.
    if (s.gyro.cwiseAbs().maxCoeff() > kMaxGyroRadPerS) {
      row.fail("angular velocity " + shortNumber(s.gyro.cwiseAbs().maxCoeff()) + " rad/s is implausible (limit " +
               std::to_string(kMaxGyroRadPerS) + "; degrees instead of radians?)");
    }
    if (s.accel.cwiseAbs().maxCoeff() > kMaxAccelMPerS2) {
      row.fail("acceleration " + shortNumber(s.accel.cwiseAbs().maxCoeff()) + " m/s^2 is implausible (limit " +
               std::to_string(kMaxAccelMPerS2) + ")");
    }
    time.check(row, s.t);
    imu.push_back(s);
  });
  if (imu.empty()) throw InputError(path + ": contains no IMU samples");
  return imu;
}

std::vector<GroundTruthState> EurocFileReader::readGroundTruth(const std::string& path,
                                                               bool skip_bad_rows,
                                                               std::vector<std::string>* warnings) {
  CsvReader csv(path);
  IncreasingTime time;
  std::vector<GroundTruthState> states;
  forEachRow(csv, skip_bad_rows, warnings, [&](CsvReader& row) {
    row.expectFieldCount(17, "ground-truth");
    GroundTruthState s;
    s.t = row.int64At(0, "timestamp");
    s.p_WB = {row.doubleAt(1, "p_x"), row.doubleAt(2, "p_y"), row.doubleAt(3, "p_z")};
    s.q_WB = Eigen::Quaterniond(row.doubleAt(4, "q_w"), row.doubleAt(5, "q_x"),
                                row.doubleAt(6, "q_y"), row.doubleAt(7, "q_z"));
    const double norm = s.q_WB.norm();
    if (std::abs(norm - 1.0) > 1e-3) {
      row.fail("quaternion (q_w, q_x, q_y, q_z) has norm " + std::to_string(norm) + ", expected 1");
    }
    // Leave unit quaternions bit-exact so write-then-read is lossless.
    if (std::abs(norm - 1.0) > 1e-12) s.q_WB.normalize();
    s.v_WB = {row.doubleAt(8, "v_x"), row.doubleAt(9, "v_y"), row.doubleAt(10, "v_z")};
    s.bias_gyro = {row.doubleAt(11, "bw_x"), row.doubleAt(12, "bw_y"), row.doubleAt(13, "bw_z")};
    s.bias_accel = {row.doubleAt(14, "ba_x"), row.doubleAt(15, "ba_y"), row.doubleAt(16, "ba_z")};
    time.check(row, s.t);
    states.push_back(s);
  });
  return states;
}

std::vector<ConflictLabel> EurocFileReader::readLabels(const std::string& path, bool skip_bad_rows,
                                                       std::vector<std::string>* warnings) {
  CsvReader csv(path);
  IncreasingTime time;
  std::vector<ConflictLabel> labels;
  forEachRow(csv, skip_bad_rows, warnings, [&](CsvReader& row) {
    row.expectFieldCount(4, "conflict label");
    ConflictLabel label;
    label.t = row.int64At(0, "timestamp");
    const std::int64_t flag = row.int64At(1, "in_conflict");
    if (flag != 0 && flag != 1) {
      row.fail("column 'in_conflict' must be 0 or 1, got " + std::to_string(flag));
    }
    label.in_conflict = flag == 1;
    label.motion = std::string(row.field(2));
    if (label.motion.empty()) row.fail("column 'motion' is empty");
    label.covered_fraction = row.doubleAt(3, "covered_fraction");
    if (label.covered_fraction < 0.0 || label.covered_fraction > 1.0) {
      row.fail("column 'covered_fraction' must be in [0, 1], got " + std::string(row.field(3)));
    }
    time.check(row, label.t);
    labels.push_back(std::move(label));
  });
  return labels;
}

StereoRigCalibration EurocFileReader::readCalibration(const std::string& dir, std::vector<std::string>* warnings) {
  const fs::path mav0 = detail::resolveMav0(dir);
  StereoRigCalibration calib;
  for (int i = 0; i < 2; ++i) {
    const std::string name = "cam" + std::to_string(i);
    detail::requireDir(mav0 / name);
    calib.camera(i) =
        SensorYaml::readCamera(detail::requireFile(mav0 / name / "sensor.yaml"), name);
  }
  detail::requireDir(mav0 / "imu0");
  calib.imu = SensorYaml::readImu(detail::requireFile(mav0 / "imu0" / "sensor.yaml"), "imu0");
  if (warnings != nullptr) {
    for (const char* sensor : {"cam0", "cam1", "imu0"}) {
      for (auto& w : SensorYaml::unreadKeys((mav0 / sensor / "sensor.yaml").string(), std::string(sensor) != "imu0"))
        warnings->push_back(std::move(w));
    }
  }
  return calib;
}

}  // namespace mcvio::dataset
