#include "mcvio/pipeline/offline_run.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "mcvio/core/input_error.hpp"
#include "mcvio/core/progress_bar.hpp"
#include "mcvio/core/write_failure.hpp"
#include "mcvio/bag/bag_reader.hpp"
#include "mcvio/pipeline/bounded_queue.hpp"
#include "mcvio/dataset/euroc_dataset.hpp"
#include "mcvio/dataset/rig_calibration_reader.hpp"
#include "mcvio/dataset/sensor_image.hpp"
#include "mcvio/rosmsg/cdr_codec.hpp"
#include "revisable_tum_file.hpp"

namespace mcvio::pipeline {

const char* const kConflictCsvHeader =
    "timestamp_ns,state,propagated_chi2,propagated_threshold,landmarks_tested,landmarks_inconsistent,"
    "inconsistent_fraction,coherence,interval_start_ns,resolution_mode,interval_onset_ns,interval_end_ns,"
    "frontend_checked,frontend_inconsistent,accel_bias_drift,split_chi2,evidence_score\n";

namespace {

struct StageStats {
  std::vector<double> values;
  void add(double v) { values.push_back(v); }
  double median() const {
    if (values.empty()) return 0;
    auto v = values;
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
  }
  nlohmann::json summary() const {
    if (values.empty()) return nlohmann::json::object();
    auto v = values;
    std::sort(v.begin(), v.end());
    double sum = 0;
    for (double x : v) sum += x;
    return {{"median", v[v.size() / 2]}, {"p90", v[std::min(v.size() - 1, v.size() * 9 / 10)]},
            {"mean", sum / static_cast<double>(v.size())}, {"max", v.back()}};
  }
};

Timestamp stampOf(const rosmsg::MessageValue& msg) {
  const auto& stamp = msg["header"]["stamp"];
  return std::get<std::int64_t>(stamp["sec"].value) * 1000000000 +
         static_cast<Timestamp>(std::get<std::uint64_t>(stamp["nanosec"].value));
}

double number(const rosmsg::MessageValue& v) { return std::get<double>(v.value); }

constexpr const char* kFeaturesTopic = "/mcvio/features";

// A recorded mcvio_msgs/FeatureFrame as the backend component reads it (an unknown label is
// kUnknown).
FeatureFrame featureFrameOf(const rosmsg::MessageValue& msg, Timestamp t);

// The same, for a bag whose FeatureFrame definition differs from ours (another version): say so.
FeatureFrame checkedFeatureFrameOf(const rosmsg::MessageValue& msg, Timestamp t) {
  try {
    return featureFrameOf(msg, t);
  } catch (const std::bad_variant_access&) {
    throw std::runtime_error("a field has another type than in this version's mcvio_msgs/msg/FeatureFrame");
  } catch (const std::out_of_range& e) {
    throw std::runtime_error(std::string("not this version's mcvio_msgs/msg/FeatureFrame: ") + e.what());
  }
}

FeatureFrame featureFrameOf(const rosmsg::MessageValue& msg, Timestamp t) {
  FeatureFrame f;
  f.t = t;
  f.frame_index = static_cast<std::uint32_t>(std::get<std::uint64_t>(msg["frame_index"].value));
  const auto& features = std::get<rosmsg::MessageValue::Array>(msg["features"].value);
  f.features.reserve(features.size());
  for (const auto& m : features) {
    FeatureObservation o;
    o.track_id = std::get<std::uint64_t>(m["track_id"].value);
    o.camera_index = static_cast<std::uint8_t>(std::get<std::uint64_t>(m["camera_index"].value));
    o.pixel = {number(m["u"]), number(m["v"])};
    o.normalized = {number(m["x"]), number(m["y"])};
    const auto label = std::get<std::uint64_t>(m["label"].value);
    o.label = label <= 2 ? static_cast<TrackLabel>(label) : TrackLabel::kUnknown;
    f.features.push_back(o);
  }
  return f;
}

// The user's --remap rules plus, for a sensor they leave alone, the topic the calibration names
// (Kalibr's rostopic) when the bag holds it: OpenVINS reads its topics from there too.
TopicRemapping withCalibratedTopics(const OfflineRunOptions& options, const StereoRigCalibration& rig,
                                    std::vector<std::string>& notes) {
  TopicRemapping remapping = options.remapping;
  std::set<std::string> held;
  const bag::BagReader every_topic(options.dataset_dir);
  for (const auto& t : every_topic.topics()) held.insert(t.name);
  const std::pair<std::string, std::string> sensors[] = {
      {"/cam0/image_raw", rig.cam0.topic}, {"/cam1/image_raw", rig.cam1.topic}, {"/imu0", rig.imu.topic}};
  for (const auto& [topic, calibrated] : sensors) {
    bool user_rule = false;  // the user's rule wins, even TOPIC:=TOPIC
    for (const auto& r : options.remapping.rules()) user_rule |= r.from == topic;
    if (calibrated.empty() || calibrated == topic || user_rule) continue;
    if (!held.count(calibrated)) {
      notes.push_back("the calibration names " + calibrated + " for " + topic + " (rostopic), and the bag has no such topic: reading " + topic);
      continue;
    }
    remapping.add(topic, calibrated);
    notes.push_back("reading " + topic + " from " + calibrated + ", its rostopic in the calibration (--remap " + topic + ":=" +
                    topic + " keeps the default)");
  }
  return remapping;
}

OfflineInput readBag(const OfflineRunOptions& options) {
  if (options.calibration_dir.empty()) {
    throw InputError(options.dataset_dir + " is a bag: give --calib DIR (EuRoC sensor.yaml folder); "
                     "camera_info carries no stereo extrinsics");
  }
  OfflineInput in;
  std::vector<std::string> calibration_warnings;
  in.calibration = dataset::RigCalibrationReader::read(options.calibration_dir, &calibration_warnings);
  const TopicRemapping remapping = withCalibratedTopics(options, in.calibration, in.notes);
  // The bag's names for what the run reads (--remap /imu0:=/camera/imu).
  const std::string cam0 = remapping.resolve("/cam0/image_raw"), cam1 = remapping.resolve("/cam1/image_raw");
  const std::string imu = remapping.resolve("/imu0"), features = remapping.resolve(kFeaturesTopic);
  for (const auto& r : options.remapping.rules()) {
    if (r.from != "/cam0/image_raw" && r.from != "/cam1/image_raw" && r.from != "/imu0" && r.from != kFeaturesTopic)
      throw InputError("--remap " + r.from + ":=" + r.to + ": `mcvio run` reads /cam0/image_raw, /cam1/image_raw, /imu0 and " +
                       kFeaturesTopic + " from a bag; " + r.from + " is none of them");
  }
  if (cam0 == cam1) throw InputError("--remap: /cam0/image_raw and /cam1/image_raw are both " + cam0 + "; the left and right images need a topic each");
  bag::BagReaderOptions ro;
  ro.topics = {cam0, cam1, imu, features};
  bag::BagReader reader(options.dataset_dir, ro);
  // metadata.yaml disagreeing with the storage, an unknown sqlite3 schema version, a topic that
  // is not CDR: the run goes on, and says so like `mcvio play` does.
  in.warnings = reader.warnings();
  in.warnings.insert(in.warnings.begin(), calibration_warnings.begin(), calibration_warnings.end());
  std::map<std::string, std::unique_ptr<rosmsg::MessageDefinitionSet>> defs;
  for (const auto& t : reader.topics()) {
    std::string definition = t.message_definition;
    if (definition.empty()) {
      const auto known = options.known_message_definitions.find(t.type);
      if (known == options.known_message_definitions.end())
        throw InputError(options.dataset_dir + ": topic " + t.name + " (" + t.type + ") has no message definition in the bag, and " +
                         t.type + " is not a built-in type");
      definition = known->second;
      in.warnings.push_back(options.dataset_dir + ": topic " + t.name + " carries no message definition (a bag from before Iron?): "
                            "read with the built-in " + t.type);
    }
    defs[t.name] = std::make_unique<rosmsg::MessageDefinitionSet>(rosmsg::MessageDefinitionSet::parse(t.type, definition));
  }
  // Images and IMU run the whole pipeline; without images, the frontend's recorded output and
  // the IMU run the estimator alone.
  const bool from_features = !(defs.count(cam0) && defs.count(cam1)) && defs.count(features);
  const std::vector<std::string> needed =
      from_features ? std::vector<std::string>{features, imu} : std::vector<std::string>{cam0, cam1, imu};
  for (const auto& topic : needed) {
    if (defs.count(topic)) continue;
    std::string held;
    const bag::BagReader every_topic(options.dataset_dir);
    for (const auto& t : every_topic.topics()) held += (held.empty() ? "" : ", ") + t.name;
    throw InputError(options.dataset_dir + ": the bag has no " + topic + " (it holds " +
                     (held.empty() ? std::string("no topics") : held) + "); `mcvio run` needs " + cam0 + ", " + cam1 +
                     " and " + imu + ", or " + features + " and " + imu +
                     " to run the estimator alone (--remap /imu0:=TOPIC names another topic)");
  }
  // Images come raw (sensor_msgs/Image) or compressed (sensor_msgs/CompressedImage, jpeg or png).
  std::set<std::string> compressed;
  for (const auto& t : reader.topics()) {
    if ((t.name != cam0 && t.name != cam1) || from_features) continue;
    if (t.type == "sensor_msgs/msg/CompressedImage") compressed.insert(t.name);
    else if (t.type != "sensor_msgs/msg/Image")
      throw InputError(options.dataset_dir + ": topic " + t.name + " has type " + t.type +
                       ", not sensor_msgs/msg/Image or sensor_msgs/msg/CompressedImage");
  }
  if (from_features) {
    for (const auto& t : reader.topics())
      if (t.name == features && t.type != "mcvio_msgs/msg/FeatureFrame")
        throw InputError(options.dataset_dir + ": topic " + features + " has type " + t.type +
                         ", not mcvio_msgs/msg/FeatureFrame");
  }
  std::map<Timestamp, FeatureFrame> feature_frames;
  std::map<Timestamp, std::pair<cv::Mat, cv::Mat>> frames;
  std::map<std::string, Timestamp> last_stamp;  // per topic, in the bag's order
  bag::BagMessage m;
  while (reader.next(m)) {
    // Only the topics this run reads are decoded.
    if ((m.topic == features) != from_features && m.topic != imu) continue;
    try {
      const auto value = rosmsg::CdrCodec(*defs[m.topic]).decode(m.data);
      const Timestamp t = stampOf(value);
      const auto last = last_stamp.find(m.topic);
      if (last != last_stamp.end() && t <= last->second) {
        // Frames and IMU go by their header stamps; one that goes back is used in stamp order.
        in.warnings.push_back(reader.where(m) + ": header stamp " + std::to_string(t) + " ns is not after the previous " +
                              std::to_string(last->second) + " ns on this topic");
      }
      last_stamp[m.topic] = std::max(t, last == last_stamp.end() ? t : last->second);
      if (m.topic == imu) {
        ImuSample s;
        s.t = t;
        s.gyro = {number(value["angular_velocity"]["x"]), number(value["angular_velocity"]["y"]), number(value["angular_velocity"]["z"])};
        s.accel = {number(value["linear_acceleration"]["x"]), number(value["linear_acceleration"]["y"]), number(value["linear_acceleration"]["z"])};
        in.imu.push_back(s);
        continue;
      }
      if (m.topic == features) {
        if (feature_frames.count(t)) {
          in.warnings.push_back(reader.where(m) + ": a second feature frame with header stamp " + std::to_string(t) +
                                " ns; the first is kept, this one skipped");
          continue;
        }
        feature_frames.emplace(t, checkedFeatureFrameOf(value, t));
        continue;
      }
      const auto& bytes = std::get<rosmsg::MessageValue::Bytes>(value["data"].value);
      const auto field = [&](const char* name) { return static_cast<std::uint32_t>(std::get<std::uint64_t>(value[name].value)); };
      std::string why;
      cv::Mat grey = compressed.count(m.topic)
                         ? dataset::greyImageOfCompressed(std::get<std::string>(value["format"].value), bytes.data(),
                                                          bytes.size(), &why)
                         : dataset::greyImageOf({std::get<std::string>(value["encoding"].value), field("width"),
                                                 field("height"), field("step"), field("is_bigendian") != 0,
                                                 bytes.data(), bytes.size()},
                                                &why);
      if (grey.empty()) {
        in.warnings.push_back(reader.where(m) + ": " + why + "; skipped");
        continue;
      }
      cv::Mat& slot = m.topic == cam0 ? frames[t].first : frames[t].second;
      if (!slot.empty()) {
        in.warnings.push_back(reader.where(m) + ": a second image with header stamp " + std::to_string(t) +
                              " ns on this topic; the first is kept, this one skipped");
        continue;
      }
      slot = std::move(grey);
    } catch (const std::exception& e) {
      // Name the bag file, topic and time: a bare CDR error does not say which message.
      throw InputError(reader.where(m) + ": " + e.what());
    }
  }
  std::sort(in.imu.begin(), in.imu.end(), [](const ImuSample& a, const ImuSample& b) { return a.t < b.t; });
  if (from_features) {
    std::vector<FeatureFrame> list;
    for (auto& [t, f] : feature_frames) {
      in.frame_times.push_back(t);
      list.push_back(std::move(f));
    }
    auto shared = std::make_shared<std::vector<FeatureFrame>>(std::move(list));
    in.features = [shared](std::size_t i) { return (*shared)[i]; };
    return in;
  }
  std::vector<std::pair<cv::Mat, cv::Mat>> pairs;
  for (auto& [t, p] : frames) {
    if (p.first.empty() || p.second.empty()) {
      in.warnings.push_back("frame at " + std::to_string(t) + " has no " + (p.first.empty() ? "left" : "right") + " image, skipped");
      continue;
    }
    in.frame_times.push_back(t);
    pairs.push_back(std::move(p));
  }
  auto shared = std::make_shared<std::vector<std::pair<cv::Mat, cv::Mat>>>(std::move(pairs));
  in.images = [shared](std::size_t i) { return (*shared)[i]; };
  return in;
}

OfflineInput readEuroc(const OfflineRunOptions& options) {
  auto data = std::make_shared<dataset::EurocDataset>(dataset::EurocDataset::open(options.dataset_dir));
  OfflineInput in;
  in.warnings = data->warnings();
  in.calibration = options.calibration_dir.empty() ? data->calibration()
                                                   : dataset::RigCalibrationReader::read(options.calibration_dir, &in.warnings);
  in.imu = data->imu();
  for (const auto& f : data->stereoFrames()) in.frame_times.push_back(f.t);
  // One damaged image costs its frame (the frontend skips a frame without both images), not the
  // run; a size that differs from sensor.yaml still stops it.
  in.images = [data](std::size_t i) {
    const auto& f = data->stereoFrames()[i];
    std::pair<cv::Mat, cv::Mat> images;
    std::string error;
    for (int c = 0; c < 2; ++c) {
      if (!data->tryLoadImage(f, c, c == 0 ? &images.first : &images.second, &error))
        std::cerr << "\nmcvio run: warning: " << error << "; frame " << f.t << " skipped\n";
    }
    return images;
  };
  return in;
}

nlohmann::json stageSummaries(const std::map<std::string, StageStats>& stages) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [name, stats] : stages) j[name] = stats.summary();
  return j;
}

double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) * 1e3 + static_cast<double>(ts.tv_nsec) * 1e-6;
}

double processCpuSeconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  const auto sec = [](const timeval& t) { return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) * 1e-6; };
  return sec(u.ru_utime) + sec(u.ru_stime);
}

// The 1-minute load average (Linux), so wall-clock figures can be read against the machine's load;
// negative when unknown.
double loadAverage() {
  std::ifstream in("/proc/loadavg");
  double load = -1;
  in >> load;
  return in ? load : -1.0;
}

double peakRssMb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // Linux reports kB
}

/// The decoded images of one frame and what decoding cost.
struct LoadedFrame {
  std::size_t index = 0;
  std::pair<cv::Mat, cv::Mat> images;
  double cpu_ms = 0;
};

/// Takes each frame's result in frame order: writes the trajectory, keeps the statistics, draws
/// the progress bar.
class RunRecorder {
 public:
  RunRecorder(const std::string& tum_path, std::size_t frames, const OfflineRunOptions& options, double data_seconds)
      : tum_(tum_path, "pose of imu0 in world"),
        conflict_(options.output_dir + "/conflict.csv"),
        secondary_(options.output_dir + "/secondary.tum",
                   "the conflicting frame S in world, identity at the interval start"),
        bar_("run", frames, options.progress),
        on_frame_(options.on_frame),
        data_seconds_(data_seconds),
        frames_total_(frames) {
    if (!conflict_) throwCannotWrite(options.output_dir + "/conflict.csv", errno);
    conflict_ << kConflictCsvHeader;
  }

  void add(std::size_t i, const VioFrameResult& r, double load_cpu_ms) {
    if (on_frame_) on_frame_(i, r);
    ++summary.frames;
    loader_ms.add(load_cpu_ms);
    frontend_ms.add(r.tracking.stats.cpu_ms_total);
    if (!r.estimated) {
      ++summary.skipped;
      ++skip_reasons[r.tracking.message];
    } else {
      features.add(r.tracking.stats.tracked + r.tracking.stats.detected);
      new_tracks += r.tracking.stats.detected;
      reidentified_tracks += r.tracking.stats.reidentified;
      stereo.add(r.tracking.stats.stereo_matched);
      const auto& e = r.estimate;
      backend_ms.add(e.timings.cpu_total_ms);
      backend_stage_ms["preintegration"].add(e.timings.preintegration_ms);
      backend_stage_ms["setup"].add(e.timings.setup_ms);
      backend_stage_ms["solve"].add(e.timings.solve_ms);
      backend_stage_ms["marginalization"].add(e.timings.marginalization_ms);
      backend_stage_ms["covariance"].add(e.timings.covariance_ms);
      backend_stage_ms["total"].add(e.timings.total_ms);
      iterations.add(e.solver_iterations);
      if (e.status == estimator::EstimatorStatus::kReset) ++summary.resets;
      if (e.status == estimator::EstimatorStatus::kNotInitialized) {
        ++not_initialized;
      } else if (!e.frame_accepted) {
        if (summary.rejected++ == 0) summary.first_rejection = e.message;
      }
      keyframes += e.is_keyframe;
      zero_velocity += e.zero_velocity;
      landmarks.add(e.num_landmarks);
      if (e.status == estimator::EstimatorStatus::kTracking && e.frame_accepted) {
        ++summary.estimated;
        tum_.add(e.t, e.p_WB, e.q_WB);
        const auto& c = e.conflict;
        if (c.secondary_valid) secondary_.add(e.t, c.p_WS, c.q_WS);
        tum_.revise(e.revised_poses);
        secondary_.revise(e.revised_secondary);
        conflict_ << e.t << ',' << estimator::toString(c.state) << ',' << c.propagated_chi2 << ','
                  << c.propagated_threshold << ',' << c.landmarks_tested << ',' << c.landmarks_inconsistent << ','
                  << c.inconsistent_fraction << ',' << c.coherence << ',' << c.interval_start << ','
                  << c.resolution_mode << ',' << c.interval_onset << ',' << c.interval_end << ','
                  << c.frontend_checked << ',' << c.frontend_inconsistent << ',' << c.accel_bias_drift << ','
                  << c.split_chi2 << ',' << c.evidence_score << '\n';
        conflict_frames += c.state == estimator::ConflictReport::State::kConflict ? 1 : 0;
        backend_stage_ms["conflict"].add(e.timings.conflict_ms);
      }
    }
    if (i % 5 == 0 || i + 1 == frames_total_) {
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
      std::ostringstream detail;
      detail << summary.estimated << " poses, " << std::setprecision(2) << std::fixed
             << (wall > 0 ? data_seconds_ * static_cast<double>(i + 1) / static_cast<double>(frames_total_) / wall : 0.0)
             << "x real time";
      bar_.update(i + 1, detail.str());
    }
  }

  /// trajectory.tum and secondary.tum become the final estimates (see RevisableTumFile).
  void finish() {
    bar_.finish();
    tum_.finish();
    secondary_.finish();
  }

  OfflineRunSummary summary;
  StageStats loader_ms, frontend_ms, backend_ms, features, stereo, landmarks, iterations;
  long long new_tracks = 0, reidentified_tracks = 0;  ///< of the new ones, lost tracks recognised again
  std::map<std::string, StageStats> backend_stage_ms;  ///< wall time of the estimator's stages
  std::size_t keyframes = 0, zero_velocity = 0, not_initialized = 0, conflict_frames = 0;
  std::map<std::string, std::size_t> skip_reasons;

 private:
  RevisableTumFile tum_;
  std::ofstream conflict_;
  RevisableTumFile secondary_;
  ProgressBar bar_;
  std::function<void(std::size_t, const VioFrameResult&)> on_frame_;
  const std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
  double data_seconds_;
  std::size_t frames_total_;
};

/// The IMU samples after those of the previous frame, up to and including the first one at or
/// after the frame time t: the estimator interpolates the frame-time endpoint, so it needs the
/// IMU to reach t, as a live backend waits for it. (Real IMU stamps jitter around the camera's:
/// EuRoC V1_01 has samples 64-128 ns after a frame; stopping before t would skip those frames.)
/// A non-finite sample (a bag's IMU may carry one) is dropped by the frontend, so it does not count
/// as reaching t. t is on the IMU's clock: a camera stamp plus the rig's camera_time_offset_ns.
std::vector<ImuSample> imuThrough(const std::vector<ImuSample>& imu, Timestamp t, std::size_t* next) {
  std::vector<ImuSample> out;
  const auto reaches = [t](const ImuSample& s) { return s.t >= t && s.gyro.allFinite() && s.accel.allFinite(); };
  while (*next < imu.size() && (*next == 0 || !reaches(imu[*next - 1]))) out.push_back(imu[(*next)++]);
  return out;
}

void throwIfStopRequested(const std::function<bool()>& stop_requested, std::size_t frame, std::size_t frames) {
  if (stop_requested && stop_requested())
    throw RunInterrupted("interrupted before frame " + std::to_string(frame) + " of " + std::to_string(frames));
}

void runSequential(const OfflineInput& data, VioPipeline& vio, RunRecorder& rec,
                   const std::function<bool()>& stop_requested) {
  std::size_t next_imu = 0;
  for (std::size_t i = 0; i < data.frame_times.size(); ++i) {
    throwIfStopRequested(stop_requested, i, data.frame_times.size());
    const Timestamp t = data.frame_times[i];
    for (const auto& s : imuThrough(data.imu, t + data.calibration.camera_time_offset_ns, &next_imu)) vio.addImu(s);
    const double c0 = threadCpuMs();
    const auto images = data.images(i);
    const double load_ms = threadCpuMs() - c0;
    rec.add(i, vio.addFrame(t, images.first, images.second), load_ms);
  }
}

// The recorded frontend output straight to the estimator, on the calling thread.
void runOnFeatures(const OfflineInput& data, VioPipeline& vio, RunRecorder& rec,
                   const std::function<bool()>& stop_requested) {
  std::size_t next_imu = 0;
  for (std::size_t i = 0; i < data.frame_times.size(); ++i) {
    throwIfStopRequested(stop_requested, i, data.frame_times.size());
    TrackedFrame frame;
    frame.index = i;
    frame.imu = imuThrough(data.imu, data.frame_times[i], &next_imu);
    const double c0 = threadCpuMs();
    frame.tracking.features = data.features(i);
    const double load_ms = threadCpuMs() - c0;
    rec.add(i, vio.estimateFrame(std::move(frame)), load_ms);
  }
}

// Decoding on one thread, the frontend on the calling thread, the estimator on a third. The
// first error stops all three and is rethrown.
void runPipelined(const OfflineInput& data, VioPipeline& vio, RunRecorder& rec,
                  const std::function<bool()>& stop_requested) {
  const std::size_t n = data.frame_times.size();
  BoundedQueue<LoadedFrame> loaded(4);
  BoundedQueue<std::pair<TrackedFrame, double>> tracked(2);
  std::mutex error_mutex;
  std::exception_ptr error;
  const auto fail = [&] {
    {
      std::lock_guard<std::mutex> lock(error_mutex);
      if (!error) error = std::current_exception();
    }
    loaded.close();
    tracked.close();
    vio.cancel();
  };

  std::thread loader([&] {
    try {
      for (std::size_t i = 0; i < n; ++i) {
        throwIfStopRequested(stop_requested, i, n);
        LoadedFrame f;
        f.index = i;
        const double c0 = threadCpuMs();
        f.images = data.images(i);
        f.cpu_ms = threadCpuMs() - c0;
        if (!loaded.push(std::move(f))) return;
      }
      loaded.close();
    } catch (...) {
      fail();
    }
  });
  std::thread estimator([&] {
    try {
      while (auto item = tracked.pop()) {
        const std::size_t i = item->first.index;
        rec.add(i, vio.estimateFrame(std::move(item->first)), item->second);
      }
    } catch (...) {
      fail();
    }
  });
  try {
    std::size_t next_imu = 0;
    while (auto f = loaded.pop()) {
      const Timestamp t = data.frame_times[f->index];
      auto frame = vio.trackFrame(t, f->images.first, f->images.second,
                                  imuThrough(data.imu, t + data.calibration.camera_time_offset_ns, &next_imu));
      f->images = {};
      if (!tracked.push({std::move(frame), f->cpu_ms})) break;
    }
    tracked.close();
  } catch (...) {
    fail();
  }
  loader.join();
  estimator.join();
  if (error) std::rethrow_exception(error);
}

// Frames before the first IMU sample or after the last cannot be estimated: say so before the run
// rather than leave an empty trajectory.
void checkImuCoverage(const OfflineInput& data, const std::string& source) {
  const Timestamp imu0 = data.imu.front().t, imu1 = data.imu.back().t;
  const Timestamp f0 = data.frame_times.front(), f1 = data.frame_times.back();
  const auto range = [](Timestamp a, Timestamp b) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(3) << toSeconds(a) << " - " << toSeconds(b) << " s";
    return os.str();
  };
  if (imu1 < f0 || imu0 > f1) {
    throw InputError(source + ": the IMU (" + range(imu0, imu1) + ") does not overlap the camera frames (" + range(f0, f1) +
                     "): no frame can be estimated");
  }
  const auto before = std::lower_bound(data.frame_times.begin(), data.frame_times.end(), imu0) - data.frame_times.begin();
  const auto after = data.frame_times.end() - std::upper_bound(data.frame_times.begin(), data.frame_times.end(), imu1);
  // A camera starting a moment before its IMU is common and costs a frame or two; say it when a
  // second or more of frames is lost.
  if ((before > 0 && imu0 - f0 >= 1000000000) || (after > 0 && f1 - imu1 >= 1000000000)) {
    std::cerr << "mcvio run: warning: " << source << ": the IMU (" << range(imu0, imu1) << ") does not cover "
              << before << " camera frame(s) before it and " << after << " after it (frames " << range(f0, f1)
              << "); those cannot be estimated\n";
  }
}

// The output folder is made before the input is read (a bag is read whole first), so a bad --out
// is reported at once.
void makeOutputFolder(const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    throw InputError("output folder '" + dir + "': " + (ec ? "cannot create it (" + ec.message() + ")" : "exists and is not a folder"));
  }
}

}  // namespace

OfflineRunSummary runOffline(const OfflineRunOptions& options) {
  namespace fs = std::filesystem;
  makeOutputFolder(options.output_dir);
  const fs::path p(options.dataset_dir);
  const bool is_bag = bag::BagReader::looksLikeBag(p);
  if (!is_bag && !options.remapping.empty())
    throw InputError("--remap names a bag's topics; " + options.dataset_dir + " is a EuRoC folder (mav0/), not a bag");
  return runOffline(is_bag ? readBag(options) : readEuroc(options), options);
}

OfflineRunSummary runOffline(const OfflineInput& data, const OfflineRunOptions& options) {
  using Clock = std::chrono::steady_clock;
  namespace fs = std::filesystem;
  for (const auto& n : data.notes) std::cerr << "mcvio run: " << n << "\n";
  for (const auto& w : data.warnings) std::cerr << "mcvio run: warning: " << w << "\n";
  if (data.frame_times.empty()) throw InputError(options.dataset_dir + ": no stereo frames to run on");
  if (data.imu.empty()) throw InputError(options.dataset_dir + ": no IMU samples");
  if (!data.images && !data.features) throw InputError(options.dataset_dir + ": no image or feature source");
  checkImuCoverage(data, options.dataset_dir);
  auto vio_options =
      options.config_file.empty() ? VioPipelineOptions::shipped() : VioPipelineOptions::fromYamlFile(options.config_file);
  if (!options.mode.empty())
    vio_options.estimator.conflict.mode = conflict::resolutionModeFromString(options.mode, "mcvio run --mode");
  makeOutputFolder(options.output_dir);
  const double data_seconds = toSeconds(data.frame_times.back() - data.frame_times.front());
  RunRecorder rec(options.output_dir + "/trajectory.tum", data.frame_times.size(), options, data_seconds);

  VioPipeline vio(data.calibration, vio_options);
  const double cpu0 = processCpuSeconds();
  const double load_start = loadAverage();
  const auto start = Clock::now();
  try {
    if (data.features) {
      runOnFeatures(data, vio, rec, options.stop_requested);
    } else if (options.pipelined) {
      runPipelined(data, vio, rec, options.stop_requested);
    } else {
      runSequential(data, vio, rec, options.stop_requested);
    }
    rec.finish();
  } catch (const std::exception& e) {
    // What was written stays (nothing is lost), but marked: an aborted run must not pass for a
    // finished one (`mcvio eval` reads this).
    const nlohmann::json failed = {{"dataset", options.dataset_dir},
                                   {"completed", false},
                                   {"error", e.what()},
                                   {"frames", rec.summary.frames},
                                   {"poses", rec.summary.estimated},
                                   {"warnings", data.warnings}};
    std::ofstream(options.output_dir + "/stats.json") << failed.dump(2) << "\n";
    throw;
  }
  OfflineRunSummary summary = rec.summary;
  summary.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  summary.cpu_seconds = processCpuSeconds() - cpu0;
  summary.data_seconds = data_seconds;
  summary.peak_rss_mb = peakRssMb();
  summary.loader_median_cpu_ms = rec.loader_ms.median();
  summary.frontend_median_cpu_ms = rec.frontend_ms.median();
  summary.backend_median_cpu_ms = rec.backend_ms.median();

  for (const auto& [reason, count] : rec.skip_reasons) {
    if (summary.skip_reasons.size() >= 3) break;
    summary.skip_reasons.push_back(reason + (count > 1 ? " (x" + std::to_string(count) + ")" : ""));
  }
  summary.not_initialized = rec.not_initialized;
  nlohmann::json stats = {
      {"dataset", options.dataset_dir},
      {"completed", true},
      {"input", data.features ? "recorded features (estimator only)" : "images"},
      {"pipelined", options.pipelined && !data.features},
      {"frames", summary.frames},
      {"poses", summary.estimated},
      {"skipped_frames", summary.skipped},
      {"skip_reasons", rec.skip_reasons},
      {"not_initialized_frames", rec.not_initialized},
      {"rejected_frames", summary.rejected},
      {"first_rejection", summary.first_rejection},
      {"resets", summary.resets},
      {"keyframes", rec.keyframes},
      {"zero_velocity_frames", rec.zero_velocity},
      {"conflict_mode", conflict::toString(vio_options.estimator.conflict.mode)},
      {"conflict_frames", rec.conflict_frames},
      {"wall_seconds", summary.wall_seconds},
      {"cpu_seconds", summary.cpu_seconds},
      {"data_seconds", summary.data_seconds},
      {"frames_per_second", summary.framesPerSecond()},
      {"realtime_factor", summary.realtimeFactor()},
      {"peak_rss_mb", summary.peak_rss_mb},
      {"load_average_1min", {{"start", load_start}, {"end", loadAverage()}}},
      {"cpu_ms_per_frame",
       {{"image_loading", rec.loader_ms.summary()}, {"frontend", rec.frontend_ms.summary()}, {"backend", rec.backend_ms.summary()}}},
      {"backend_wall_ms_per_frame", stageSummaries(rec.backend_stage_ms)},
      {"solver_iterations", rec.iterations.summary()},
      {"features_per_frame", rec.features.summary()},
      {"new_tracks", rec.new_tracks},
      {"reidentified_tracks", rec.reidentified_tracks},
      {"stereo_matches_per_frame", rec.stereo.summary()},
      {"landmarks_in_window", rec.landmarks.summary()},
      {"warnings", data.warnings}};
  std::ofstream(options.output_dir + "/stats.json") << stats.dump(2) << "\n";
  return summary;
}

}  // namespace mcvio::pipeline
