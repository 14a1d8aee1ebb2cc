#include "mcvio/sim/recorded_sequence_reader.hpp"

#include <filesystem>

#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/csv_reader.hpp"
#include "mcvio/dataset/sensor_yaml.hpp"

namespace mcvio::sim {

std::vector<dataset::GroundTruthState> RecordedSequenceReader::readGroundTruth(const std::string& path) {
  dataset::CsvReader csv(path);
  std::vector<dataset::GroundTruthState> out;
  while (csv.nextRow()) {
    csv.expectFieldCount(17, "ground-truth row");
    dataset::GroundTruthState s;
    s.t = csv.int64At(0, "timestamp");
    s.p_WB = {csv.doubleAt(1, "p_x"), csv.doubleAt(2, "p_y"), csv.doubleAt(3, "p_z")};
    s.q_WB = Eigen::Quaterniond(csv.doubleAt(4, "q_w"), csv.doubleAt(5, "q_x"), csv.doubleAt(6, "q_y"),
                                csv.doubleAt(7, "q_z"));
    if (s.q_WB.norm() < 1e-6) csv.fail("quaternion has zero length");
    s.q_WB.normalize();
    s.v_WB = {csv.doubleAt(8, "v_x"), csv.doubleAt(9, "v_y"), csv.doubleAt(10, "v_z")};
    s.bias_gyro = {csv.doubleAt(11, "b_w_x"), csv.doubleAt(12, "b_w_y"), csv.doubleAt(13, "b_w_z")};
    s.bias_accel = {csv.doubleAt(14, "b_a_x"), csv.doubleAt(15, "b_a_y"), csv.doubleAt(16, "b_a_z")};
    if (!out.empty() && s.t <= out.back().t) csv.fail("timestamp not increasing");
    out.push_back(s);
  }
  if (out.size() < 2) throw InputError(path + ": needs at least two ground-truth rows");
  return out;
}

std::vector<ImuSample> RecordedSequenceReader::readImu(const std::string& path) {
  dataset::CsvReader csv(path);
  std::vector<ImuSample> out;
  while (csv.nextRow()) {
    csv.expectFieldCount(7, "IMU row");
    ImuSample s;
    s.t = csv.int64At(0, "timestamp");
    s.gyro = {csv.doubleAt(1, "w_x"), csv.doubleAt(2, "w_y"), csv.doubleAt(3, "w_z")};
    s.accel = {csv.doubleAt(4, "a_x"), csv.doubleAt(5, "a_y"), csv.doubleAt(6, "a_z")};
    if (!out.empty() && s.t <= out.back().t) csv.fail("timestamp not increasing");
    out.push_back(s);
  }
  if (out.empty()) throw InputError(path + ": no IMU rows");
  return out;
}

StereoRigCalibration RecordedSequenceReader::readCalibration(const std::string& dir,
                                                             const ImuCalibration& imu_fallback) {
  namespace fs = std::filesystem;
  fs::path root(dir);
  if (!fs::exists(root / "cam0" / "sensor.yaml") && fs::exists(root / "mav0" / "cam0" / "sensor.yaml"))
    root /= "mav0";
  for (const char* cam : {"cam0", "cam1"})
    if (!fs::exists(root / cam / "sensor.yaml"))
      throw InputError(dir + ": calibration folder has no " + cam + "/sensor.yaml");
  StereoRigCalibration rig;
  rig.cam0 = dataset::SensorYaml::readCamera((root / "cam0" / "sensor.yaml").string(), "cam0");
  rig.cam1 = dataset::SensorYaml::readCamera((root / "cam1" / "sensor.yaml").string(), "cam1");
  rig.imu = imu_fallback;
  if (fs::exists(root / "imu0" / "sensor.yaml"))
    rig.imu = dataset::SensorYaml::readImu((root / "imu0" / "sensor.yaml").string(), "imu0");
  return rig;
}

}  // namespace mcvio::sim
