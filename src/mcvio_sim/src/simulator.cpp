#include "mcvio/sim/simulator.hpp"

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>

#include "mcvio/core/input_error.hpp"
#include "mcvio/dataset/euroc_writer.hpp"
#include "mcvio/sim/euroc_rig_defaults.hpp"
#include "mcvio/sim/imu_synthesizer.hpp"
#include "mcvio/sim/recorded_sequence_reader.hpp"
#include "mcvio/sim/sampled_trajectory.hpp"
#include "mcvio/sim/world_generator.hpp"

namespace mcvio::sim {
namespace {

std::uint64_t mixSeed(std::uint64_t a, std::uint64_t b) {
  std::uint64_t x = a * 0x9E3779B97F4A7C15ULL + b + 0x632BE59BD9B4E019ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

Eigen::Isometry3d toIsometry(const KinematicState& s) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = s.q_wb.toRotationMatrix();
  T.translation() = s.p_wb;
  return T;
}

}  // namespace

Simulator::Simulator(SimulatorOptions options) : options_(std::move(options)) {
  options_.validate();
  rig_ = eurocRigDefaults();
  rig_.imu.noise = options_.imu_noise;
  if (!options_.calibration_dir.empty()) {
    rig_ = RecordedSequenceReader::readCalibration(options_.calibration_dir, rig_.imu);
    if (!options_.semiReal()) rig_.imu.noise = options_.imu_noise;  // we synthesise with these
  }
  const Timestamp period = fromSeconds(1.0 / options_.camera_rate_hz);

  WorldGenerator::Inputs in;
  in.scenario = options_.scenario;
  in.seed = options_.seed;
  in.cam0 = rig_.cam0;
  in.texture_size = options_.texture_size;

  std::vector<ImuSample> real_imu;
  std::shared_ptr<SampledTrajectory> recorded;
  if (options_.semiReal()) {
    auto gt = RecordedSequenceReader::readGroundTruth(options_.groundtruth_csv);
    real_imu = RecordedSequenceReader::readImu(options_.imu_csv);
    recorded = std::make_shared<SampledTrajectory>(gt);
    in.start = std::max(gt.front().t, real_imu.front().t);
    in.end = std::min(gt.back().t, real_imu.back().t);
    if (in.end - in.start < 2 * period)
      throw InputError(options_.groundtruth_csv + " and " + options_.imu_csv +
                       ": ground truth and IMU overlap for less than two camera frames");
    if (fromSeconds(options_.scenario.onset_s + options_.scenario.duration_s) > in.end - in.start)
      throw InputError("option 'scenario.duration_s' makes the conflict end after the recording (" +
                       std::to_string(toSeconds(in.end - in.start)) + " s)");
    in.recorded = recorded;
  } else {
    in.start = options_.start_time_ns;
    in.end = options_.start_time_ns + fromSeconds(options_.duration_s);
  }
  world_ = WorldGenerator::generate(in);

  for (Timestamp t = in.start; t <= in.end; t += period) frame_times_.push_back(t);

  if (options_.semiReal()) {
    // Keep the real IMU; a ride adds its acceleration, seen in the body frame.
    for (const ImuSample& m : real_imu) {
      if (m.t < in.start || m.t > in.end) continue;
      ImuSample out = m;
      if (world_.device_rides) {
        const KinematicState s = recorded->evaluate(m.t);
        out.accel += s.q_wb.conjugate() * world_.device_ride.acceleration(m.t);
      }
      imu_.push_back(out);
    }
    for (const auto& g : recorded->samples()) {
      if (g.t < in.start || g.t > in.end) continue;
      dataset::GroundTruthState out = g;
      if (world_.device_rides) {
        out.p_WB += world_.device_ride.displacement(g.t);
        out.v_WB += world_.device_ride.velocity(g.t);
      }
      ground_truth_.push_back(out);
    }
  } else {
    ImuSynthesizer::Options io;
    io.noise = options_.imu_noise;
    io.add_noise = options_.imu_noise_enabled;
    io.initial_gyro_bias = options_.initial_gyro_bias;
    io.initial_accel_bias = options_.initial_accel_bias;
    io.seed = mixSeed(options_.seed, 1);
    ImuSequence seq = ImuSynthesizer(io).synthesize(*world_.trajectory, in.start, in.end);
    imu_ = std::move(seq.samples);
    ground_truth_ = std::move(seq.ground_truth);
  }
}

const CameraRenderer& Simulator::renderer(int camera) const {
  std::call_once(renderers_built_, [this] {
    for (int c = 0; c < 2; ++c)
      renderer_[c] = std::make_unique<CameraRenderer>(rig_.camera(c), options_.threads);
  });
  return *renderer_[camera];
}

Eigen::Isometry3d Simulator::bodyPose(Timestamp t) const {
  return toIsometry(world_.trajectory->evaluate(t));
}

dataset::ConflictLabel Simulator::labelFor(Timestamp t, const RenderResult& cam0) const {
  dataset::ConflictLabel label;
  label.t = t;
  long covered = 0;
  for (int b : world_.conflict_bodies)
    if (world_.scene.movingInWorld(b, t)) covered += cam0.body_pixels[static_cast<size_t>(b)];
  label.covered_fraction = static_cast<double>(covered) / (static_cast<double>(cam0.image.rows) * cam0.image.cols);
  label.in_conflict = covered > 0;
  label.motion = label.in_conflict ? world_.motion_name : "none";
  return label;
}

RenderResult Simulator::renderCamera(std::size_t index, int camera) const {
  const Timestamp t = frame_times_.at(index);
  const double s = toSeconds(t - frame_times_.front());
  const double w = 2.0 * M_PI / options_.gain_period_s;
  RenderSettings settings;
  // Slow exposure/gain drift shared by both cameras, as an auto-exposure would produce.
  settings.gain = 1.0 + options_.gain_drift * (0.7 * std::sin(w * s) + 0.3 * std::sin(2.7 * w * s + 1.0));
  settings.noise_sigma = options_.pixel_noise_sigma;
  settings.texture_filter = options_.texture_filter;
  settings.noise_seed = mixSeed(options_.seed, 2 * index + 100 + static_cast<std::uint64_t>(camera));
  RenderResult r;
  renderer(camera).render(world_.scene, t, bodyPose(t), settings, &r);
  return r;
}

StereoRender Simulator::renderFrame(std::size_t index) const {
  StereoRender out;
  out.t = frame_times_.at(index);
  RenderResult r0 = renderCamera(index, 0);
  RenderResult r1 = renderCamera(index, 1);
  out.label = labelFor(out.t, r0);
  out.cam0 = r0.image;
  out.cam1 = r1.image;
  out.cam0_body_ids = r0.body_ids;
  return out;
}

SimulationSummary Simulator::writeDataset(
    const std::function<void(std::size_t, std::size_t)>& progress) {
  using Clock = std::chrono::steady_clock;
  const auto t0 = Clock::now();
  if (options_.output_dir.empty()) throw InputError("option 'output_dir' is required to write a data set");
  dataset::EurocWriter::Options wo;
  wo.png_compression = options_.png_compression;
  wo.overwrite = options_.overwrite;
  dataset::EurocWriter writer(options_.output_dir, rig_, wo);
  for (const auto& m : imu_) writer.addImu(m);
  for (const auto& g : ground_truth_) writer.addGroundTruth(g);

  SimulationSummary summary;
  summary.imu_samples = imu_.size();
  summary.ground_truth_rows = ground_truth_.size();

  // Rendering on this thread, PNG encoding on a writer thread: the two overlap.
  std::mutex mutex;
  std::condition_variable cv;
  std::deque<StereoRender> queue;
  bool done = false;
  std::exception_ptr write_error;
  std::thread consumer([&] {
    std::size_t written = 0;
    for (;;) {
      StereoRender item;
      {
        std::unique_lock<std::mutex> lock(mutex);
        cv.wait(lock, [&] { return !queue.empty() || done; });
        if (queue.empty()) return;
        item = std::move(queue.front());
        queue.pop_front();
      }
      cv.notify_all();
      try {
        if (!write_error) {
          writer.addStereoFrame(item.t, item.cam0, item.cam1);
          writer.addLabel(item.label);
          ++written;
          if (progress) progress(written, frame_times_.size());
        }
      } catch (...) {
        {
          std::lock_guard<std::mutex> lock(mutex);
          write_error = std::current_exception();
        }
        cv.notify_all();
      }
    }
  });
  double render_seconds = 0;
  for (std::size_t k = 0; k < frame_times_.size(); ++k) {
    const auto r0 = Clock::now();
    StereoRender frame = renderFrame(k);
    render_seconds += std::chrono::duration<double>(Clock::now() - r0).count();
    if (frame.label.in_conflict) ++summary.conflict_frames;
    std::unique_lock<std::mutex> lock(mutex);
    cv.wait(lock, [&] { return queue.size() < 4 || write_error; });
    if (write_error) break;
    queue.push_back(std::move(frame));
    lock.unlock();
    cv.notify_all();
  }
  {
    std::lock_guard<std::mutex> lock(mutex);
    done = true;
  }
  cv.notify_all();
  consumer.join();
  if (write_error) std::rethrow_exception(write_error);
  writer.close();
  summary.frames = frame_times_.size();
  summary.render_seconds = render_seconds;
  summary.total_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  return summary;
}

SimulationSummary runSimulation(const SimulatorOptions& options,
                                const std::function<void(std::size_t, std::size_t)>& progress) {
  Simulator sim(options);
  return sim.writeDataset(progress);
}

}  // namespace mcvio::sim
