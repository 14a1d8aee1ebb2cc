#include "test_sequence.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include "mcvio/dataset/euroc_writer.hpp"

namespace mcvio::dataset::test {

namespace fs = std::filesystem;

StereoRigCalibration makeRig() {
  StereoRigCalibration rig;
  rig.cam0.name = "cam0";
  rig.cam0.model = CameraModel(64, 48, {45.123456789012345, 44.98765432109876, 31.7, 23.3},
                               DistortionModel::kRadialTangential,
                               {-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05});
  rig.cam0.rate_hz = 20.0;
  rig.cam0.T_BC.linear() =
      Eigen::AngleAxisd(0.1, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  rig.cam0.T_BC.translation() = Eigen::Vector3d(-0.0216401454975, -0.064676986768, 0.1 / 3.0);
  rig.cam1.name = "cam1";
  rig.cam1.model =
      CameraModel(64, 48, {100.0 / 3.0, 200.0 / 7.0, 32.0, 24.0}, DistortionModel::kEquidistant,
                  {0.0034823894, 0.000715034, -0.0020532361, 0.00020293673});
  rig.cam1.rate_hz = 20.0;
  rig.cam1.T_BC.linear() =
      Eigen::AngleAxisd(-0.2, Eigen::Vector3d(3, 1, 2).normalized()).toRotationMatrix();
  rig.cam1.T_BC.translation() = Eigen::Vector3d(0.11, 1.0 / 9.0, -0.002);
  rig.imu.noise.gyroscope_noise_density = 1.6968e-04;
  rig.imu.noise.gyroscope_random_walk = 1.9393e-05;
  rig.imu.noise.accelerometer_noise_density = 2.0e-3;
  rig.imu.noise.accelerometer_random_walk = 3.0e-3;
  rig.imu.noise.rate_hz = 200.0;
  return rig;
}

TestSequence makeSequence(int frames, unsigned seed) {
  TestSequence seq;
  seq.rig = makeRig();
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_int_distribution<int> pixel(0, 255);
  const Timestamp t0 = 1403715273262142976;
  const Timestamp frame_dt = 50'000'000, imu_dt = 5'000'000;
  for (int i = 0; i < frames; ++i) {
    const Timestamp t = t0 + i * frame_dt + (i % 3);  // real EuRoC stamps are not round
    seq.frame_times.push_back(t);
    cv::Mat a(48, 64, CV_8UC1), b(48, 64, CV_8UC1);
    for (int r = 0; r < 48; ++r)
      for (int c = 0; c < 64; ++c) {
        a.at<unsigned char>(r, c) = static_cast<unsigned char>(pixel(rng));
        b.at<unsigned char>(r, c) = static_cast<unsigned char>(pixel(rng));
      }
    seq.cam0.push_back(a);
    seq.cam1.push_back(b);
    GroundTruthState gt;
    gt.t = t;
    gt.p_WB = Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    gt.q_WB = Eigen::Quaterniond(
        Eigen::Vector4d(noise(rng), noise(rng), noise(rng), noise(rng)).normalized());
    gt.v_WB = Eigen::Vector3d(noise(rng), noise(rng), noise(rng)) * 1e-3;
    gt.bias_gyro = Eigen::Vector3d(noise(rng), noise(rng), noise(rng)) * 1e-7;
    gt.bias_accel = Eigen::Vector3d(noise(rng), noise(rng), noise(rng)) * 1e12;
    seq.ground_truth.push_back(gt);
    ConflictLabel label;
    label.t = t;
    label.in_conflict = i % 4 >= 2;
    label.motion = label.in_conflict ? "elevator" : "none";
    label.covered_fraction = label.in_conflict ? std::abs(std::sin(0.1 * i)) : 0.0;
    seq.labels.push_back(label);
  }
  for (int i = 0; i < frames * 10; ++i) {
    ImuSample s;
    s.t = t0 + i * imu_dt - 7;
    s.gyro = Eigen::Vector3d(noise(rng), noise(rng), noise(rng)) * 0.01;
    s.accel = Eigen::Vector3d(noise(rng), noise(rng), 9.81 + noise(rng)) / 3.0;
    seq.imu.push_back(s);
  }
  return seq;
}

void writeSequence(const std::string& dir, const TestSequence& seq, bool with_ground_truth,
                   bool with_labels) {
  EurocWriter::Options options;
  options.overwrite = true;
  EurocWriter writer(dir, seq.rig, options);
  for (std::size_t i = 0; i < seq.frame_times.size(); ++i) {
    writer.addStereoFrame(seq.frame_times[i], seq.cam0[i], seq.cam1[i]);
    if (with_ground_truth) writer.addGroundTruth(seq.ground_truth[i]);
    if (with_labels) writer.addLabel(seq.labels[i]);
  }
  for (const ImuSample& s : seq.imu) writer.addImu(s);
  writer.close();
}

std::string freshDir(const std::string& name) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("mcvio_dataset_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
}

void replaceLine(const std::string& path, int line, const std::string& text) {
  std::istringstream in(readText(path));
  std::string out, current;
  int n = 0;
  bool found = false;
  while (std::getline(in, current)) {
    ++n;
    if (n == line) {
      current = text;
      found = true;
    }
    out += current + "\n";
  }
  if (!found) throw std::runtime_error("no line " + std::to_string(line) + " in " + path);
  writeText(path, out);
}

}  // namespace mcvio::dataset::test
