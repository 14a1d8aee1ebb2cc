#include "mcvio/dataset/euroc_dataset.hpp"
#include "mcvio/dataset/png_gray_decoder.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <unordered_map>
#include <unordered_set>

#include "folder_layout.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/csv_reader.hpp"
#include "mcvio/dataset/euroc_file_reader.hpp"
#include "mcvio/dataset/sensor_yaml.hpp"
#include "row_parsing.hpp"

namespace mcvio::dataset {

namespace fs = std::filesystem;
using detail::forEachRow;
using detail::IncreasingTime;
using detail::requireDir;
using detail::requireFile;
using detail::resolveMav0;

namespace {

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
  IncreasingTime time;
  std::unordered_map<std::string, std::string> used_by;  // image -> the row that named it first
  constexpr int kOddNamesToList = 5;
  int odd_names = 0;
  forEachRow(csv, options.skip_bad_rows, warnings, [&](CsvReader& row) {
    row.expectFieldCount(2, "camera");
    const Timestamp t = row.int64At(0, "timestamp");
    const std::string name(row.field(1));
    if (name.empty()) row.fail("column 'filename' is empty");
    time.check(row, t);
    const bool exists = name.find('/') == std::string::npos
                            ? files.count(name) > 0
                            : fs::is_regular_file(data_dir / name, ec);
    if (!exists) {
      warnings->push_back(row.location() + ": image data/" + name + " does not exist; frame " +
                          std::to_string(t) + " skipped");
      return;
    }
    // EuRoC names every image after its timestamp: a row naming another time's image (an edited
    // CSV, a shifted column) or an image already used plays a wrong or frozen frame.
    // (Ten digits or more: a time in s, us or ns; sequential numbering stays quiet.)
    const auto [first_use, unused] = used_by.emplace(name, row.location());
    const auto stem = fs::path(name).stem().string();
    std::string problem;
    if (!unused) {
      problem = " is already the image of " + first_use->second + "; frame " + std::to_string(t) + " repeats it";
    } else if (stem.size() >= 10 && stem.size() <= 19 && stem.find_first_not_of("0123456789") == std::string::npos &&
               stem != std::to_string(t)) {
      problem = " is named after another time than the row's " + std::to_string(t) + "; used as given";
    }
    if (!problem.empty() && ++odd_names <= kOddNamesToList) warnings->push_back(row.location() + ": image data/" + name + problem);
    rows.push_back({t, (data_dir / name).string()});
  });
  if (odd_names > kOddNamesToList)
    warnings->push_back(csv.path() + ": " + std::to_string(odd_names - kOddNamesToList) +
                        " more rows name an image of another time or one already used");
  return rows;
}

}  // namespace

EurocDataset EurocDataset::open(const std::string& dir, const EurocDatasetOptions& options) {
  if (options.max_stereo_offset_ns < 0) {
    throw InputError("dataset options: max_stereo_offset_ns must not be negative");
  }
  std::error_code ec;
  EurocDataset data;
  const fs::path mav0 = resolveMav0(dir);
  data.root_ = mav0.string();
  data.calibration_ = EurocFileReader::readCalibration(data.root_, &data.warnings_);
  const StereoRigCalibration& calib = data.calibration_;

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
      if (PngGrayDecoder::readSize(path, &w, &h) && (w != c.model.width() || h != c.model.height())) {
        throw InputError(sizeMismatch(path, w, h, c, (mav0 / c.name / "sensor.yaml").string()));
      }
    }
  }

  // IMU, ground truth (optional), conflict labels (optional).
  data.imu_ = EurocFileReader::readImu(requireFile(mav0 / "imu0" / "data.csv"),
                                       options.skip_bad_rows, &data.warnings_);
  const fs::path gt_dir = mav0 / "state_groundtruth_estimate0";
  if (fs::is_directory(gt_dir, ec)) {
    if (!fs::is_regular_file(gt_dir / "data.csv", ec)) {
      data.warnings_.push_back((gt_dir / "data.csv").string() + ": missing file; no ground truth");
    } else {
      data.ground_truth_ = EurocFileReader::readGroundTruth((gt_dir / "data.csv").string(),
                                                            options.skip_bad_rows, &data.warnings_);
    }
  }
  const fs::path labels_path = mav0 / "conflict_labels.csv";
  if (fs::exists(labels_path, ec)) {
    data.labels_ =
        EurocFileReader::readLabels(labels_path.string(), options.skip_bad_rows, &data.warnings_);
  }
  return data;
}

cv::Mat EurocDataset::loadImage(const StereoFrame& frame, int camera) const {
  return loadImage(frame.path(camera), camera);
}

cv::Mat EurocDataset::loadImage(const std::string& path, int camera) const {
  cv::Mat image;
  std::string error;
  if (!decode(path, camera, &image, &error)) throw InputError(error);
  checkSize(path, image.cols, image.rows, camera);
  return image;
}

bool EurocDataset::tryLoadImage(const StereoFrame& frame, int camera, cv::Mat* image, std::string* error) const {
  const std::string path = frame.path(camera);
  *image = cv::Mat();
  cv::Mat decoded;
  if (!decode(path, camera, &decoded, error)) return false;
  checkSize(path, decoded.cols, decoded.rows, camera);
  *image = decoded;
  return true;
}

bool EurocDataset::decode(const std::string& path, int camera, cv::Mat* image, std::string* error) const {
  // EuRoC's own 8-bit greyscale PNGs take the fast path (which caps the size it decodes);
  // anything else goes to OpenCV.
  PngGrayDecoder::Status status;
  try {
    status = PngGrayDecoder::decodeFile(path, image);
  } catch (const InputError& e) {  // PngGrayDecoder's errors name the file and the damage
    *error = e.what();
    return false;
  }
  try {
    if (status == PngGrayDecoder::Status::kUnsupported) {
      // OpenCV would decode whatever size the header claims before checkSize could refuse it.
      int width = 0, height = 0;
      if (PngGrayDecoder::readSize(path, &width, &height)) checkSize(path, width, height, camera);
      *image = cv::imread(path, cv::IMREAD_GRAYSCALE);
    }
  } catch (const cv::Exception& e) {
    *error = path + ": cannot decode image: " + e.what();
    return false;
  }
  if (image->empty()) {
    *error = path + ": cannot read or decode image (missing or corrupt)";
    return false;
  }
  return true;
}

void EurocDataset::checkSize(const std::string& path, int width, int height, int camera) const {
  const CameraCalibration& c = calibration_.camera(camera);
  if (width != c.model.width() || height != c.model.height()) {
    throw InputError(sizeMismatch(path, width, height, c,
                                  (fs::path(root_) / c.name / "sensor.yaml").string()));
  }
}

}  // namespace mcvio::dataset
