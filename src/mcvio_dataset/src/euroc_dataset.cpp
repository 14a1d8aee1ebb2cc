#include "mcvio/dataset/euroc_dataset.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <unordered_set>

#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/csv_reader.hpp"
#include "mcvio/dataset/sensor_yaml.hpp"

namespace mcvio::dataset {

namespace fs = std::filesystem;

namespace {

// Runs parse_row on every data row; with skip_bad_rows an InputError only skips its row.
template <typename ParseRow>
void forEachRow(CsvReader& csv, const EurocDatasetOptions& options,
                std::vector<std::string>* warnings, ParseRow parse_row) {
  while (csv.nextRow()) {
    try {
      parse_row(csv);
    } catch (const InputError& e) {
      if (!options.skip_bad_rows) throw;
      warnings->push_back(std::string(e.what()) + " (row skipped)");
    }
  }
}

// Time must increase strictly; a row failing this is not accepted, so `last` stays valid.
void checkIncreasing(const CsvReader& csv, Timestamp t, Timestamp* last, bool* have_last) {
  if (*have_last && t <= *last) {
    csv.fail(t == *last ? "duplicate timestamp " + std::to_string(t)
                        : "timestamp " + std::to_string(t) +
                              " is earlier than the previous row's " + std::to_string(*last));
  }
  *last = t;
  *have_last = true;
}

std::string requireDir(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_directory(path, ec)) throw InputError(path.string() + ": missing folder");
  return path.string();
}

std::string requireFile(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw InputError(path.string() + ": missing file");
  return path.string();
}

// Reads width and height from a PNG's IHDR chunk; false if the file is not a readable PNG.
bool readPngSize(const std::string& path, int* width, int* height) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "rb"),
                                                       &std::fclose);
  if (!file) return false;
  unsigned char header[24];
  if (std::fread(header, 1, sizeof(header), file.get()) != sizeof(header)) return false;
  static const unsigned char kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (std::memcmp(header, kSignature, 8) != 0 || std::memcmp(header + 12, "IHDR", 4) != 0)
    return false;
  auto be32 = [](const unsigned char* p) {
    return static_cast<int>((std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) |
                            (std::uint32_t(p[2]) << 8) | std::uint32_t(p[3]));
  };
  *width = be32(header + 16);
  *height = be32(header + 20);
  return true;
}

std::string sizeMismatch(const std::string& path, int width, int height,
                         const CameraCalibration& cam, const std::string& yaml) {
  return path + ": image is " + std::to_string(width) + "x" + std::to_string(height) + " but " +
         yaml + " gives resolution [" + std::to_string(cam.model.width()) + ", " +
         std::to_string(cam.model.height()) + "]";
}

struct CameraRow {
  Timestamp t;
  std::string path;
};

// Lists a camera's frames whose image exists; rows without an image are reported and skipped.
std::vector<CameraRow> readCameraRows(const fs::path& cam_dir, const EurocDatasetOptions& options,
                                      std::vector<std::string>* warnings) {
  const fs::path data_dir = requireDir(cam_dir / "data");
  std::unordered_set<std::string> files;
  std::error_code ec;
  for (fs::directory_iterator it(data_dir, ec), end; !ec && it != end; it.increment(ec)) {
    files.insert(it->path().filename().string());
  }
  if (ec) throw InputError(data_dir.string() + ": cannot list folder: " + ec.message());

  CsvReader csv((cam_dir / "data.csv").string());
  std::vector<CameraRow> rows;
  Timestamp last = 0;
  bool have_last = false;
  forEachRow(csv, options, warnings, [&](CsvReader& row) {
    row.expectFieldCount(2, "camera");
    const Timestamp t = row.int64At(0, "timestamp");
    const std::string name(row.field(1));
    if (name.empty()) row.fail("column 'filename' is empty");
    checkIncreasing(row, t, &last, &have_last);
    const bool exists = name.find('/') == std::string::npos
                            ? files.count(name) > 0
                            : fs::is_regular_file(data_dir / name, ec);
    if (!exists) {
      warnings->push_back(row.location() + ": image data/" + name + " does not exist; frame " +
                          std::to_string(t) + " skipped");
      return;
    }
    rows.push_back({t, (data_dir / name).string()});
  });
  return rows;
}

}  // namespace

EurocDataset EurocDataset::open(const std::string& dir, const EurocDatasetOptions& options) {
  if (options.max_stereo_offset_ns < 0) {
    throw InputError("dataset options: max_stereo_offset_ns must not be negative");
  }
  std::error_code ec;
  const fs::path base(dir);
  if (!fs::is_directory(base, ec)) throw InputError(dir + ": EuRoC folder does not exist");
  fs::path root = base / "mav0";
  if (!fs::is_directory(root, ec)) {
    if (!fs::is_directory(base / "cam0", ec) && !fs::is_directory(base / "imu0", ec)) {
      throw InputError(dir + ": not a EuRoC folder (no mav0 folder, and no cam0/imu0 in it)");
    }
    root = base;
  }

  EurocDataset data;
  data.root_ = fs::absolute(root, ec).lexically_normal().string();
  if (ec) data.root_ = root.string();
  const fs::path mav0(data.root_);

  // Calibration.
  StereoRigCalibration& calib = data.calibration_;
  for (int i = 0; i < 2; ++i) {
    const std::string name = "cam" + std::to_string(i);
    requireDir(mav0 / name);
    calib.camera(i) = SensorYaml::readCamera(requireFile(mav0 / name / "sensor.yaml"), name);
  }
  requireDir(mav0 / "imu0");
  calib.imu = SensorYaml::readImu(requireFile(mav0 / "imu0" / "sensor.yaml"), "imu0");

  // Stereo frames.
  const std::vector<CameraRow> cam0 = readCameraRows(mav0 / "cam0", options, &data.warnings_);
  const std::vector<CameraRow> cam1 = readCameraRows(mav0 / "cam1", options, &data.warnings_);
  std::size_t i = 0, j = 0;
  auto unpaired = [&](const char* camera, const char* other, Timestamp t) {
    data.warnings_.push_back((mav0 / camera / "data.csv").string() + ": frame " +
                             std::to_string(t) + " has no " + other +
                             " image at the same time; skipped");
  };
  while (i < cam0.size() || j < cam1.size()) {
    if (j == cam1.size()) {
      unpaired("cam0", "cam1", cam0[i++].t);
    } else if (i == cam0.size()) {
      unpaired("cam1", "cam0", cam1[j++].t);
    } else if (std::llabs(cam1[j].t - cam0[i].t) <= options.max_stereo_offset_ns) {
      data.frames_.push_back({cam0[i].t, cam1[j].t, cam0[i].path, cam1[j].path});
      ++i;
      ++j;
    } else if (cam0[i].t < cam1[j].t) {
      unpaired("cam0", "cam1", cam0[i++].t);
    } else {
      unpaired("cam1", "cam0", cam1[j++].t);
    }
  }
  if (data.frames_.empty()) {
    throw InputError(data.root_ +
                     ": no stereo pairs (cam0 and cam1 share no timestamp with images)");
  }
  if (options.check_image_size) {
    for (int cam = 0; cam < 2; ++cam) {
      const std::string& path = data.frames_.front().path(cam);
      int w = 0, h = 0;
      const CameraCalibration& c = calib.camera(cam);
      if (readPngSize(path, &w, &h) && (w != c.model.width() || h != c.model.height())) {
        throw InputError(sizeMismatch(path, w, h, c, (mav0 / c.name / "sensor.yaml").string()));
      }
    }
  }

  // IMU.
  {
    CsvReader csv(requireFile(mav0 / "imu0" / "data.csv"));
    Timestamp last = 0;
    bool have_last = false;
    data.imu_.reserve(32768);
    forEachRow(csv, options, &data.warnings_, [&](CsvReader& row) {
      row.expectFieldCount(7, "IMU");
      ImuSample s;
      s.t = row.int64At(0, "timestamp");
      s.gyro = {row.doubleAt(1, "w_RS_S_x"), row.doubleAt(2, "w_RS_S_y"),
                row.doubleAt(3, "w_RS_S_z")};
      s.accel = {row.doubleAt(4, "a_RS_S_x"), row.doubleAt(5, "a_RS_S_y"),
                 row.doubleAt(6, "a_RS_S_z")};
      checkIncreasing(row, s.t, &last, &have_last);
      data.imu_.push_back(s);
    });
    if (data.imu_.empty()) throw InputError(csv.path() + ": contains no IMU samples");
  }

  // Ground truth (optional).
  const fs::path gt_dir = mav0 / "state_groundtruth_estimate0";
  if (fs::is_directory(gt_dir, ec)) {
    if (!fs::is_regular_file(gt_dir / "data.csv", ec)) {
      data.warnings_.push_back((gt_dir / "data.csv").string() + ": missing file; no ground truth");
    } else {
      CsvReader csv((gt_dir / "data.csv").string());
      Timestamp last = 0;
      bool have_last = false;
      forEachRow(csv, options, &data.warnings_, [&](CsvReader& row) {
        row.expectFieldCount(17, "ground-truth");
        GroundTruthState s;
        s.t = row.int64At(0, "timestamp");
        s.p_WB = {row.doubleAt(1, "p_x"), row.doubleAt(2, "p_y"), row.doubleAt(3, "p_z")};
        s.q_WB = Eigen::Quaterniond(row.doubleAt(4, "q_w"), row.doubleAt(5, "q_x"),
                                    row.doubleAt(6, "q_y"), row.doubleAt(7, "q_z"));
        const double norm = s.q_WB.norm();
        if (std::abs(norm - 1.0) > 1e-3) {
          row.fail("quaternion (q_w, q_x, q_y, q_z) has norm " + std::to_string(norm) +
                   ", expected 1");
        }
        // Leave unit quaternions bit-exact so write-then-read is lossless.
        if (std::abs(norm - 1.0) > 1e-12) s.q_WB.normalize();
        s.v_WB = {row.doubleAt(8, "v_x"), row.doubleAt(9, "v_y"), row.doubleAt(10, "v_z")};
        s.bias_gyro = {row.doubleAt(11, "bw_x"), row.doubleAt(12, "bw_y"),
                       row.doubleAt(13, "bw_z")};
        s.bias_accel = {row.doubleAt(14, "ba_x"), row.doubleAt(15, "ba_y"),
                        row.doubleAt(16, "ba_z")};
        checkIncreasing(row, s.t, &last, &have_last);
        data.ground_truth_.push_back(s);
      });
    }
  }

  // Conflict labels (optional).
  const fs::path labels_path = mav0 / "conflict_labels.csv";
  if (fs::exists(labels_path, ec)) {
    CsvReader csv(labels_path.string());
    Timestamp last = 0;
    bool have_last = false;
    forEachRow(csv, options, &data.warnings_, [&](CsvReader& row) {
      row.expectFieldCount(4, "conflict label");
      ConflictLabel label;
      label.t = row.int64At(0, "timestamp");
      const std::int64_t flag = row.int64At(1, "in_conflict");
      if (flag != 0 && flag != 1)
        row.fail("column 'in_conflict' must be 0 or 1, got " + std::to_string(flag));
      label.in_conflict = flag == 1;
      label.motion = std::string(row.field(2));
      if (label.motion.empty()) row.fail("column 'motion' is empty");
      label.covered_fraction = row.doubleAt(3, "covered_fraction");
      if (label.covered_fraction < 0.0 || label.covered_fraction > 1.0) {
        row.fail("column 'covered_fraction' must be in [0, 1], got " + std::string(row.field(3)));
      }
      checkIncreasing(row, label.t, &last, &have_last);
      data.labels_.push_back(std::move(label));
    });
  }
  return data;
}

cv::Mat EurocDataset::loadImage(const StereoFrame& frame, int camera) const {
  return loadImage(frame.path(camera), camera);
}

cv::Mat EurocDataset::loadImage(const std::string& path, int camera) const {
  cv::Mat image;
  try {
    image = cv::imread(path, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot decode image: " + e.what());
  }
  if (image.empty()) throw InputError(path + ": cannot read or decode image (missing or corrupt)");
  const CameraCalibration& c = calibration_.camera(camera);
  if (image.cols != c.model.width() || image.rows != c.model.height()) {
    throw InputError(sizeMismatch(path, image.cols, image.rows, c,
                                  (fs::path(root_) / c.name / "sensor.yaml").string()));
  }
  return image;
}

}  // namespace mcvio::dataset
