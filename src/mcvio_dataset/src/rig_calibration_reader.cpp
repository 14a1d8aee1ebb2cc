#include "mcvio/dataset/rig_calibration_reader.hpp"

#include <algorithm>
#include <filesystem>
#include <vector>

#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/euroc_file_reader.hpp"
#include "mcvio/dataset/kalibr_calibration.hpp"

namespace mcvio::dataset {
namespace {

namespace fs = std::filesystem;

bool isYaml(const fs::path& p) { return p.extension() == ".yaml" || p.extension() == ".yml"; }

// The YAML files in `dir` whose names start with `prefix`, sorted.
std::vector<fs::path> yamlFiles(const fs::path& dir, const std::string& prefix) {
  std::vector<fs::path> found;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && isYaml(e.path()) && name.rfind(prefix, 0) == 0) found.push_back(e.path());
  }
  std::sort(found.begin(), found.end());
  return found;
}

std::string listed(const std::vector<fs::path>& files) {
  std::string s;
  for (const auto& f : files) s += (s.empty() ? "" : ", ") + f.filename().string();
  return s;
}

StereoRigCalibration readKalibr(const fs::path& camchain) {
  const fs::path dir = camchain.parent_path().empty() ? fs::path(".") : camchain.parent_path();
  const auto imu = yamlFiles(dir, "imu");
  if (imu.empty()) {
    throw InputError(camchain.string() + " is a Kalibr camchain; its IMU noise comes from Kalibr's imu*.yaml beside it, and " +
                     dir.string() + " has none");
  }
  if (imu.size() > 1) {
    throw InputError(camchain.string() + " is a Kalibr camchain; " + dir.string() + " holds several IMU files (" + listed(imu) +
                     "): keep one imu*.yaml beside it");
  }
  return KalibrCalibration::read(camchain.string(), imu.front().string());
}

}  // namespace

bool RigCalibrationReader::isEurocFolder(const std::string& path) {
  const fs::path p(path);
  std::error_code ec;
  return fs::is_directory(p, ec) && (fs::exists(p / "mav0", ec) || fs::exists(p / "cam0", ec));
}

StereoRigCalibration RigCalibrationReader::read(const std::string& path, std::vector<std::string>* warnings) {
  const fs::path p(path);
  std::error_code ec;
  if (fs::is_regular_file(p, ec)) {
    if (!isYaml(p)) throw InputError(path + ": a calibration file must be a Kalibr camchain YAML (or give a EuRoC folder)");
    return readKalibr(p);
  }
  if (!fs::is_directory(p, ec)) throw InputError(path + ": calibration folder or file does not exist (a EuRoC folder, or Kalibr's camchain-imucam YAML)");
  if (isEurocFolder(path)) return EurocFileReader::readCalibration(path, warnings);
  const auto chains = yamlFiles(p, "camchain-imucam");
  if (chains.size() == 1) return readKalibr(chains.front());
  if (chains.size() > 1) throw InputError(path + ": several Kalibr camchains (" + listed(chains) + "): name one with --calib FILE");
  const auto camera_only = yamlFiles(p, "camchain");
  throw InputError(path + ": neither a EuRoC folder (mav0/cam0, cam1, imu0 with sensor.yaml) nor Kalibr's files "
                   "(camchain-imucam*.yaml and imu*.yaml)" +
                   (camera_only.empty() ? std::string()
                                        : "; " + listed(camera_only) +
                                              " is a camera-only camchain: mcvio needs kalibr_calibrate_imu_camera's camchain-imucam"));
}

}  // namespace mcvio::dataset
