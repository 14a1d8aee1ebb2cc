// Raw write throughput of BagWriter with 1 MB messages against a plain sequential write (dd-like)
// of the same bytes to the same directory, in the same run.
//   bench_bag_write [--benchmark_filter=...]   (MCVIO_BENCH_DIR picks the disk; default /tmp)
#include <benchmark/benchmark.h>
#include <fcntl.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <stdexcept>
#include <vector>

#include "mcvio/bag/bag_writer.hpp"

namespace {

constexpr std::size_t kMessageSize = 1 << 20;
constexpr int kMessages = 64;  // 64 MiB per iteration

std::filesystem::path benchDir() {
  const char* env = std::getenv("MCVIO_BENCH_DIR");
  auto p =
      std::filesystem::path(env ? env : "/tmp") / ("mcvio_bag_bench_" + std::to_string(getpid()));
  std::filesystem::create_directories(p);
  return p;
}

/// kind 0: random bytes (incompressible); kind 1: a camera-like mono8 image (smooth
/// gradient + sensor noise), which compresses.
std::vector<std::vector<std::uint8_t>> payloads(int kind) {
  std::mt19937 rng(42);
  std::vector<std::vector<std::uint8_t>> out(4, std::vector<std::uint8_t>(kMessageSize));
  for (auto& p : out) {
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (kind == 0) {
        p[i] = static_cast<std::uint8_t>(rng());
      } else {
        const std::size_t x = i % 1024;
        const std::size_t y = i / 1024;
        p[i] = static_cast<std::uint8_t>((x / 4 + y / 8) % 200 + (rng() % 8));
      }
    }
  }
  return out;
}

void BM_PlainSequentialWrite(benchmark::State& state) {
  const bool sync = state.range(1) != 0;
  const auto data = payloads(static_cast<int>(state.range(0)));
  const auto dir = benchDir();
  for (auto _ : state) {
    const auto path = dir / "plain.bin";
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0) throw std::runtime_error("open");
    for (int i = 0; i < kMessages; ++i) {
      const auto& d = data[static_cast<std::size_t>(i) % data.size()];
      std::size_t done = 0;
      while (done < d.size()) {
        const ssize_t w = ::write(fd, d.data() + done, d.size() - done);
        if (w <= 0) throw std::runtime_error("write");
        done += static_cast<std::size_t>(w);
      }
    }
    if (sync) ::fsync(fd);
    ::close(fd);
    state.PauseTiming();
    std::filesystem::remove(path);
    state.ResumeTiming();
  }
  state.SetBytesProcessed(state.iterations() * kMessages * static_cast<std::int64_t>(kMessageSize));
  std::filesystem::remove_all(dir);
}

void BM_BagWriterMcap(benchmark::State& state) {
  const auto compression = static_cast<mcvio::bag::Compression>(state.range(0));
  const auto data = payloads(static_cast<int>(state.range(1)));
  const bool sync = state.range(2) != 0;
  const bool crc = state.range(3) != 0;
  const auto dir = benchDir();
  mcvio::bag::TopicInfo topic;
  topic.name = "/cam0/image_raw";
  topic.type = "std_msgs/msg/String";
  topic.message_definition = "string data\n";
  std::uint64_t bytes_on_disk = 0;
  for (auto _ : state) {
    const auto bag = dir / "bag";
    {
      mcvio::bag::BagWriterOptions o;
      o.compression = compression;
      o.fsync = false;
      o.crc = crc;
      mcvio::bag::BagWriter w(bag, o);
      const auto t = w.addTopic(topic);
      for (int i = 0; i < kMessages; ++i) {
        const auto& d = data[static_cast<std::size_t>(i) % data.size()];
        w.write(t, i * 50000000LL, i * 50000000LL, d.data(), d.size());
      }
      w.close();
    }
    if (sync) {
      const int fd = ::open((bag / "bag_0.mcap").c_str(), O_RDONLY);
      ::fsync(fd);
      ::close(fd);
    }
    state.PauseTiming();
    bytes_on_disk = std::filesystem::file_size(bag / "bag_0.mcap");
    std::filesystem::remove_all(bag);
    state.ResumeTiming();
  }
  state.SetBytesProcessed(state.iterations() * kMessages * static_cast<std::int64_t>(kMessageSize));
  state.counters["ratio"] =
      static_cast<double>(bytes_on_disk) / (static_cast<double>(kMessages) * kMessageSize);
  std::filesystem::remove_all(dir);
}

}  // namespace

// Args: payload kind (0 random, 1 image-like), fsync at end.
BENCHMARK(BM_PlainSequentialWrite)
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
// Args: compression (0 none, 1 zstd, 2 lz4), payload kind, fsync at end, CRCs on.
BENCHMARK(BM_BagWriterMcap)
    ->ArgsProduct({{0, 1, 2}, {0, 1}, {0, 1}, {1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_BagWriterMcap)
    ->ArgsProduct({{0}, {0}, {0, 1}, {0}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();
