// Randomly damaged files must give a loaded data set or mcvio::InputError, never anything else.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/euroc_dataset.hpp"
#include "test_sequence.hpp"

namespace mcvio::dataset {
namespace {

namespace fs = std::filesystem;

// Overwrites, deletes or inserts a few random bytes (printable and control characters alike).
std::string damage(const std::string& text, std::mt19937& rng) {
  std::string out = text;
  std::uniform_int_distribution<int> edits(1, 4), kind(0, 2), byte(0, 255);
  const int n = edits(rng);
  for (int i = 0; i < n && !out.empty(); ++i) {
    std::uniform_int_distribution<std::size_t> pos(0, out.size() - 1);
    const std::size_t p = pos(rng);
    switch (kind(rng)) {
      case 0:
        out[p] = static_cast<char>(byte(rng));
        break;
      case 1:
        out.erase(p, std::uniform_int_distribution<std::size_t>(1, 20)(rng));
        break;
      default:
        out.insert(p, 1, static_cast<char>(byte(rng)));
    }
  }
  return out;
}

TEST(EurocCorruption, DamagedFilesGiveDataOrInputError) {
  const std::string dir = test::freshDir("corruption");
  test::writeSequence(dir, test::makeSequence(4, 21));
  const std::string mav0 = dir + "/mav0";
  const std::vector<std::string> files = {mav0 + "/imu0/data.csv",
                                          mav0 + "/cam0/data.csv",
                                          mav0 + "/cam1/data.csv",
                                          mav0 + "/state_groundtruth_estimate0/data.csv",
                                          mav0 + "/conflict_labels.csv",
                                          mav0 + "/cam0/sensor.yaml",
                                          mav0 + "/cam1/sensor.yaml",
                                          mav0 + "/imu0/sensor.yaml",
                                          mav0 + "/cam0/data/1403715273262142976.png"};
  std::mt19937 rng(1234);
  int errors = 0, loaded = 0;
  for (const std::string& file : files) {
    const std::string original = test::readText(file);
    for (int trial = 0; trial < 40; ++trial) {
      test::writeText(file, damage(original, rng));
      for (const bool skip : {false, true}) {
        EurocDatasetOptions options;
        options.skip_bad_rows = skip;
        try {
          const EurocDataset data = EurocDataset::open(dir, options);
          for (const StereoFrame& f : data.stereoFrames()) {
            try {
              data.loadImage(f, 0);
            } catch (const InputError&) {
              ++errors;
            }
          }
          ++loaded;
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find(mav0), std::string::npos) << e.what();
          ++errors;
        }
      }
    }
    test::writeText(file, original);
  }
  // Both outcomes occur, so the loop really exercised the error paths.
  EXPECT_GT(errors, 50);
  EXPECT_GT(loaded, 50);
}

}  // namespace
}  // namespace mcvio::dataset
