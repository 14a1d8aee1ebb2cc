// Loading the real EuRoC V1_01 excerpt: calibration, frame list, 29k IMU rows, ground truth.
// Run: mcvio_dataset_benchmark (reads MCVIO_SHARED_DIR, default /work/shared).
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>

#include "mcvio/dataset/csv_reader.hpp"
#include "mcvio/dataset/euroc_dataset.hpp"

#include <opencv2/imgcodecs.hpp>

namespace {

std::string excerptDir() {
  const char* shared = std::getenv("MCVIO_SHARED_DIR");
  return std::string(shared ? shared : "/work/shared") + "/data/euroc_V1_01_excerpt";
}

void BM_OpenRealExcerpt(benchmark::State& state) {
  const std::string dir = excerptDir();
  std::size_t imu = 0;
  for (auto _ : state) {
    const auto data = mcvio::dataset::EurocDataset::open(dir);
    imu = data.imu().size();
    benchmark::DoNotOptimize(imu);
  }
  state.counters["imu_samples"] = static_cast<double>(imu);
}
BENCHMARK(BM_OpenRealExcerpt)->Unit(benchmark::kMillisecond);

// The IMU CSV alone: split and parse 29120 rows of 7 numbers.
void BM_ParseImuCsv(benchmark::State& state) {
  const std::string path = excerptDir() + "/mav0/imu0/data.csv";
  std::size_t rows = 0;
  for (auto _ : state) {
    mcvio::dataset::CsvReader csv(path);
    rows = 0;
    double sum = 0.0;
    while (csv.nextRow()) {
      sum += csv.doubleAt(1, "w_x") + static_cast<double>(csv.int64At(0, "t") & 1);
      for (std::size_t i = 2; i < 7; ++i) sum += csv.doubleAt(i, "v");
      ++rows;
    }
    benchmark::DoNotOptimize(sum);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * rows));
}
BENCHMARK(BM_ParseImuCsv)->Unit(benchmark::kMillisecond);

void BM_LoadImage(benchmark::State& state) {
  const auto data = mcvio::dataset::EurocDataset::open(excerptDir());
  std::size_t i = 0;
  for (auto _ : state) {
    const cv::Mat image = data.loadImage(data.stereoFrames()[i % data.stereoFrames().size()], 0);
    benchmark::DoNotOptimize(image.data);
    ++i;
  }
}
BENCHMARK(BM_LoadImage)->Unit(benchmark::kMillisecond);

// What loadImage cost before PngGrayDecoder: OpenCV's libpng path on the same files.
void BM_LoadImageOpenCv(benchmark::State& state) {
  const auto data = mcvio::dataset::EurocDataset::open(excerptDir());
  std::size_t i = 0;
  for (auto _ : state) {
    const cv::Mat image = cv::imread(data.stereoFrames()[i % data.stereoFrames().size()].path(0), cv::IMREAD_GRAYSCALE);
    benchmark::DoNotOptimize(image.data);
    ++i;
  }
}
BENCHMARK(BM_LoadImageOpenCv)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
