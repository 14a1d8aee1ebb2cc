#include "mcvio/dataset/euroc_writer.hpp"

#include <cerrno>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/write_failure.hpp"
#include "mcvio/dataset/sensor_yaml.hpp"
#include "number_format.hpp"

namespace mcvio::dataset {

namespace fs = std::filesystem;
using detail::appendDouble;
using detail::appendInt;

namespace {

void createDir(const fs::path& path) {
  std::error_code ec;
  fs::create_directories(path, ec);
  if (ec) throw InputError(path.string() + ": cannot create folder: " + ec.message());
}

void appendVector(std::string& line, const Eigen::Vector3d& v) {
  for (int i = 0; i < 3; ++i) {
    line += ',';
    appendDouble(line, v[i]);
  }
}

}  // namespace

EurocWriter::EurocWriter(const std::string& dir, const StereoRigCalibration& calibration,
                         const Options& options)
    : calibration_(calibration), options_(options) {
  if (options.png_compression < 0 || options.png_compression > 9) {
    throw std::invalid_argument("EurocWriter: png_compression must be in 0-9");
  }
  const fs::path mav0 = fs::path(dir) / "mav0";
  std::error_code ec;
  if (fs::exists(mav0, ec)) {
    if (!options.overwrite) {
      throw InputError(mav0.string() + ": already exists (--overwrite, or overwrite: true in the options, replaces it)");
    }
    fs::remove_all(mav0, ec);
    if (ec) throw InputError(mav0.string() + ": cannot remove: " + ec.message());
  }
  root_ = mav0.string();
  for (int i = 0; i < 2; ++i) {
    const fs::path cam_dir = mav0 / ("cam" + std::to_string(i));
    createDir(cam_dir / "data");
    CameraCalibration cam = calibration.camera(i);
    cam.name = "cam" + std::to_string(i);
    SensorYaml::writeCamera((cam_dir / "sensor.yaml").string(), cam);
    openStream(&cam_[i], (cam_dir / "data.csv").string(), "#timestamp [ns],filename\n");
  }
  createDir(mav0 / "imu0");
  SensorYaml::writeImu((mav0 / "imu0" / "sensor.yaml").string(), calibration.imu);
  openStream(&imu_, (mav0 / "imu0" / "data.csv").string(),
             "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
             "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n");
  SensorYaml::writePoseSensor((mav0 / "body.yaml").string(), "body", "written by mcvio",
                              Eigen::Isometry3d::Identity());
}

EurocWriter::~EurocWriter() {
  try {
    close();
  } catch (...) {
    // A destructor must not throw; close() reports failures to callers who ask.
  }
}

void EurocWriter::openStream(Stream* stream, const std::string& path, const char* header) {
  stream->path = path;
  stream->file = std::fopen(path.c_str(), "wb");
  if (!stream->file) throw InputError(path + ": cannot create file");
  std::setvbuf(stream->file, nullptr, _IOFBF, 1 << 16);
  writeLine(stream, header);
}

void EurocWriter::checkOpen() const {
  if (closed_) throw std::logic_error("EurocWriter: add after close()");
}

void EurocWriter::checkTime(Stream* stream, Timestamp t, const char* what) const {
  if (stream->has_rows && t <= stream->last_t) {
    throw std::invalid_argument(std::string("EurocWriter: ") + what + " timestamp " +
                                std::to_string(t) + " does not increase (previous " +
                                std::to_string(stream->last_t) + ")");
  }
}

void EurocWriter::writeLine(Stream* stream, const std::string& line) {
  if (std::fwrite(line.data(), 1, line.size(), stream->file) != line.size()) {
    throw InputError(stream->path + ": write failed");
  }
}

void EurocWriter::addStereoFrame(Timestamp t, const cv::Mat& cam0, const cv::Mat& cam1) {
  // Validate both before writing either, so a bad pair leaves no half frame behind.
  checkOpen();
  checkTime(&cam_[0], t, "cam0");
  checkTime(&cam_[1], t, "cam1");
  for (int i = 0; i < 2; ++i) {
    const cv::Mat& image = i == 0 ? cam0 : cam1;
    const CameraModel& model = calibration_.camera(i).model;
    if (image.type() != CV_8UC1 || image.cols != model.width() || image.rows != model.height()) {
      throw std::invalid_argument("EurocWriter: cam" + std::to_string(i) +
                                  " image must be CV_8UC1 " + std::to_string(model.width()) + "x" +
                                  std::to_string(model.height()));
    }
  }
  addImage(0, t, cam0);
  addImage(1, t, cam1);
}

void EurocWriter::addImage(int camera, Timestamp t, const cv::Mat& image) {
  checkOpen();
  if (camera != 0 && camera != 1) throw std::invalid_argument("EurocWriter: camera must be 0 or 1");
  Stream& stream = cam_[camera];
  const char* name = camera == 0 ? "cam0" : "cam1";
  checkTime(&stream, t, name);
  const CameraModel& model = calibration_.camera(camera).model;
  if (image.type() != CV_8UC1 || image.cols != model.width() || image.rows != model.height()) {
    throw std::invalid_argument(std::string("EurocWriter: ") + name + " image must be CV_8UC1 " +
                                std::to_string(model.width()) + "x" +
                                std::to_string(model.height()));
  }
  const std::string filename = std::to_string(t) + ".png";
  const std::string path = (fs::path(root_) / name / "data" / filename).string();
  bool ok = false;
  try {
    ok = cv::imwrite(path, image, {cv::IMWRITE_PNG_COMPRESSION, options_.png_compression});
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot write image: " + e.what());
  }
  if (!ok) throwCannotWrite(path, errno, "image");
  line_.clear();
  appendInt(line_, t);
  line_ += ',';
  line_ += filename;
  line_ += '\n';
  writeLine(&stream, line_);
  stream.last_t = t;
  stream.has_rows = true;
}

void EurocWriter::addImu(const ImuSample& s) {
  checkOpen();
  checkTime(&imu_, s.t, "IMU");
  if (!s.gyro.allFinite() || !s.accel.allFinite()) {
    throw std::invalid_argument("EurocWriter: IMU sample at " + std::to_string(s.t) +
                                " is not finite");
  }
  line_.clear();
  appendInt(line_, s.t);
  appendVector(line_, s.gyro);
  appendVector(line_, s.accel);
  line_ += '\n';
  writeLine(&imu_, line_);
  imu_.last_t = s.t;
  imu_.has_rows = true;
}

void EurocWriter::addGroundTruth(const GroundTruthState& s) {
  checkOpen();
  checkTime(&ground_truth_, s.t, "ground-truth");
  if (!s.p_WB.allFinite() || !s.q_WB.coeffs().allFinite() || !s.v_WB.allFinite() ||
      !s.bias_gyro.allFinite() || !s.bias_accel.allFinite()) {
    throw std::invalid_argument("EurocWriter: ground-truth state at " + std::to_string(s.t) +
                                " is not finite");
  }
  if (!ground_truth_.file) {
    const fs::path dir = fs::path(root_) / "state_groundtruth_estimate0";
    createDir(dir);
    SensorYaml::writePoseSensor((dir / "sensor.yaml").string(), "visual-inertial",
                                "ground truth written by mcvio", Eigen::Isometry3d::Identity());
    openStream(&ground_truth_, (dir / "data.csv").string(),
               "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], "
               "q_RS_y [], q_RS_z [], v_RS_R_x [m s^-1], v_RS_R_y [m s^-1], v_RS_R_z [m s^-1], "
               "b_w_RS_S_x [rad s^-1], b_w_RS_S_y [rad s^-1], b_w_RS_S_z [rad s^-1], "
               "b_a_RS_S_x [m s^-2], b_a_RS_S_y [m s^-2], b_a_RS_S_z [m s^-2]\n");
  }
  line_.clear();
  appendInt(line_, s.t);
  appendVector(line_, s.p_WB);
  for (double q : {s.q_WB.w(), s.q_WB.x(), s.q_WB.y(), s.q_WB.z()}) {
    line_ += ',';
    appendDouble(line_, q);
  }
  appendVector(line_, s.v_WB);
  appendVector(line_, s.bias_gyro);
  appendVector(line_, s.bias_accel);
  line_ += '\n';
  writeLine(&ground_truth_, line_);
  ground_truth_.last_t = s.t;
  ground_truth_.has_rows = true;
}

void EurocWriter::addLabel(const ConflictLabel& label) {
  checkOpen();
  checkTime(&labels_, label.t, "conflict label");
  if (label.motion.empty() || label.motion.find_first_of(",\"\r\n#") != std::string::npos ||
      label.motion.front() == ' ' || label.motion.back() == ' ') {
    throw std::invalid_argument("EurocWriter: label motion '" + label.motion +
                                "' must be non-empty without commas, quotes, '#', line breaks or "
                                "surrounding spaces");
  }
  if (!(label.covered_fraction >= 0.0 && label.covered_fraction <= 1.0)) {
    throw std::invalid_argument("EurocWriter: label covered_fraction must be in [0, 1]");
  }
  if (!labels_.file) {
    openStream(&labels_, (fs::path(root_) / "conflict_labels.csv").string(),
               "#timestamp [ns],in_conflict,motion,covered_fraction\n");
  }
  line_.clear();
  appendInt(line_, label.t);
  line_ += label.in_conflict ? ",1," : ",0,";
  line_ += label.motion;
  line_ += ',';
  appendDouble(line_, label.covered_fraction);
  line_ += '\n';
  writeLine(&labels_, line_);
  labels_.last_t = label.t;
  labels_.has_rows = true;
}

void EurocWriter::close() {
  if (closed_) return;
  closed_ = true;
  std::string failed;
  for (Stream* s : {&cam_[0], &cam_[1], &imu_, &ground_truth_, &labels_}) {
    if (s->file && std::fclose(s->file) != 0 && failed.empty()) failed = s->path;
    s->file = nullptr;
  }
  if (!failed.empty()) throw InputError(failed + ": write failed on close");
}

}  // namespace mcvio::dataset
