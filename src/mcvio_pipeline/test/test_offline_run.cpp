#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <thread>
#include <unistd.h>

#include "clean_sequences.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/pipeline/bounded_queue.hpp"
#include "mcvio/pipeline/offline_run.hpp"
#include "mcvio/sim/simulator.hpp"
#include "../src/revisable_tum_file.hpp"

using namespace mcvio;

namespace {

std::string excerpt() {
  const char* shared = std::getenv("MCVIO_SHARED_DIR");
  const std::string dir = std::string(shared ? shared : "") + "/data/euroc_V1_01_excerpt";
  return std::filesystem::exists(dir + "/mav0") ? dir : "";
}

std::vector<std::array<double, 8>> readTum(const std::string& path) {
  std::vector<std::array<double, 8>> rows;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::array<double, 8> r{};
    for (auto& x : r) s >> x;
    rows.push_back(r);
  }
  return rows;
}

}  // namespace

TEST(OfflineRun, RealExcerptStandingStillStaysPutAndIsRepeatable) {
  const auto dir = excerpt();
  if (dir.empty()) GTEST_SKIP() << "no ../shared/data/euroc_V1_01_excerpt";
  const std::string out = ::testing::TempDir() + "/run_" + std::to_string(getpid());
  pipeline::OfflineRunOptions o;
  o.dataset_dir = dir;
  o.progress = false;
  o.output_dir = out + "_a";
  const auto a = pipeline::runOffline(o);
  o.output_dir = out + "_b";
  pipeline::runOffline(o);
  EXPECT_EQ(a.frames, 95u);
  EXPECT_EQ(a.skipped, 0u);
  EXPECT_EQ(a.resets, 0u);
  const auto ta = readTum(out + "_a/trajectory.tum"), tb = readTum(out + "_b/trajectory.tum");
  ASSERT_GT(ta.size(), 70u);  // initialisation takes ~1 s of IMU history (20 frames)
  ASSERT_EQ(ta.size(), tb.size());
  for (std::size_t i = 0; i < ta.size(); ++i) {
    for (int k = 0; k < 8; ++k) {
      ASSERT_TRUE(std::isfinite(ta[i][k]));
      EXPECT_NEAR(ta[i][k], tb[i][k], 1e-6) << "row " << i;
    }
    // The device stands still (ground truth moves < 2 mm): the estimate must not drift.
    const double d = std::hypot(ta[i][1] - ta[0][1], ta[i][2] - ta[0][2], ta[i][3] - ta[0][3]);
    EXPECT_LT(d, 0.02) << "row " << i;
  }
  std::ifstream stats(out + "_a/stats.json");
  std::stringstream ss;
  ss << stats.rdbuf();
  EXPECT_NE(ss.str().find("\"cpu_ms_per_frame\""), std::string::npos);
  EXPECT_NE(ss.str().find("\"keyframes\""), std::string::npos);
  std::filesystem::remove_all(out + "_a");
  std::filesystem::remove_all(out + "_b");
}

TEST(OfflineRun, MissingDatasetOrImuIsAClearError) {
  pipeline::OfflineRunOptions o;
  o.dataset_dir = "/nonexistent/dataset";
  o.output_dir = ::testing::TempDir() + "/run_missing";
  o.progress = false;
  try {
    pipeline::runOffline(o);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dataset"), std::string::npos) << e.what();
  }
}

namespace {

// A short rendered sequence (moving from the first frame) with its images decoded once, so
// several runs see the same input without rendering it again.
struct CachedSequence {
  pipeline::OfflineInput input;
  std::vector<std::pair<cv::Mat, cv::Mat>> images;
};

const CachedSequence& shortRenderedSequence() {
  static const CachedSequence seq = [] {
    CachedSequence s;
    auto options = pipeline::sequences::renderedNone(6.0, 3);
    options.start_time_ns = 1403715273262142976;  // a EuRoC stamp: not a whole number of microseconds
    const sim::Simulator simulator(options);
    s.input = pipeline::sequences::renderedInput(simulator);
    for (std::size_t i = 0; i < s.input.frame_times.size(); ++i) s.images.push_back(s.input.images(i));
    return s;
  }();
  return seq;
}

pipeline::OfflineInput cachedInput(const CachedSequence& seq) {
  pipeline::OfflineInput in = seq.input;
  in.images = [&seq](std::size_t i) { return seq.images[i]; };
  return in;
}

bool sameFeatures(const FeatureFrame& a, const FeatureFrame& b, std::string* why) {
  if (a.t != b.t || a.features.size() != b.features.size()) {
    *why = "time or count differs: " + std::to_string(a.features.size()) + " vs " + std::to_string(b.features.size());
    return false;
  }
  for (std::size_t k = 0; k < a.features.size(); ++k) {
    const auto &x = a.features[k], &y = b.features[k];
    // Bit-exact: the same computation in the same order must give the same doubles.
    if (x.track_id != y.track_id || x.camera_index != y.camera_index || x.label != y.label ||
        x.pixel != y.pixel || x.normalized != y.normalized) {
      *why = "feature " + std::to_string(k) + " (track " + std::to_string(x.track_id) + ") differs";
      return false;
    }
  }
  return true;
}

}  // namespace

// The two-stage use (frontend and estimator on their own threads) must hand the estimator the
// very same IMU samples and feature frames as the one-thread use.
TEST(VioPipeline, TwoThreadStagesFeedTheEstimatorTheSameInputAsOneThread) {
  const auto& seq = shortRenderedSequence();
  const auto& in = seq.input;
  const std::size_t n = in.frame_times.size();
  ASSERT_GE(n, 100u);

  std::vector<pipeline::VioFrameResult> sequential;
  {
    pipeline::VioPipeline vio(in.calibration, {});
    std::size_t next = 0;
    for (std::size_t i = 0; i < n; ++i) {
      while (next < in.imu.size() && in.imu[next].t <= in.frame_times[i]) vio.addImu(in.imu[next++]);
      sequential.push_back(vio.addFrame(in.frame_times[i], seq.images[i].first, seq.images[i].second));
    }
  }
  std::vector<pipeline::VioFrameResult> staged(n);
  std::vector<std::vector<ImuSample>> staged_imu(n);
  {
    pipeline::VioPipeline vio(in.calibration, {});
    pipeline::BoundedQueue<pipeline::TrackedFrame> queue(2);
    std::thread estimator([&] {
      while (auto f = queue.pop()) {
        const auto i = f->index;
        staged_imu[i] = f->imu;
        staged[i] = vio.estimateFrame(std::move(*f));
      }
    });
    std::size_t next = 0;
    for (std::size_t i = 0; i < n; ++i) {
      std::vector<ImuSample> imu;
      while (next < in.imu.size() && in.imu[next].t <= in.frame_times[i]) imu.push_back(in.imu[next++]);
      queue.push(vio.trackFrame(in.frame_times[i], seq.images[i].first, seq.images[i].second, std::move(imu)));
    }
    queue.close();
    estimator.join();
  }
  std::size_t tracking = 0, imu_total = 0;
  for (std::size_t i = 0; i < n; ++i) {
    imu_total += staged_imu[i].size();
    ASSERT_EQ(sequential[i].estimated, staged[i].estimated) << "frame " << i;
    std::string why;
    ASSERT_TRUE(sameFeatures(sequential[i].tracking.features, staged[i].tracking.features, &why)) << "frame " << i << ": " << why;
    const auto &a = sequential[i].estimate, &b = staged[i].estimate;
    ASSERT_EQ(a.status, b.status) << "frame " << i;
    tracking += a.status == estimator::EstimatorStatus::kTracking;
    // The estimator is bit-reproducible (its blocks live in its own pools, see
    // ParameterBlockPool); the tolerance dates from before and only leaves a margin.
    EXPECT_LT((a.p_WB - b.p_WB).norm(), 1e-7) << "frame " << i;
    EXPECT_LT((a.bias.gyro - b.bias.gyro).norm(), 1e-9) << "frame " << i;
  }
  // Every IMU sample up to the last frame went through the stages, once.
  std::size_t up_to_last = 0;
  while (up_to_last < in.imu.size() && in.imu[up_to_last].t <= in.frame_times.back()) ++up_to_last;
  EXPECT_EQ(imu_total, up_to_last);
  EXPECT_GT(tracking, n / 2);
}

TEST(OfflineRun, PipelinedRunWritesTheSequentialTrajectory) {
  const auto& seq = shortRenderedSequence();
  const std::string out = ::testing::TempDir() + "/pipelined_" + std::to_string(getpid());
  pipeline::OfflineRunOptions o;
  o.progress = false;
  o.dataset_dir = "rendered none 6 s";
  o.output_dir = out + "_seq";
  o.pipelined = false;
  const auto a = pipeline::runOffline(cachedInput(seq), o);
  o.output_dir = out + "_pipe";
  o.pipelined = true;
  const auto b = pipeline::runOffline(cachedInput(seq), o);
  EXPECT_EQ(a.frames, b.frames);
  EXPECT_EQ(a.estimated, b.estimated);
  EXPECT_EQ(a.resets, b.resets);
  EXPECT_GT(a.estimated, a.frames / 2);
  EXPECT_GT(b.peak_rss_mb, 10.0);
  EXPECT_GT(b.cpu_seconds, 0.0);
  EXPECT_GT(b.backend_median_cpu_ms, 0.0);
  const auto ta = readTum(out + "_seq/trajectory.tum"), tb = readTum(out + "_pipe/trajectory.tum");
  ASSERT_EQ(ta.size(), a.estimated);
  ASSERT_EQ(ta.size(), tb.size());
  for (std::size_t i = 0; i < ta.size(); ++i)
    for (int k = 0; k < 8; ++k) ASSERT_NEAR(ta[i][k], tb[i][k], 1e-7) << "row " << i << " field " << k;
  // Times are written to the nanosecond, so poses match per-frame output by time.
  {
    std::ifstream tum(out + "_pipe/trajectory.tum");
    std::string line;
    std::size_t matched = 0;
    while (std::getline(tum, line)) {
      if (line.empty() || line[0] == '#') continue;
      const auto dot = line.find('.'), space = line.find(' ');
      ASSERT_EQ(space - dot, 10u) << line;
      const Timestamp t = std::stoll(line.substr(0, dot)) * 1000000000 + std::stoll(line.substr(dot + 1, 9));
      matched += std::count(seq.input.frame_times.begin(), seq.input.frame_times.end(), t) == 1;
    }
    EXPECT_EQ(matched, tb.size());
  }
  std::ifstream stats(out + "_pipe/stats.json");
  std::stringstream ss;
  ss << stats.rdbuf();
  for (const char* key : {"\"peak_rss_mb\"", "\"realtime_factor\"", "\"frames_per_second\"", "\"image_loading\"", "\"cpu_seconds\"", "\"load_average_1min\""})
    EXPECT_NE(ss.str().find(key), std::string::npos) << key;
  std::filesystem::remove_all(out + "_seq");
  std::filesystem::remove_all(out + "_pipe");
}

// A camera whose stamps run behind the IMU's clock (Kalibr's timeshift_cam_imu): with the shift in
// the calibration the run is the one of a camera stamped on the IMU's clock, to the byte.
TEST(OfflineRun, ACameraTimeShiftPutsTheFramesOnTheImusClock) {
  const auto& seq = shortRenderedSequence();
  const std::string out = ::testing::TempDir() + "/time_shift_" + std::to_string(getpid());
  pipeline::OfflineRunOptions o;
  o.progress = false;
  o.dataset_dir = "rendered none 6 s";
  o.output_dir = out + "_imu_clock";
  const auto a = pipeline::runOffline(cachedInput(seq), o);
  constexpr Timestamp kShift = 2345678;  // not a multiple of the 5 ms IMU period
  auto shifted = cachedInput(seq);
  for (auto& t : shifted.frame_times) t -= kShift;
  shifted.calibration.camera_time_offset_ns = kShift;
  o.output_dir = out + "_shifted";
  const auto b = pipeline::runOffline(shifted, o);
  EXPECT_EQ(a.estimated, b.estimated);
  EXPECT_GT(a.estimated, a.frames / 2);
  std::ifstream ta(out + "_imu_clock/trajectory.tum"), tb(out + "_shifted/trajectory.tum");
  std::stringstream sa, sb;
  sa << ta.rdbuf();
  sb << tb.rdbuf();
  EXPECT_FALSE(sa.str().empty());
  EXPECT_EQ(sa.str(), sb.str());
  // Without the shift the poses carry the camera's stamps and the IMU is cut elsewhere.
  shifted.calibration.camera_time_offset_ns = 0;
  o.output_dir = out + "_unshifted";
  pipeline::runOffline(shifted, o);
  std::ifstream tc(out + "_unshifted/trajectory.tum");
  std::stringstream sc;
  sc << tc.rdbuf();
  EXPECT_NE(sa.str(), sc.str());
  for (const char* d : {"_imu_clock", "_shifted", "_unshifted"}) std::filesystem::remove_all(out + d);
}

// A failing image source stops all stages and reaches the caller as the error it was.
TEST(OfflineRun, ImageErrorInThePipelineIsRethrown) {
  const auto& seq = shortRenderedSequence();
  auto in = cachedInput(seq);
  in.images = [&seq](std::size_t i) -> std::pair<cv::Mat, cv::Mat> {
    if (i == 40) throw InputError("frame 40: cannot decode image");
    return seq.images[i];
  };
  pipeline::OfflineRunOptions o;
  o.progress = false;
  o.output_dir = ::testing::TempDir() + "/pipelined_error_" + std::to_string(getpid());
  for (bool pipelined : {true, false}) {
    o.pipelined = pipelined;
    try {
      pipeline::runOffline(in, o);
      FAIL() << "no error, pipelined=" << pipelined;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("frame 40"), std::string::npos) << e.what();
    }
    // What was written stays, marked as an aborted run.
    std::ifstream stats(o.output_dir + "/stats.json");
    std::stringstream ss;
    ss << stats.rdbuf();
    EXPECT_NE(ss.str().find("\"completed\": false"), std::string::npos) << ss.str();
    EXPECT_NE(ss.str().find("frame 40: cannot decode image"), std::string::npos) << ss.str();
  }
  std::filesystem::remove_all(o.output_dir);
}

TEST(OfflineRun, StopRequestEndsTheRunAndKeepsWhatWasWritten) {
  const auto& seq = shortRenderedSequence();
  pipeline::OfflineRunOptions o;
  o.progress = false;
  o.output_dir = ::testing::TempDir() + "/interrupted_" + std::to_string(getpid());
  for (bool pipelined : {true, false}) {
    o.pipelined = pipelined;
    std::size_t polls = 0;
    o.stop_requested = [&polls] { return ++polls > 60; };  // stop before frame 60
    try {
      pipeline::runOffline(cachedInput(seq), o);
      FAIL() << "not interrupted, pipelined=" << pipelined;
    } catch (const pipeline::RunInterrupted& e) {
      EXPECT_NE(std::string(e.what()).find("before frame 60 of " + std::to_string(seq.input.frame_times.size())),
                std::string::npos)
          << e.what();
    }
    std::ifstream stats(o.output_dir + "/stats.json");
    std::stringstream ss;
    ss << stats.rdbuf();
    EXPECT_NE(ss.str().find("\"completed\": false"), std::string::npos) << ss.str();
    EXPECT_NE(ss.str().find("interrupted before frame 60"), std::string::npos) << ss.str();
    // The frames estimated before the stop are on disk (initialisation takes ~20 of them).
    const auto poses = readTum(o.output_dir + "/trajectory.tum");
    EXPECT_GT(poses.size(), 20u) << "pipelined=" << pipelined;
    EXPECT_LT(poses.size(), 61u) << "pipelined=" << pipelined;
  }
  std::filesystem::remove_all(o.output_dir);
}

// IMU that never reaches the frames: a clear error before the run, not an empty trajectory.
TEST(OfflineRun, ImuThatDoesNotOverlapTheFramesIsAClearError) {
  const auto& seq = shortRenderedSequence();
  auto in = cachedInput(seq);
  const Timestamp shift = in.frame_times.back() - in.imu.front().t + 1000000000;
  for (auto& s : in.imu) s.t += shift;
  pipeline::OfflineRunOptions o;
  o.dataset_dir = "rendered_6s";
  o.progress = false;
  o.output_dir = ::testing::TempDir() + "/imu_late_" + std::to_string(getpid());
  try {
    pipeline::runOffline(in, o);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rendered_6s: the IMU"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("does not overlap the camera frames"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(o.output_dir);
}

// A bag's IMU may carry a NaN sample: the frontend drops it, and the frame it would have closed
// still gets the next sample instead of being skipped for want of IMU.
TEST(OfflineRun, ANonFiniteImuSampleAtAFrameTimeCostsNoFrame) {
  const auto& seq = shortRenderedSequence();
  pipeline::OfflineRunOptions o;
  o.progress = false;
  o.output_dir = ::testing::TempDir() + "/imu_nan_" + std::to_string(getpid());
  const auto clean = pipeline::runOffline(cachedInput(seq), o);
  auto in = cachedInput(seq);
  const Timestamp t = in.frame_times[60];
  const auto it = std::lower_bound(in.imu.begin(), in.imu.end(), t, [](const ImuSample& s, Timestamp x) { return s.t < x; });
  ASSERT_NE(it, in.imu.end());
  it->gyro.x() = std::numeric_limits<double>::quiet_NaN();
  const auto s = pipeline::runOffline(in, o);
  EXPECT_EQ(s.skipped, clean.skipped);
  EXPECT_EQ(s.estimated, clean.estimated);
  EXPECT_EQ(s.resets, 0u);
  std::filesystem::remove_all(o.output_dir);
}

// A frame without an image is skipped, and the summary says why.
TEST(OfflineRun, SkippedFramesCarryTheirReason) {
  const auto& seq = shortRenderedSequence();
  auto in = cachedInput(seq);
  in.images = [&seq](std::size_t i) {
    auto images = seq.images[i];
    if (i == 50) images.first = cv::Mat();
    return images;
  };
  pipeline::OfflineRunOptions o;
  o.progress = false;
  o.output_dir = ::testing::TempDir() + "/skip_reason_" + std::to_string(getpid());
  const auto s = pipeline::runOffline(in, o);
  EXPECT_EQ(s.skipped, 1u);
  ASSERT_EQ(s.skip_reasons.size(), 1u);
  EXPECT_NE(s.skip_reasons[0].find("left image is missing"), std::string::npos) << s.skip_reasons[0];
  EXPECT_GT(s.estimated, 0u);
  std::filesystem::remove_all(o.output_dir);
}

// Real IMU stamps jitter around the camera's (EuRoC V1_01: a sample 64-128 ns after a frame). The
// run must hand the estimator the IMU through the frame time, or it skips such frames.
TEST(OfflineRun, ImuStampsJustAfterTheFramesStillGiveEveryPose) {
  const auto& seq = shortRenderedSequence();
  auto in = cachedInput(seq);
  for (auto& s : in.imu) s.t += 100;
  pipeline::OfflineRunOptions o;
  o.progress = false;
  o.output_dir = ::testing::TempDir() + "/imu_jitter_" + std::to_string(getpid());
  std::size_t accepted = 0, tracking = 0;
  o.on_frame = [&](std::size_t, const pipeline::VioFrameResult& r) {
    tracking += r.estimated && r.estimate.status == estimator::EstimatorStatus::kTracking;
    accepted += r.estimated && r.estimate.status == estimator::EstimatorStatus::kTracking && r.estimate.frame_accepted;
  };
  const auto s = pipeline::runOffline(in, o);
  EXPECT_EQ(s.resets, 0u);
  EXPECT_GT(tracking, s.frames / 2);
  EXPECT_EQ(accepted, tracking);
  EXPECT_EQ(s.estimated, accepted);
  std::filesystem::remove_all(o.output_dir);
}

TEST(RevisableTumFile, KeepsThePublishedPosesAndWritesTheRevisedOnes) {
  const auto dir = std::filesystem::temp_directory_path() / ("mcvio_revisable_tum_" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "secondary.tum").string();
  const Timestamp t0 = 1'403'715'273'262'142'976;  // EuRoC epoch: nine decimals must survive
  {
    pipeline::RevisableTumFile f(path, "the conflicting frame");
    for (int i = 0; i < 4; ++i) f.add(t0 + i * 50'000'000, Eigen::Vector3d(i, 0, 0), Eigen::Quaterniond::Identity());
    f.revise({{t0 + 50'000'000, Eigen::Vector3d(1, 2, 3), Eigen::Quaterniond::Identity()},
              {t0 + 7, Eigen::Vector3d(9, 9, 9), Eigen::Quaterniond::Identity()}});  // no such frame: ignored
    EXPECT_TRUE(f.revised());
    f.finish();
  }
  const auto final_rows = readTum(path);
  const auto online_rows = readTum((dir / "secondary_online.tum").string());
  ASSERT_EQ(final_rows.size(), 4u);
  ASSERT_EQ(online_rows.size(), 4u);
  EXPECT_DOUBLE_EQ(final_rows[1][2], 2.0);
  EXPECT_DOUBLE_EQ(online_rows[1][2], 0.0);
  EXPECT_DOUBLE_EQ(final_rows[2][1], online_rows[2][1]);
  std::ifstream in(path);
  std::string header, first;
  std::getline(in, header);
  std::getline(in, first);
  EXPECT_NE(header.find("as published per frame: secondary_online.tum"), std::string::npos) << header;
  EXPECT_EQ(first.rfind("1403715273.262142976 ", 0), 0u) << first;

  // Unrevised: one file, and a stale per-frame file from an earlier run into the folder goes.
  {
    pipeline::RevisableTumFile f(path, "the conflicting frame");
    f.add(t0, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity());
    f.finish();
  }
  EXPECT_EQ(readTum(path).size(), 1u);
  EXPECT_FALSE(std::filesystem::exists(dir / "secondary_online.tum"));
  EXPECT_THROW(pipeline::RevisableTumFile((dir / "missing" / "x.tum").string(), "x"), InputError);
  std::filesystem::remove_all(dir);
}
