// Each kind of bad input: a clear mcvio::InputError naming the file (and line), or a warning
// naming it while the rest of the sequence still loads.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>
#include <zlib.h>

#include <algorithm>
#include <filesystem>

#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/euroc_dataset.hpp"
#include "test_sequence.hpp"

namespace mcvio::dataset {
namespace {

namespace fs = std::filesystem;
using test::readText;
using test::replaceLine;
using test::writeText;

constexpr int kFrames = 6;

class EurocBadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = test::freshDir(std::string("bad_") + info->name());
    seq_ = test::makeSequence(kFrames, 11);
    test::writeSequence(dir_, seq_);
    mav0_ = dir_ + "/mav0";
  }

  // Opens the data set expecting InputError; returns its message.
  std::string openError(const EurocDatasetOptions& options = {}) {
    try {
      EurocDataset::open(dir_, options);
    } catch (const InputError& e) {
      return e.what();
    }
    ADD_FAILURE() << "open() did not throw InputError";
    return "";
  }

  std::string imagePath(int camera, int frame) const {
    return mav0_ + "/cam" + std::to_string(camera) + "/data/" +
           std::to_string(seq_.frame_times[frame]) + ".png";
  }

  std::string dir_, mav0_;
  test::TestSequence seq_;
};

#define EXPECT_CONTAINS(text, part) \
  EXPECT_NE(std::string(text).find(part), std::string::npos) << "message: " << (text)

TEST_F(EurocBadInput, SequenceIsValidBeforeCorruption) {
  const EurocDataset data = EurocDataset::open(dir_);
  EXPECT_EQ(data.stereoFrames().size(), static_cast<std::size_t>(kFrames));
  EXPECT_TRUE(data.warnings().empty());
}

TEST_F(EurocBadInput, MissingFolder) {
  try {
    EurocDataset::open(dir_ + "/nowhere");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), dir_ + "/nowhere");
    EXPECT_CONTAINS(e.what(), "does not exist");
  }
  fs::remove_all(mav0_);
  EXPECT_CONTAINS(openError(), "not a EuRoC folder");
}

TEST_F(EurocBadInput, MissingCameraFolder) {
  fs::remove_all(mav0_ + "/cam1");
  const std::string message = openError();
  EXPECT_CONTAINS(message, mav0_ + "/cam1");
  EXPECT_CONTAINS(message, "missing folder");
}

TEST_F(EurocBadInput, MissingImuCsv) {
  fs::remove(mav0_ + "/imu0/data.csv");
  EXPECT_CONTAINS(openError(), mav0_ + "/imu0/data.csv");
}

TEST_F(EurocBadInput, ImuCsvIsAFolder) {
  fs::remove(mav0_ + "/imu0/data.csv");
  fs::create_directory(mav0_ + "/imu0/data.csv");
  EXPECT_CONTAINS(openError(), mav0_ + "/imu0/data.csv: is a folder, expected a file");
}

TEST_F(EurocBadInput, MissingCameraCsv) {
  fs::remove(mav0_ + "/cam0/data.csv");
  EXPECT_CONTAINS(openError(), mav0_ + "/cam0/data.csv");
}

TEST_F(EurocBadInput, MissingSensorYaml) {
  fs::remove(mav0_ + "/cam0/sensor.yaml");
  EXPECT_CONTAINS(openError(), mav0_ + "/cam0/sensor.yaml");
}

TEST_F(EurocBadInput, ImuRowWithWrongColumnCount) {
  replaceLine(mav0_ + "/imu0/data.csv", 3, "1403715273262142976,0.1,0.2");
  const std::string message = openError();
  EXPECT_CONTAINS(message, mav0_ + "/imu0/data.csv:3:");
  EXPECT_CONTAINS(message, "3 columns, expected 7");
}

TEST_F(EurocBadInput, ImuFieldNotANumber) {
  replaceLine(mav0_ + "/imu0/data.csv", 4, "1403715273277142969,0.1,abc,0.3,0.4,0.5,0.6");
  const std::string message = openError();
  EXPECT_CONTAINS(message, mav0_ + "/imu0/data.csv:4:");
  EXPECT_CONTAINS(message, "'abc' is not a number");
  EXPECT_CONTAINS(message, "w_RS_S_y");
}

TEST_F(EurocBadInput, ImuTimestampNotANumber) {
  replaceLine(mav0_ + "/imu0/data.csv", 2, "14037x5273262142976,0.1,0.2,0.3,0.4,0.5,0.6");
  EXPECT_CONTAINS(openError(), "imu0/data.csv:2: column 'timestamp'");
}

TEST_F(EurocBadInput, ImuTimeGoingBackwards) {
  replaceLine(mav0_ + "/imu0/data.csv", 5, "1403715273000000000,0.1,0.2,0.3,0.4,0.5,0.6");
  const std::string message = openError();
  EXPECT_CONTAINS(message, mav0_ + "/imu0/data.csv:5:");
  EXPECT_CONTAINS(message, "earlier than the previous row");
}

TEST_F(EurocBadInput, ImuDuplicateTimestamp) {
  const std::string t = std::to_string(seq_.imu[3].t);
  replaceLine(mav0_ + "/imu0/data.csv", 6, t + ",0.1,0.2,0.3,0.4,0.5,0.6");
  const std::string message = openError();
  EXPECT_CONTAINS(message, mav0_ + "/imu0/data.csv:6:");
  EXPECT_CONTAINS(message, "duplicate timestamp " + t);
}

TEST_F(EurocBadInput, ImuNaN) {
  replaceLine(mav0_ + "/imu0/data.csv", 7,
              std::to_string(seq_.imu[5].t) + ",0.1,0.2,nan,0.4,0.5,0.6");
  const std::string message = openError();
  EXPECT_CONTAINS(message, mav0_ + "/imu0/data.csv:7:");
  EXPECT_CONTAINS(message, "not finite");
}

TEST_F(EurocBadInput, ImuImplausibleMagnitude) {
  replaceLine(mav0_ + "/imu0/data.csv", 7, std::to_string(seq_.imu[5].t) + ",0.1,0.2,0.3,0.4,1e308,0.6");
  std::string message = openError();
  EXPECT_CONTAINS(message, mav0_ + "/imu0/data.csv:7:");
  EXPECT_CONTAINS(message, "acceleration 1e+308 m/s^2");  // not its 309 digits
  replaceLine(mav0_ + "/imu0/data.csv", 7, std::to_string(seq_.imu[5].t) + ",0.1,5729.6,0.3,0.4,0.5,0.6");
  message = openError();
  EXPECT_CONTAINS(message, "angular velocity");
  EXPECT_CONTAINS(message, "degrees instead of radians");
}

TEST_F(EurocBadInput, ImuTruncatedLastLine) {
  writeText(mav0_ + "/imu0/data.csv",
            readText(mav0_ + "/imu0/data.csv") + std::to_string(seq_.imu.back().t + 5) + ",0.1,0.");
  const int last_line = static_cast<int>(seq_.imu.size()) + 2;
  EXPECT_CONTAINS(openError(),
                  "imu0/data.csv:" + std::to_string(last_line) + ": IMU row has 3 columns");
}

TEST_F(EurocBadInput, ImuWithoutSamples) {
  writeText(mav0_ + "/imu0/data.csv", "#timestamp [ns],w_x,w_y,w_z,a_x,a_y,a_z\n");
  EXPECT_CONTAINS(openError(), mav0_ + "/imu0/data.csv: contains no IMU samples");
}

TEST_F(EurocBadInput, GroundTruthInfinite) {
  const std::string path = mav0_ + "/state_groundtruth_estimate0/data.csv";
  replaceLine(path, 2, std::to_string(seq_.frame_times[0]) + ",1,2,inf,1,0,0,0,0,0,0,0,0,0,0,0,0");
  const std::string message = openError();
  EXPECT_CONTAINS(message, path + ":2:");
  EXPECT_CONTAINS(message, "'p_z'");
}

TEST_F(EurocBadInput, GroundTruthQuaternionNotUnit) {
  const std::string path = mav0_ + "/state_groundtruth_estimate0/data.csv";
  replaceLine(path, 3, std::to_string(seq_.frame_times[1]) + ",1,2,3,2,0,0,0,0,0,0,0,0,0,0,0,0");
  EXPECT_CONTAINS(openError(), path + ":3: quaternion");
}

TEST_F(EurocBadInput, MissingGroundTruthFileIsAWarning) {
  fs::remove(mav0_ + "/state_groundtruth_estimate0/data.csv");
  const EurocDataset data = EurocDataset::open(dir_);
  EXPECT_TRUE(data.groundTruth().empty());
  ASSERT_EQ(data.warnings().size(), 1u);
  EXPECT_CONTAINS(data.warnings()[0], "state_groundtruth_estimate0/data.csv: missing file");
}

TEST_F(EurocBadInput, CameraCsvDuplicateTimestamp) {
  replaceLine(
      mav0_ + "/cam0/data.csv", 4,
      std::to_string(seq_.frame_times[1]) + "," + std::to_string(seq_.frame_times[2]) + ".png");
  const std::string message = openError();
  EXPECT_CONTAINS(message, mav0_ + "/cam0/data.csv:4:");
  EXPECT_CONTAINS(message, "duplicate timestamp");
}

TEST_F(EurocBadInput, CameraCsvMalformedRow) {
  replaceLine(mav0_ + "/cam1/data.csv", 2, "not_a_time,x.png");
  EXPECT_CONTAINS(openError(), mav0_ + "/cam1/data.csv:2: column 'timestamp'");
  replaceLine(mav0_ + "/cam1/data.csv", 2, std::to_string(seq_.frame_times[0]) + ",a.png,extra");
  EXPECT_CONTAINS(openError(), mav0_ + "/cam1/data.csv:2: camera row has 3 columns, expected 2");
}

TEST_F(EurocBadInput, SkipBadRowsKeepsTheRest) {
  replaceLine(mav0_ + "/imu0/data.csv", 3, "1403715273262142976,0.1,0.2");
  replaceLine(mav0_ + "/imu0/data.csv", 9, std::to_string(seq_.imu[7].t) + ",nan,0,0,0,0,0");
  replaceLine(mav0_ + "/cam1/data.csv", 3, "garbage,row");
  EurocDatasetOptions options;
  options.skip_bad_rows = true;
  const EurocDataset data = EurocDataset::open(dir_, options);
  EXPECT_EQ(data.imu().size(), seq_.imu.size() - 2);
  EXPECT_EQ(data.imu()[1].t, seq_.imu[2].t);  // row 3 (sample 1) is gone
  EXPECT_EQ(data.stereoFrames().size(), static_cast<std::size_t>(kFrames - 1));
  // Three skipped rows plus the cam0 frame that lost its partner.
  ASSERT_EQ(data.warnings().size(), 4u);
  EXPECT_CONTAINS(data.warnings()[0], mav0_ + "/cam1/data.csv:3:");
  EXPECT_CONTAINS(data.warnings()[1],
                  mav0_ + "/cam0/data.csv: frame " + std::to_string(seq_.frame_times[1]));
  EXPECT_CONTAINS(data.warnings()[2], mav0_ + "/imu0/data.csv:3:");
  EXPECT_CONTAINS(data.warnings()[2], "row skipped");
  EXPECT_CONTAINS(data.warnings()[3], mav0_ + "/imu0/data.csv:9:");
}

TEST_F(EurocBadInput, MissingImageSkipsTheFrameWithWarnings) {
  fs::remove(imagePath(0, 2));
  const EurocDataset data = EurocDataset::open(dir_);
  ASSERT_EQ(data.stereoFrames().size(), static_cast<std::size_t>(kFrames - 1));
  EXPECT_EQ(data.stereoFrames()[2].t, seq_.frame_times[3]);
  ASSERT_EQ(data.warnings().size(), 2u);
  EXPECT_CONTAINS(data.warnings()[0], mav0_ + "/cam0/data.csv:4: image data/" +
                                          std::to_string(seq_.frame_times[2]) +
                                          ".png does not exist");
  EXPECT_CONTAINS(data.warnings()[1], mav0_ + "/cam1/data.csv: frame " +
                                          std::to_string(seq_.frame_times[2]) +
                                          " has no cam0 image");
}

// Line 4 is frame 2; it names frame 3's image, which line 5 names again.
TEST_F(EurocBadInput, RowNamingAnotherFramesImageIsAWarning) {
  replaceLine(mav0_ + "/cam0/data.csv", 4,
              std::to_string(seq_.frame_times[2]) + "," + std::to_string(seq_.frame_times[3]) + ".png");
  const EurocDataset data = EurocDataset::open(dir_);
  EXPECT_EQ(data.stereoFrames().size(), static_cast<std::size_t>(kFrames));
  ASSERT_EQ(data.warnings().size(), 2u);
  EXPECT_CONTAINS(data.warnings()[0], mav0_ + "/cam0/data.csv:4: image data/" + std::to_string(seq_.frame_times[3]) +
                                          ".png is named after another time than the row's " +
                                          std::to_string(seq_.frame_times[2]));
  EXPECT_CONTAINS(data.warnings()[1], mav0_ + "/cam0/data.csv:5: image data/" + std::to_string(seq_.frame_times[3]) +
                                          ".png is already the image of " + mav0_ + "/cam0/data.csv:4");
}

// Sequentially numbered images (another tool's EuRoC export) are not timestamps: no warnings.
TEST_F(EurocBadInput, SequentiallyNumberedImagesAreAccepted) {
  for (int cam = 0; cam < 2; ++cam) {
    std::string csv = "#timestamp [ns],filename\n";
    for (int i = 0; i < kFrames; ++i) {
      char name[16];
      std::snprintf(name, sizeof(name), "%06d.png", i);
      fs::rename(imagePath(cam, i), mav0_ + "/cam" + std::to_string(cam) + "/data/" + name);
      csv += std::to_string(seq_.frame_times[i]) + "," + name + "\n";
    }
    writeText(mav0_ + "/cam" + std::to_string(cam) + "/data.csv", csv);
  }
  const EurocDataset data = EurocDataset::open(dir_);
  EXPECT_EQ(data.stereoFrames().size(), static_cast<std::size_t>(kFrames));
  EXPECT_TRUE(data.warnings().empty()) << data.warnings().front();
}

TEST_F(EurocBadInput, NoStereoPairsAtAll) {
  for (int i = 0; i < kFrames; ++i) fs::remove(imagePath(1, i));
  EXPECT_CONTAINS(openError(), "no stereo pairs");
}

TEST_F(EurocBadInput, UnreadablePng) {
  writeText(imagePath(1, 3), "this is not a PNG file");
  const EurocDataset data = EurocDataset::open(dir_);
  EXPECT_NO_THROW(data.loadImage(data.stereoFrames()[3], 0));
  try {
    data.loadImage(data.stereoFrames()[3], 1);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), imagePath(1, 3));
    EXPECT_CONTAINS(e.what(), "cannot read or decode");
  }
}

TEST_F(EurocBadInput, TruncatedPng) {
  const std::string png = readText(imagePath(0, 4));
  writeText(imagePath(0, 4), png.substr(0, png.size() / 3));
  const EurocDataset data = EurocDataset::open(dir_);
  try {
    data.loadImage(data.stereoFrames()[4], 0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), imagePath(0, 4));
  }
}

TEST_F(EurocBadInput, TryLoadImageSkipsADamagedFrameButNotAWrongSize) {
  const std::string png = readText(imagePath(0, 4));
  writeText(imagePath(0, 4), png.substr(0, png.size() / 3));
  writeText(imagePath(1, 2), "this is not a PNG file");
  const EurocDataset data = EurocDataset::open(dir_);
  cv::Mat image;
  std::string error;
  EXPECT_TRUE(data.tryLoadImage(data.stereoFrames()[1], 0, &image, &error));
  EXPECT_FALSE(image.empty());
  for (const auto& [frame, camera] : {std::pair{4, 0}, std::pair{2, 1}}) {
    EXPECT_FALSE(data.tryLoadImage(data.stereoFrames()[static_cast<std::size_t>(frame)], camera, &image, &error));
    EXPECT_TRUE(image.empty());
    EXPECT_CONTAINS(error, imagePath(camera, frame));
  }
  // A size sensor.yaml contradicts is the calibration's error: it still throws.
  const std::string yaml = mav0_ + "/cam0/sensor.yaml";
  std::string text = readText(yaml);
  text.replace(text.find("resolution: [64, 48]"), 20, "resolution: [640, 48]");
  writeText(yaml, text);
  EurocDatasetOptions options;
  options.check_image_size = false;
  const EurocDataset resized = EurocDataset::open(dir_, options);
  EXPECT_THROW(resized.tryLoadImage(resized.stereoFrames()[1], 0, &image, &error), InputError);
}

TEST_F(EurocBadInput, ImageSizeContradictsSensorYaml) {
  const std::string yaml = mav0_ + "/cam0/sensor.yaml";
  std::string text = readText(yaml);
  const std::size_t pos = text.find("resolution: [64, 48]");
  ASSERT_NE(pos, std::string::npos);
  text.replace(pos, 20, "resolution: [640, 48]");
  writeText(yaml, text);
  const std::string message = openError();
  EXPECT_CONTAINS(message, imagePath(0, 0));
  EXPECT_CONTAINS(message, "64x48");
  EXPECT_CONTAINS(message, yaml);
  // Without the check at open(), loadImage still refuses the image.
  EurocDatasetOptions options;
  options.check_image_size = false;
  const EurocDataset data = EurocDataset::open(dir_, options);
  try {
    data.loadImage(data.stereoFrames()[2], 0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), imagePath(0, 2));
    EXPECT_CONTAINS(e.what(), "resolution [640, 48]");
  }
}

TEST_F(EurocBadInput, AHugeImageIsRefusedByItsHeaderBeforeDecoding) {
  // A PNG header claiming 40000 x 30000 pixels (a photo dropped into cam0/data, or a forged
  // file): refused as the wrong size from its first bytes, not decoded (1.2 GB) and then refused.
  // A well-formed 8-bit greyscale IHDR (its CRC right), then a few bytes of nothing.
  const unsigned char ihdr[17] = {'I', 'H', 'D', 'R', 0, 0, 0x9c, 0x40, 0, 0, 0x75, 0x30, 8, 0, 0, 0, 0};
  const auto crc = static_cast<std::uint32_t>(crc32(0L, ihdr, sizeof(ihdr)));
  std::string forged = readText(imagePath(0, 3)).substr(0, 12) + std::string(reinterpret_cast<const char*>(ihdr), 17);
  for (int shift : {24, 16, 8, 0}) forged += static_cast<char>((crc >> shift) & 0xff);
  forged += std::string(64, '\0');
  writeText(imagePath(0, 3), forged);
  EurocDatasetOptions options;
  options.check_image_size = false;
  const EurocDataset data = EurocDataset::open(dir_, options);
  cv::Mat image;
  std::string error;
  try {
    data.tryLoadImage(data.stereoFrames()[3], 0, &image, &error);
    FAIL() << "tryLoadImage did not throw; error: " << error;
  } catch (const InputError& e) {
    EXPECT_CONTAINS(e.what(), imagePath(0, 3));
    EXPECT_CONTAINS(e.what(), "image is 40000x30000 but");
  }
  EXPECT_THROW(data.loadImage(data.stereoFrames()[3], 0), InputError);
}

TEST_F(EurocBadInput, AKeyMcvioDoesNotReadIsAWarningNamingFileAndLine) {
  const std::string yaml = mav0_ + "/cam1/sensor.yaml";
  writeText(yaml, readText(yaml) + "camera_modle: ds\n");
  const std::string imu_yaml = mav0_ + "/imu0/sensor.yaml";
  writeText(imu_yaml, readText(imu_yaml) + "resolution: [1, 1]\n");
  const EurocDataset data = EurocDataset::open(dir_);
  std::string all;
  for (const auto& w : data.warnings()) all += w + "\n";
  const std::string text = readText(yaml);
  const auto lines = std::count(text.begin(), text.end(), '\n');
  EXPECT_CONTAINS(all, yaml + ":" + std::to_string(lines) + ": key 'camera_modle' is not one mcvio reads from a camera's");
  EXPECT_CONTAINS(all, imu_yaml + ":");
  EXPECT_CONTAINS(all, "key 'resolution' is not one mcvio reads from an IMU's sensor.yaml; ignored");
  EXPECT_EQ(all.find("cam0/sensor.yaml"), std::string::npos) << all;
}

TEST_F(EurocBadInput, SensorYamlMissingKey) {
  const std::string yaml = mav0_ + "/cam1/sensor.yaml";
  std::string text = readText(yaml);
  const std::size_t begin = text.find("intrinsics:");
  text.erase(begin, text.find('\n', begin) - begin + 1);
  writeText(yaml, text);
  const std::string message = openError();
  EXPECT_CONTAINS(message, yaml);
  EXPECT_CONTAINS(message, "missing key 'intrinsics'");
}

TEST_F(EurocBadInput, SensorYamlWrongListLength) {
  const std::string yaml = mav0_ + "/cam0/sensor.yaml";
  std::string text = readText(yaml);
  const std::size_t begin = text.find("intrinsics:");
  text.replace(begin, text.find('\n', begin) - begin, "intrinsics: [1, 2, 3]");
  writeText(yaml, text);
  const std::string message = openError();
  EXPECT_CONTAINS(message, yaml + ":");
  EXPECT_CONTAINS(message, "key 'intrinsics' must have 4 values, got 3");
}

TEST_F(EurocBadInput, SensorYamlSyntaxError) {
  const std::string yaml = mav0_ + "/cam0/sensor.yaml";
  writeText(yaml, "%YAML:1.0\nsensor_type: camera\nintrinsics: [1, 2,\nrate_hz: 20\n  bad: : ]\n");
  const std::string message = openError();
  EXPECT_CONTAINS(message, yaml + ":");
  EXPECT_CONTAINS(message, "YAML syntax error");
}

TEST_F(EurocBadInput, SensorYamlUnknownDistortionModel) {
  const std::string yaml = mav0_ + "/cam0/sensor.yaml";
  std::string text = readText(yaml);
  const std::size_t pos = text.find("radial-tangential");
  text.replace(pos, 17, "omni");
  writeText(yaml, text);
  const std::string message = openError();
  EXPECT_CONTAINS(message, yaml);
  EXPECT_CONTAINS(message, "'distortion_model'");
  EXPECT_CONTAINS(message, "omni");
}

TEST_F(EurocBadInput, SensorYamlNonNumericValue) {
  const std::string yaml = mav0_ + "/imu0/sensor.yaml";
  std::string text = readText(yaml);
  const std::size_t begin = text.find("gyroscope_random_walk:");
  text.replace(begin, text.find('\n', begin) - begin, "gyroscope_random_walk: lots");
  writeText(yaml, text);
  const std::string message = openError();
  EXPECT_CONTAINS(message, yaml + ":");
  EXPECT_CONTAINS(message, "'gyroscope_random_walk' must be a number, got 'lots'");
}

TEST_F(EurocBadInput, SensorYamlTransformNotARotation) {
  const std::string yaml = mav0_ + "/cam1/sensor.yaml";
  std::string text = readText(yaml);
  const std::size_t begin = text.find("data: [") + 7;
  text.replace(begin, text.find(',', begin) - begin, "3.5");
  writeText(yaml, text);
  const std::string message = openError();
  EXPECT_CONTAINS(message, yaml);
  EXPECT_CONTAINS(message, "'T_BS.data'");
  EXPECT_CONTAINS(message, "not a rotation matrix");
}

TEST_F(EurocBadInput, ImuSensorYamlMissingNoiseKey) {
  const std::string yaml = mav0_ + "/imu0/sensor.yaml";
  std::string text = readText(yaml);
  const std::size_t begin = text.find("accelerometer_noise_density:");
  text.erase(begin, text.find('\n', begin) - begin + 1);
  writeText(yaml, text);
  EXPECT_CONTAINS(openError(), yaml + ": missing key 'accelerometer_noise_density'");
}

TEST_F(EurocBadInput, LabelWithBadValues) {
  const std::string path = mav0_ + "/conflict_labels.csv";
  replaceLine(path, 2, std::to_string(seq_.frame_times[0]) + ",2,elevator,0.5");
  EXPECT_CONTAINS(openError(), path + ":2: column 'in_conflict' must be 0 or 1");
  replaceLine(path, 2, std::to_string(seq_.frame_times[0]) + ",1,elevator,1.5");
  EXPECT_CONTAINS(openError(), path + ":2: column 'covered_fraction' must be in [0, 1]");
  replaceLine(path, 2, std::to_string(seq_.frame_times[0]) + ",1,,0.5");
  EXPECT_CONTAINS(openError(), path + ":2: column 'motion' is empty");
}

TEST(EurocDatasetOptions, FromYamlValidatesKeys) {
  const EurocDatasetOptions options = EurocDatasetOptions::fromYaml(
      YAML::Load("{skip_bad_rows: true, max_stereo_offset_ns: 1000}"));
  EXPECT_TRUE(options.skip_bad_rows);
  EXPECT_EQ(options.max_stereo_offset_ns, 1000);
  EXPECT_TRUE(options.check_image_size);
  auto error = [](const char* text) {
    try {
      EurocDatasetOptions::fromYaml(YAML::Load(text));
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_CONTAINS(error("{skip_bad_row: true}"), "unknown key 'skip_bad_row'");
  EXPECT_CONTAINS(error("{check_image_size: maybe}"), "'check_image_size'");
  EXPECT_CONTAINS(error("{max_stereo_offset_ns: -5}"),
                  "'max_stereo_offset_ns' must not be negative");
}

TEST_F(EurocBadInput, StereoOffsetTolerancePairsNearbyStamps) {
  // Shift every cam1 stamp by 3 ms (renaming the images too): exact pairing fails, 5 ms pairs.
  std::string csv = "#timestamp [ns],filename\n";
  for (int i = 0; i < kFrames; ++i) {
    const Timestamp t = seq_.frame_times[i] + 3'000'000;
    const std::string name = std::to_string(t) + ".png";
    fs::rename(imagePath(1, i), mav0_ + "/cam1/data/" + name);
    csv += std::to_string(t) + "," + name + "\n";
  }
  writeText(mav0_ + "/cam1/data.csv", csv);
  EXPECT_CONTAINS(openError(), "no stereo pairs");
  EurocDatasetOptions options;
  options.max_stereo_offset_ns = 5'000'000;
  const EurocDataset data = EurocDataset::open(dir_, options);
  ASSERT_EQ(data.stereoFrames().size(), static_cast<std::size_t>(kFrames));
  EXPECT_EQ(data.stereoFrames()[0].t_cam1 - data.stereoFrames()[0].t, 3'000'000);
  EXPECT_TRUE(data.warnings().empty());
}

}  // namespace
}  // namespace mcvio::dataset
