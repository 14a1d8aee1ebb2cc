#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "commands/command_context.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/euroc_writer.hpp"
#include "mcvio/dataset/kalibr_calibration.hpp"
#include "mcvio/dataset/rig_calibration_reader.hpp"

namespace mcvio::cli {
namespace {

std::string vec3(const Eigen::Vector3d& v, int precision) {
  char b[96];
  std::snprintf(b, sizeof(b), "[%.*f, %.*f, %.*f]", precision, v.x(), precision, v.y(), precision, v.z());
  return b;
}

// What mcvio reads from the calibration: the numbers a wrong file or a wrong convention shows in.
std::string describe(const StereoRigCalibration& rig) {
  std::ostringstream os;
  os.setf(std::ios::fixed);
  for (int i = 0; i < 2; ++i) {
    const CameraCalibration& c = rig.camera(i);
    const CameraModel& m = c.model;
    const Eigen::Vector4d& d = m.distortionCoefficients();
    os.precision(3);
    const bool wide = isProjectionModel(m.distortionModel());
    os << "cam" << i << ": " << m.width() << "x" << m.height() << " " << (wide ? toString(m.distortionModel()) : "pinhole")
       << ", fu " << m.fu() << " fv " << m.fv() << " cu " << m.cu() << " cv " << m.cv();
    char b[128];
    if (m.distortionModel() == DistortionModel::kDoubleSphere) {
      std::snprintf(b, sizeof(b), ", xi %.6g alpha %.6g", d[0], d[1]);
      os << b;
    } else if (m.distortionModel() == DistortionModel::kExtendedUnified) {
      std::snprintf(b, sizeof(b), ", alpha %.6g beta %.6g", d[0], d[1]);
      os << b;
    } else {
      os << ", " << toString(m.distortionModel());
      if (m.distortionModel() != DistortionModel::kNone) {
        std::snprintf(b, sizeof(b), " [%.6g, %.6g, %.6g, %.6g]", d[0], d[1], d[2], d[3]);
        os << b;
      }
    }
    os << "\n      in the IMU frame: position " << vec3(c.T_BC.translation(), 4) << " m, optical axis "
       << vec3(c.T_BC.linear().col(2), 3) << "\n";
  }
  const Eigen::Isometry3d T_C0C1 = rig.T_C0C1();
  os.precision(4);
  os << "stereo: baseline " << rig.baseline() << " m; cam1 in cam0: position " << vec3(T_C0C1.translation(), 4)
     << " m, rotated by ";
  os.precision(3);
  os << Eigen::AngleAxisd(T_C0C1.linear()).angle() * 180.0 / M_PI << " degrees\n";
  os << "camera time shift: " << static_cast<double>(rig.camera_time_offset_ns) * 1e-6
     << " ms (IMU time = camera stamp + shift)\n";
  if (!rig.cam0.topic.empty() || !rig.cam1.topic.empty() || !rig.imu.topic.empty()) {
    const auto topic = [](const std::string& t, const char* fallback) { return t.empty() ? std::string(fallback) : t; };
    os << "topics (rostopic): cam0 " << topic(rig.cam0.topic, "/cam0/image_raw") << ", cam1 "
       << topic(rig.cam1.topic, "/cam1/image_raw") << ", imu0 " << topic(rig.imu.topic, "/imu0")
       << " (frontend, backend and run read these unless --remap says otherwise)\n";
  }
  const ImuNoiseParams& n = rig.imu.noise;
  os.unsetf(std::ios::fixed);
  os << "imu0: " << n.rate_hz << " Hz; gyroscope noise " << n.gyroscope_noise_density << " rad/s/sqrt(Hz), random walk "
     << n.gyroscope_random_walk << " rad/s^2/sqrt(Hz); accelerometer noise " << n.accelerometer_noise_density
     << " m/s^2/sqrt(Hz), random walk " << n.accelerometer_random_walk << " m/s^3/sqrt(Hz)\n";
  return os.str();
}

}  // namespace

void addCalibCommand(CLI::App& app, CommandContext&) {
  struct Options {
    std::string path, to_euroc, to_kalibr;
  };
  auto opt = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "calib",
      "Show the stereo-inertial calibration as mcvio reads it from what --calib takes: a EuRoC folder\n"
      "(cam0/cam1/imu0 sensor.yaml) or Kalibr's camchain-imucam YAML (file, or its folder) with its\n"
      "imu*.yaml beside it. Camera models: pinhole with radtan, equidistant or no distortion, and the\n"
      "wide-angle ds (double sphere) and eucm (extended unified) that Basalt and Kalibr calibrate.\n"
      "Prints each camera's intrinsics, distortion, position and optical axis in the IMU frame, the\n"
      "stereo baseline, the topics Kalibr's rostopic names, the camera time shift and the IMU noise;\n"
      "--to-euroc writes the same as a EuRoC folder without data (DIR/mav0/cam0, cam1, imu0 sensor.yaml),\n"
      "usable as --calib DIR; --to-kalibr writes Kalibr's camchain-imucam.yaml and imu.yaml (OpenVINS's\n"
      "kalibr_imucam_chain and kalibr_imu_chain take them too).\n"
      "Examples:\n"
      "  mcvio calib ../shared/data/euroc_V1_01_excerpt\n"
      "  mcvio calib /data/kalibr/camchain-imucam-run1.yaml\n"
      "  mcvio calib /data/kalibr --to-euroc /data/rig_euroc\n"
      "  mcvio calib ../shared/data/euroc_V1_01_excerpt --to-kalibr /tmp/v1_kalibr");
  cmd->add_option("calibration", opt->path, "EuRoC folder, Kalibr camchain-imucam YAML, or the folder holding it")->required();
  cmd->add_option("--to-euroc", opt->to_euroc,
                  "write the calibration as EuRoC sensor.yaml files below DIR/mav0 (DIR/mav0 must not exist)");
  cmd->add_option("--to-kalibr", opt->to_kalibr,
                  "write the calibration as Kalibr's DIR/camchain-imucam.yaml and DIR/imu.yaml (neither may exist);\n"
                  "rostopic is the calibration's topics, or /cam0/image_raw, /cam1/image_raw and /imu0");
  cmd->callback([opt] {
    namespace fs = std::filesystem;
    std::error_code ec;
    // Refused before anything is written: a second run must not overwrite a calibration.
    if (!opt->to_euroc.empty() && fs::exists(fs::path(opt->to_euroc) / "mav0", ec))
      throw InputError((fs::path(opt->to_euroc) / "mav0").string() + ": already exists; --to-euroc writes a new folder");
    for (const char* name : {"camchain-imucam.yaml", "imu.yaml"})
      if (!opt->to_kalibr.empty() && fs::exists(fs::path(opt->to_kalibr) / name, ec))
        throw InputError((fs::path(opt->to_kalibr) / name).string() + ": already exists; --to-kalibr does not overwrite");
    std::vector<std::string> warnings;
    const StereoRigCalibration rig = dataset::RigCalibrationReader::read(opt->path, &warnings);
    for (const auto& w : warnings) std::cerr << "mcvio calib: warning: " << w << "\n";
    std::cout << "calibration: " << opt->path << "\n" << describe(rig);
    if (!opt->to_kalibr.empty()) {
      dataset::KalibrCalibration::write(rig, opt->to_kalibr);
      std::cout << "wrote " << (fs::path(opt->to_kalibr) / "camchain-imucam.yaml").string() << " and imu.yaml\n";
    }
    if (opt->to_euroc.empty()) return;
    const fs::path mav0 = fs::path(opt->to_euroc) / "mav0";
    // The writer of every EuRoC folder mcvio makes: sensor.yaml files (and empty data.csv files).
    dataset::EurocWriter(opt->to_euroc, rig).close();
    std::cout << "wrote " << mav0.string() << "/{cam0,cam1,imu0}/sensor.yaml\n";
    if (!dataset::RigCalibrationReader::isEurocFolder(opt->path)) {
      std::cerr << "mcvio calib: note: Kalibr's files give no camera frame rate; the sensor.yaml files say rate_hz "
                << rig.cam0.rate_hz << " (mcvio does not use it; edit it for other tools)\n";
    }
    if (!rig.cam0.topic.empty() || !rig.cam1.topic.empty() || !rig.imu.topic.empty()) {
      std::cerr << "mcvio calib: note: EuRoC's sensor.yaml names no topics; with " << opt->to_euroc
                << " as --calib, give the rostopic above with --remap (e.g. --remap /imu0:=" << (rig.imu.topic.empty() ? "TOPIC" : rig.imu.topic) << ")\n";
    }
    if (rig.camera_time_offset_ns != 0) {
      std::cerr << "mcvio calib: warning: EuRoC's sensor.yaml has no camera time shift; the " << opt->to_euroc
                << " calibration leaves out the " << static_cast<double>(rig.camera_time_offset_ns) * 1e-6
                << " ms shift (keep giving the Kalibr files to apply it)\n";
    }
  });
}

}  // namespace mcvio::cli
