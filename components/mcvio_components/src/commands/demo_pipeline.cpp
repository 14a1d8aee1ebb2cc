#include "commands/demo_pipeline.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "mcvio/components/backend_component.hpp"
#include "mcvio/components/frontend_component.hpp"
#include "mcvio/components/player.hpp"
#include "mcvio/components/recorder.hpp"
#include "mcvio/components/ros_conversions.hpp"
#include "mcvio/conflict/conflict_options.hpp"
#include "mcvio/core/input_error.hpp"
#include "mcvio/core/progress_bar.hpp"
#include "mcvio/core/write_failure.hpp"
#include "mcvio/dataset/euroc_dataset.hpp"
#include "mcvio/dds/graph_monitor.hpp"
#include "mcvio/dds/node.hpp"
#include "mcvio/dds/shutdown_signal.hpp"
#include "mcvio/evaluation/evaluator.hpp"
#include "mcvio/evaluation/plot_canvas.hpp"
#include "mcvio/evaluation/report_plotter.hpp"
#include "mcvio/evaluation/report_writer.hpp"
#include "mcvio/evaluation/ride_measurement.hpp"
#include "mcvio/evaluation/trajectory_io.hpp"
#include "mcvio/pipeline/offline_run.hpp"
#include "mcvio/pipeline/vio_pipeline.hpp"
#include "mcvio/sim/simulator.hpp"

namespace mcvio::cli {

namespace fs = std::filesystem;
namespace ev = mcvio::evaluation;
using Clock = std::chrono::steady_clock;
using Odometry = nav_msgs::msg::dds_::Odometry_;
using MotionConflict = mcvio_msgs::msg::dds_::MotionConflict_;
using Path = nav_msgs::msg::dds_::Path_;

namespace {

dds::ParticipantOptions named(dds::ParticipantOptions o, const std::string& name) {
  o.name = name;
  return o;
}

// Ctrl-C: the long library calls (rendering, the offline run) stop at the exception thrown from
// their callbacks.
void throwIfInterrupted(const std::string& during) {
  if (dds::ShutdownSignal::requested()) throw std::runtime_error("interrupted during " + during);
}

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// t in seconds with all nine decimals, as `mcvio run` writes it.
void writeSeconds(std::ostream& out, Timestamp t) {
  out << t / 1000000000 << '.' << std::setw(9) << std::setfill('0') << t % 1000000000 << std::setfill(' ');
}

Timestamp nanosOf(const builtin_interfaces::msg::dds_::Time_& t) {
  return static_cast<Timestamp>(t.sec()) * 1000000000 + t.nanosec();
}

void writePose(std::ostream& out, Timestamp t, const geometry_msgs::msg::dds_::Pose_& p) {
  writeSeconds(out, t);
  out << ' ' << p.position().x() << ' ' << p.position().y() << ' ' << p.position().z() << ' ' << p.orientation().x()
      << ' ' << p.orientation().y() << ' ' << p.orientation().z() << ' ' << p.orientation().w() << '\n';
}

void writePose(std::ostream& out, const Odometry& o) { writePose(out, components::stampOf(o.header()), o.pose().pose()); }

/// As `mcvio run`: NAME.tum is the final estimate (the last Path on `path_topic`, where conflict
/// windows revised earlier poses), NAME_online.tum what `odometry_topic` said per frame. A path
/// that does not hold every pose (its newest message lost) leaves the per-frame poses in NAME.tum.
void writeFinalAndOnline(const fs::path& dir, const std::string& name, const std::string& what, const Path& path,
                         const std::string& path_topic, const std::vector<Odometry>& per_frame,
                         const std::string& odometry_topic) {
  std::ofstream final_file(dir / (name + ".tum"));
  if (!final_file) throwCannotWrite(dir / (name + ".tum"), errno);
  std::ofstream online(dir / (name + "_online.tum"));
  if (!online) throwCannotWrite(dir / (name + "_online.tum"), errno);
  online << "# t x y z qx qy qz qw  (" << what << "; t in seconds; " << odometry_topic << " per frame)\n"
         << std::setprecision(9) << std::fixed;
  for (const auto& o : per_frame) writePose(online, o);
  final_file << "# t x y z qx qy qz qw  (" << what << "; t in seconds; final estimate, the last " << path_topic << ")\n"
             << std::setprecision(9) << std::fixed;
  if (path.poses().size() == per_frame.size()) {
    for (const auto& ps : path.poses()) writePose(final_file, components::stampOf(ps.header()), ps.pose());
  } else {
    std::cerr << "mcvio demo: warning: the last " << path_topic << " holds " << path.poses().size() << " poses, "
              << odometry_topic << " " << per_frame.size() << "; " << name << ".tum is the per-frame odometry\n";
    for (const auto& o : per_frame) writePose(final_file, o);
  }
}

const char* stateName(std::uint8_t state) {
  switch (state) {
    case 0: return "none";
    case 1: return "suspected";
    case 2: return "conflict";
    default: return "unknown";
  }
}

// Waits until `done` holds, failing when nothing moved (`progress` unchanged) for `stall`.
template <class Done, class Progress>
void waitWhileProgressing(Done done, Progress progress, std::chrono::seconds stall, const std::string& what) {
  auto last = progress();
  auto last_change = Clock::now();
  while (!done()) {
    if (dds::ShutdownSignal::requested()) throw std::runtime_error("interrupted while " + what);
    const auto now_value = progress();
    if (now_value != last) {
      last = now_value;
      last_change = Clock::now();
    } else if (Clock::now() - last_change > stall) {
      throw std::runtime_error("stalled for " + std::to_string(stall.count()) + " s while " + what);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

std::string fixed(double v, int decimals) {
  if (!std::isfinite(v)) return "n/a";
  std::ostringstream s;
  s << std::fixed << std::setprecision(decimals) << v;
  return s.str();
}

std::uintmax_t folderBytes(const fs::path& dir) {
  std::uintmax_t bytes = 0;
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir, ec); !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (it->is_regular_file(ec)) bytes += it->file_size(ec);
  }
  return bytes;
}

}  // namespace

struct DemoPipeline::Sequence {
  std::string name;
  fs::path dir, data_dir, bag_dir, mcvio_dir, reference_dir, report_dir;
  sim::SimulatorOptions sim;
  std::string signature;  ///< what was rendered: a rerun with the same signature reuses it
};

void DemoPipeline::Options::validate() const {
  if (out_dir.empty()) throw std::invalid_argument("--out: empty");
  if (!(duration_s >= 12.0 && duration_s <= 600.0)) {
    throw std::invalid_argument("--duration: " + std::to_string(duration_s) + " s is outside 12..600 s");
  }
  conflict::resolutionModeFromString(mode, "--mode");
  if (mode == "reference") {
    throw std::invalid_argument("--mode reference: the demo compares MC-VIO with reference; choose imu, selective or auto");
  }
  if (scenarios.empty()) throw std::invalid_argument("no scenario to run");
}

double DemoPipeline::SequenceResult::reduction() const {
  return ev::ReportWriter::relativeReduction(reference_ate_m, mcvio_ate_m);
}

DemoPipeline::DemoPipeline(Options options) : options_(std::move(options)) { options_.validate(); }

DemoPipeline::Sequence DemoPipeline::plan(const std::string& scenario) const {
  Sequence s;
  s.name = scenario;
  s.dir = fs::path(options_.out_dir) / scenario;
  s.data_dir = s.dir / "data";
  s.bag_dir = s.dir / "bag";
  s.mcvio_dir = s.dir / "mcvio";
  s.reference_dir = s.dir / "reference";
  s.report_dir = s.dir / "report";
  auto& o = s.sim;
  o.output_dir = s.data_dir.string();
  o.overwrite = true;
  o.seed = options_.seed;
  o.duration_s = options_.duration_s;
  o.scenario.kind = sim::scenarioKindFromString(scenario);
  // The conflict from 1/3 to 11/15 of the sequence (10 s to 22 s of 30 s): the estimator is
  // settled before it and has a while after it to show the drift it left.
  o.scenario.onset_s = options_.duration_s / 3.0;
  o.scenario.duration_s = options_.duration_s * 0.4;
  if (o.scenario.kind == sim::ScenarioKind::kElevator) {
    o.scenario.coverage = 1.0;                               // a closed cabin
    o.scenario.travel_m = 0.7 * o.scenario.duration_s;       // 0.7 m/s: 8.4 m in 12 s
  }
  o.validate();
  std::ostringstream sig;
  sig << "scenario " << scenario << "\nseed " << o.seed << "\nduration_s " << o.duration_s << "\nonset_s "
      << o.scenario.onset_s << "\nconflict_s " << o.scenario.duration_s << "\ncoverage " << o.scenario.coverage
      << "\ntravel_m " << o.scenario.travel_m << "\n";
  s.signature = sig.str();
  return s;
}

// Returns false when a previous run left the same rendering (signature file written last).
bool DemoPipeline::render(const Sequence& s) const {
  const fs::path sig_file = s.data_dir / "demo_render.txt";
  if (fs::is_regular_file(sig_file) && fs::is_directory(s.data_dir / "mav0" / "cam0" / "data") &&
      fs::is_directory(s.data_dir / "mav0" / "cam1" / "data")) {
    std::ifstream in(sig_file);
    std::stringstream old;
    old << in.rdbuf();
    if (old.str() == s.signature) return false;
  }
  fs::remove(sig_file);
  sim::Simulator simulator(s.sim);
  ProgressBar bar("render " + s.name, simulator.frameTimes().size(), isatty(2));
  simulator.writeDataset([&](std::size_t done, std::size_t total) {
    throwIfInterrupted("rendering");
    bar.update(done, std::to_string(done) + "/" + std::to_string(total) + " stereo frames");
  });
  bar.finish();
  std::ofstream out(sig_file);
  out << s.signature;
  if (!out) throwCannotWrite(sig_file, errno);
  return true;
}

void DemoPipeline::runOverDds(const Sequence& s, SequenceResult& r) const {
  const auto data = dataset::EurocDataset::open(s.data_dir.string());
  r.frames = data.stereoFrames().size();
  fs::remove_all(s.bag_dir);
  fs::remove_all(s.mcvio_dir);
  fs::create_directories(s.mcvio_dir);

  // What the run published, kept in arrival order (one reliable writer each: time order).
  std::mutex m;
  std::vector<Odometry> odometry, secondary;
  std::vector<MotionConflict> conflicts;
  Path path;  // the newest: the final trajectory, conflict windows revised
  Path secondary_path;  // the newest: the conflicting frame's final poses
  std::size_t secondary_paths_received = 0;

  // The recorder has a participant of its own (it must not share typed registrations).
  dds::GraphMonitor monitor;
  auto recorder_participant = dds::Participant::create(named(options_.participant, "mcvio_demo_recorder"), &monitor);
  components::RecorderOptions ro;
  // Not the images: a 30 s stereo stream is ~430 MB raw; /mcvio/path repeats the odometry.
  ro.regex = "^/(imu0|ground_truth/odometry|tf|tf_static|mcvio/(odometry|conflict|secondary_odometry|features|landmarks))$";
  ro.validate();
  components::Recorder recorder(recorder_participant->createNode("recorder", "/mcvio"), monitor, s.bag_dir.string(), ro);
  recorder.start();

  auto participant = dds::Participant::create(named(options_.participant, "mcvio_demo_components"));
  auto listener = participant->createNode("demo_listener", "/mcvio");
  const auto lossless = dds::QosProfile::lossless();
  auto odom_sub = listener->createSubscription<Odometry>("/mcvio/odometry", lossless, [&](const Odometry& o) {
    std::lock_guard<std::mutex> lock(m);
    odometry.push_back(o);
  });
  auto conflict_sub = listener->createSubscription<MotionConflict>("/mcvio/conflict", lossless, [&](const MotionConflict& c) {
    std::lock_guard<std::mutex> lock(m);
    conflicts.push_back(c);
  });
  auto path_sub = listener->createSubscription<Path>("/mcvio/path", dds::QosProfile::transientLocal(1), [&](const Path& p) {
    std::lock_guard<std::mutex> lock(m);
    path = p;
  });
  auto secondary_sub = listener->createSubscription<Odometry>("/mcvio/secondary_odometry", lossless, [&](const Odometry& o) {
    std::lock_guard<std::mutex> lock(m);
    secondary.push_back(o);
  });
  const auto latched = dds::QosProfile::transientLocal(1);
  auto secondary_path_sub = listener->createSubscription<Path>("/mcvio/secondary_path", latched, [&](const Path& p) {
    std::lock_guard<std::mutex> lock(m);
    secondary_path = p;
    ++secondary_paths_received;
  });

  // The offline reference run uses the shipped configuration: so do the components, but for the mode.
  const pipeline::VioPipelineOptions defaults = pipeline::VioPipelineOptions::shipped();
  components::BackendComponentOptions bo;
  bo.estimator = defaults.estimator;
  bo.estimator.conflict.mode = conflict::resolutionModeFromString(options_.mode, "--mode");
  bo.calibration_dir = s.data_dir.string();
  bo.lossless = true;
  bo.landmarks_every_n_frames = 10;  // a cloud every half second is plenty for a bag
  components::BackendComponent backend(participant->createNode("backend", "/mcvio"), bo);
  components::FrontendComponentOptions fo;
  fo.tracker = defaults.frontend;
  fo.calibration_dir = s.data_dir.string();
  fo.lossless = true;
  components::FrontendComponent frontend(participant->createNode("frontend", "/mcvio"), fo);

  auto player_participant = dds::Participant::create(named(options_.participant, "mcvio_demo_player"));
  components::PlayerOptions po;
  po.lossless = true;
  po.progress = isatty(2);
  po.wait_for_readers_s = 30;
  po.min_readers = 1;
  components::Player player(player_participant->createNode("player", "/mcvio"), data, po);
  // A lossless player waits for a reader on every topic it publishes; nobody in the demo needs
  // camera_info (the components read the calibration folder) and only the recorder wants the
  // ground truth, so these readers stand in.
  auto extra = player_participant->createNode("demo_extra_readers", "/mcvio");
  auto info0 = extra->createSubscription<sensor_msgs::msg::dds_::CameraInfo_>("/cam0/camera_info", lossless, [](const auto&) {});
  auto info1 = extra->createSubscription<sensor_msgs::msg::dds_::CameraInfo_>("/cam1/camera_info", lossless, [](const auto&) {});
  auto gt = extra->createSubscription<Odometry>("/ground_truth/odometry", lossless, [](const auto&) {});

  // The bag should hold the run from its first message: wait until the recorder subscribed.
  const std::vector<std::string> wanted = {"/imu0", "/ground_truth/odometry", "/mcvio/odometry", "/mcvio/conflict"};
  const auto recorder_deadline = Clock::now() + std::chrono::seconds(20);
  for (;;) {
    const auto topics = recorder.recordedTopics();
    const bool all = std::all_of(wanted.begin(), wanted.end(), [&](const std::string& t) {
      return std::find(topics.begin(), topics.end(), t) != topics.end();
    });
    if (all) break;
    if (Clock::now() > recorder_deadline) {
      std::cerr << "mcvio demo: warning: the recorder has not subscribed to every topic after 20 s; the bag may miss "
                   "the start of some\n";
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // matching is two-sided

  const auto t0 = Clock::now();
  const auto playback = player.run();
  if (playback.interrupted) throw std::runtime_error("interrupted during playback");
  const std::size_t pairs = data.stereoFrames().size() - playback.skipped_frames;
  waitWhileProgressing([&] { const auto st = frontend.stats(); return st.frames_published + st.frames_skipped >= pairs; },
                       [&] { const auto st = frontend.stats(); return st.frames_published + st.frames_skipped; },
                       std::chrono::seconds(60), "the frontend tracked the last frames");
  const std::size_t published = frontend.stats().frames_published;
  waitWhileProgressing([&] { return backend.stats().frames_received >= published; },
                       [&] { return backend.stats().frames_received; }, std::chrono::seconds(60),
                       "the backend received the last feature frames");
  backend.flush();
  const auto stats = backend.stats();
  waitWhileProgressing(
      [&] { std::lock_guard<std::mutex> lock(m); return odometry.size() >= stats.poses_published && conflicts.size() >= stats.poses_published; },
      [&] { std::lock_guard<std::mutex> lock(m); return odometry.size() + conflicts.size(); }, std::chrono::seconds(30),
      "the last poses arrived");
  // The path of the last frame (keep-last 1: only the newest is sure to arrive); without it the
  // per-frame odometry stands in below.
  for (const auto deadline = Clock::now() + std::chrono::seconds(5); Clock::now() < deadline;) {
    {
      std::lock_guard<std::mutex> lock(m);
      if (odometry.empty() || components::stampOf(path.header()) == components::stampOf(odometry.back().header())) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  // The secondary path is published only while the conflicting frame is tracked and when a
  // conflict window revises it: wait until nothing more arrives.
  for (std::size_t last = 0, quiet = 0; quiet < 10;) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    std::lock_guard<std::mutex> lock(m);
    quiet = secondary_paths_received == last ? quiet + 1 : 0;
    last = secondary_paths_received;
  }
  r.dds_s = secondsSince(t0);
  // Let the recorder drain what is still on the wire, then close the bag.
  for (std::size_t last = recorder.messagesWritten(), n = 0; n < 100; ++n) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    const std::size_t now = recorder.messagesWritten();
    if (now == last) break;
    last = now;
  }
  const auto recording = recorder.stop();
  r.bag_messages = recording.messages;

  std::lock_guard<std::mutex> lock(m);
  r.mcvio_poses = odometry.size();
  std::ofstream csv(s.mcvio_dir / "conflict.csv");
  if (!csv) throwCannotWrite(s.mcvio_dir / "conflict.csv", errno);
  writeFinalAndOnline(s.mcvio_dir, "trajectory", "pose of imu0 in world", path, "/mcvio/path", odometry,
                      "/mcvio/odometry");
  writeFinalAndOnline(s.mcvio_dir, "secondary", "the conflicting frame S in world, identity at the interval start",
                      secondary_path, "/mcvio/secondary_path", secondary, "/mcvio/secondary_odometry");
  csv << pipeline::kConflictCsvHeader;
  for (const auto& c : conflicts) {
    csv << components::stampOf(c.header()) << ',' << stateName(c.state()) << ',' << c.propagated_chi2() << ','
        << c.propagated_threshold() << ',' << c.landmarks_tested() << ',' << c.landmarks_inconsistent() << ','
        << c.inconsistent_fraction() << ',' << c.coherence() << ',' << nanosOf(c.interval_start()) << ','
        << c.resolution_mode() << ',' << nanosOf(c.interval_onset()) << ',' << nanosOf(c.interval_end()) << ','
        << c.frontend_checked() << ',' << c.frontend_inconsistent() << ',' << c.accel_bias_drift() << ','
        << c.split_chi2() << ',' << c.evidence_score() << '\n';
  }
  std::cout << "  DDS run: " << stats.frames_received << " feature frames, " << stats.poses_published << " poses ("
            << stats.conflict_frames << " in conflict, " << stats.resets << " resets) in " << fixed(r.dds_s, 1)
            << " s; bag: " << recording.messages << " messages on " << recording.messages_per_topic.size()
            << " topics -> " << s.bag_dir.string() << "\n";
  if (odometry.empty()) {
    throw std::runtime_error(s.name + ": the backend published no pose over DDS (" + std::to_string(stats.frames_received) +
                             " feature frames received, " + std::to_string(stats.not_initialized) +
                             " before initialisation)");
  }
}

void DemoPipeline::runReference(const Sequence& s) const {
  pipeline::OfflineRunOptions o;
  o.dataset_dir = s.data_dir.string();
  o.output_dir = s.reference_dir.string();
  o.mode = "reference";
  o.progress = isatty(2);
  o.on_frame = [](std::size_t, const pipeline::VioFrameResult&) { throwIfInterrupted("the reference run"); };
  fs::remove_all(s.reference_dir);
  fs::create_directories(s.reference_dir);
  const auto summary = pipeline::runOffline(o);
  std::cout << "  reference run: " << summary.estimated << " poses of " << summary.frames << " frames, "
            << summary.resets << " resets -> " << s.reference_dir.string() << "\n";
}

namespace {

/// The elevator's ride as each trajectory saw it: height gained since the labelled ride began,
/// the ground truth's, the reference's and MC-VIO's (position+yaw aligned), and the cabin's own
/// (MC-VIO's secondary frame, which starts as the world where the interval opens).
std::string plotRide(const std::string& dir, const ev::Trajectory& gt, const ev::ConflictLabelTimeline& labels,
                     const ev::EvaluationReport& report, const ev::Trajectory& cabin) {
  const auto& l = labels.labels();
  const auto start = std::find_if(l.begin(), l.end(), [](const auto& x) { return x.in_conflict; });
  if (start == l.end() || gt.poses().empty()) return {};
  const Timestamp t0 = gt.poses().front().t, ride = start->t;
  auto heightsSince = [&](const std::vector<ev::StampedPose>& poses, std::vector<double>* t, std::vector<double>* z) {
    const auto at = std::lower_bound(poses.begin(), poses.end(), ride, [](const auto& p, Timestamp x) { return p.t < x; });
    if (at == poses.end()) return;
    for (const auto& p : poses) {
      t->push_back(toSeconds(p.t - t0));
      z->push_back(p.p.z() - at->p.z());
    }
  };
  ev::PlotCanvas c("Elevator ride: height gained since the ride began");
  c.setXLabel("time [s]");
  c.setYLabel("height [m]");
  for (const auto& i : labels.conflictIntervals())
    c.addXBand(toSeconds(i.start - t0), toSeconds(i.end - t0), ev::ReportPlotter::conflictColor(), "labelled ride", 0.3);
  std::vector<double> t, z;
  heightsSince(gt.poses(), &t, &z);
  c.addLine(t, z, ev::ReportPlotter::groundTruthColor(), "ground truth", 2, true);
  for (std::size_t i = 0; i < report.estimates.size(); ++i) {
    t.clear();
    z.clear();
    heightsSince(report.estimates[i].ate_posyaw.aligned_estimate, &t, &z);
    c.addLine(t, z, ev::ReportPlotter::runColor(i), report.estimates[i].name, 2);
  }
  t.clear();
  z.clear();
  for (const auto& p : cabin.poses()) {
    t.push_back(toSeconds(p.t - t0));
    z.push_back(p.p.z());
  }
  if (!t.empty()) c.addLine(t, z, cv::Scalar(40, 40, 200), "the cabin (MC-VIO's secondary frame)", 3);
  const std::string path = dir + "/ride_heights.png";
  c.save(path);
  return path;
}

}  // namespace

void DemoPipeline::evaluate(const Sequence& s, SequenceResult& r) const {
  ev::EvaluationOptions eo;
  eo.baseline = "reference";
  eo.validate();
  const ev::Trajectory gt = ev::loadTrajectory(s.data_dir.string());
  const auto labels = ev::ConflictLabelTimeline::load((s.data_dir / "mav0" / "conflict_labels.csv").string());
  std::vector<ev::EstimateInput> runs(2);
  runs[0].name = "reference";
  runs[0].trajectory = ev::loadTum((s.reference_dir / "trajectory.tum").string());
  runs[0].online_trajectory = ev::loadOnlineTrajectory(s.reference_dir.string());
  runs[0].detector = ev::DetectorLog::load((s.reference_dir / "conflict.csv").string());
  runs[1].name = "mcvio";
  runs[1].trajectory = ev::loadTum((s.mcvio_dir / "trajectory.tum").string());
  runs[1].online_trajectory = ev::loadOnlineTrajectory(s.mcvio_dir.string());
  runs[1].detector = ev::DetectorLog::load((s.mcvio_dir / "conflict.csv").string());
  const auto report = ev::Evaluator(eo).evaluate(gt, runs, labels);
  fs::remove_all(s.report_dir);
  ev::ReportWriter::write(report, s.report_dir.string());
  r.plots = ev::ReportPlotter::write(report, s.report_dir.string());
  r.report_dir = s.report_dir.string();
  r.bag_dir = s.bag_dir.string();
  const auto* ref = report.find("reference");
  const auto* mc = report.find("mcvio");
  r.reference_poses = ref->poses;
  r.reference_ate_m = ref->ate_posyaw.translation.rmse;
  r.mcvio_ate_m = mc->ate_posyaw.translation.rmse;
  r.mcvio_online_ate_m = mc->onlineAtePosYawRmse();
  r.reference_rpe_m = ref->rpe_time.translation.rmse;
  r.mcvio_rpe_m = mc->rpe_time.translation.rmse;
  if (mc->detection) {
    r.has_detection = true;
    r.mcvio_tpr = mc->detection->counts.tpr();
    r.mcvio_fpr = mc->detection->counts.fpr();
    if (mc->detection->has_hindsight) {
      r.mcvio_hindsight_tpr = mc->detection->hindsight.tpr();
      r.mcvio_hindsight_fpr = mc->detection->hindsight.fpr();
    }
    r.mcvio_onset_delay_s = mc->detection->labelledSpan().onset_delay_s;
  }
  if (s.sim.scenario.kind == sim::ScenarioKind::kElevator) {
    // The conflicting frame's final poses; a run that never tracked one leaves the header only.
    const ev::Trajectory cabin = ev::loadTum((s.mcvio_dir / "secondary.tum").string(), ev::EmptyTum::kEmptyTrajectory);
    r.reference_ride = ev::RideMeasurement::measure(runs[0].trajectory, ev::Trajectory(), gt, labels,
                                                    ref->ate_posyaw.T_gt_est.linear());
    r.mcvio_ride = ev::RideMeasurement::measure(runs[1].trajectory, cabin, gt, labels, mc->ate_posyaw.T_gt_est.linear());
    const std::string plot = plotRide(s.report_dir.string(), gt, labels, report, cabin);
    if (!plot.empty()) r.plots.push_back(plot);
  }
}

void DemoPipeline::checkDomainIsFree() const {
  dds::GraphMonitor monitor;
  auto participant = dds::Participant::create(named(options_.participant, "mcvio_demo_check"), &monitor);
  const std::vector<std::string> ours = {"/imu0", "/cam0/image_raw", "/cam1/image_raw", "/mcvio/features", "/mcvio/odometry"};
  std::string taken;
  // Discovery of the participants already there takes a moment; 3 s finds them under load.
  monitor.waitFor([&](const std::vector<dds::DiscoveredTopic>& topics) {
    for (const auto& t : topics) {
      if (t.publishers > 0 && std::find(ours.begin(), ours.end(), t.name) != ours.end()) {
        taken = t.name;
        return true;
      }
    }
    return false;
  }, std::chrono::milliseconds(3000));
  if (!taken.empty()) {
    throw std::runtime_error("DDS domain " + std::to_string(options_.participant.domain_id) + " already has a publisher of " +
                             taken + " (another player, demo or VIO?); its messages would mix into the demo's. Stop it "
                             "or give the demo a domain of its own, e.g. mcvio --domain 42 demo");
  }
}

std::vector<DemoPipeline::SequenceResult> DemoPipeline::run() const {
  std::vector<Sequence> sequences;
  for (const auto& name : options_.scenarios) sequences.push_back(plan(name));
  fs::create_directories(options_.out_dir);
  checkDomainIsFree();
  const int steps = static_cast<int>(sequences.size()) * 4;
  int step = 0;
  const auto stepLine = [&](const std::string& what) {
    std::cout << "[" << ++step << "/" << steps << "] " << what << std::endl;
  };
  std::vector<SequenceResult> results(sequences.size());
  for (std::size_t i = 0; i < sequences.size(); ++i) {
    const auto& s = sequences[i];
    auto& r = results[i];
    r.name = s.name;
    const auto& sc = s.sim.scenario;
    stepLine("render " + s.name + ": " + fixed(s.sim.duration_s, 0) + " s, conflict " + fixed(sc.onset_s, 1) + "-" +
             fixed(sc.onset_s + sc.duration_s, 1) + " s" +
             (sc.travel_m > 0 ? ", cabin travel " + fixed(sc.travel_m, 1) + " m" : std::string()) + " -> " +
             s.data_dir.string());
    auto t = Clock::now();
    r.rendered = render(s);
    r.render_s = secondsSince(t);
    std::cout << (r.rendered ? "  rendered in " + fixed(r.render_s, 1) + " s\n"
                             : "  reusing the rendering of a previous run with the same options (" + s.data_dir.string() + ")\n");

    stepLine(s.name + ": Recorder + BackendComponent (" + options_.mode +
             ") + FrontendComponent + Player (lossless) over DDS, domain " + std::to_string(options_.participant.domain_id));
    runOverDds(s, r);

    stepLine(s.name + ": reference run offline (runOffline, mode reference)");
    t = Clock::now();
    runReference(s);
    r.reference_s = secondsSince(t);

    stepLine(s.name + ": evaluate reference and MC-VIO against ground truth and conflict labels");
    evaluate(s, r);
    std::cout << "  ATE pos+yaw: reference " << fixed(r.reference_ate_m, 3) << " m, MC-VIO " << fixed(r.mcvio_ate_m, 3)
              << " m -> " << r.report_dir << "/eval.md\n";

    if (!options_.keep_images) {
      const fs::path mav0 = s.data_dir / "mav0";
      const std::uintmax_t bytes = folderBytes(mav0 / "cam0" / "data") + folderBytes(mav0 / "cam1" / "data");
      fs::remove(s.data_dir / "demo_render.txt");
      fs::remove_all(mav0 / "cam0" / "data");
      fs::remove_all(mav0 / "cam1" / "data");
      std::cout << "  removed the rendered images (" << bytes / 1000000 << " MB; --keep keeps them for the next run)\n";
    }
  }
  return results;
}

std::string DemoPipeline::summary(const std::vector<SequenceResult>& results, const std::string& mode) {
  std::ostringstream out;
  out << "\n| sequence | frames | ATE ref [m] | ATE MC-VIO (" << mode
      << ") [m] | MC-VIO per frame [m] | reduction | RPE 1 s ref [m] | RPE 1 s MC-VIO [m] | detection TPR | detection FPR | TPR / FPR in hindsight | detected after [s] |\n"
      << "|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : results) {
    const std::string red = std::isfinite(r.reduction()) ? (r.reduction() >= 0 ? "+" : "") + fixed(r.reduction(), 0) + " %" : "n/a";
    out << "| " << r.name << " | " << r.frames << " | " << fixed(r.reference_ate_m, 3) << " | " << fixed(r.mcvio_ate_m, 3)
        << " | " << fixed(r.mcvio_online_ate_m, 3) << " | " << red << " | " << fixed(r.reference_rpe_m, 3) << " | " << fixed(r.mcvio_rpe_m, 3) << " | "
        << (r.has_detection ? fixed(r.mcvio_tpr, 2) : "n/a") << " | " << (r.has_detection ? fixed(r.mcvio_fpr, 2) : "n/a")
        << " | "
        << (std::isfinite(r.mcvio_hindsight_tpr) ? fixed(r.mcvio_hindsight_tpr, 2) + " / " + fixed(r.mcvio_hindsight_fpr, 2)
                                                 : "n/a")
        << " | " << fixed(r.mcvio_onset_delay_s, 2) << " |\n";
  }
  out << "\nATE: RMSE after position+yaw alignment, of the final trajectory; MC-VIO per frame: the same for the poses\n"
         "as /mcvio/odometry published them, before the conflict window revised an IMU-dominated interval;\n"
         "reduction: 100 * (ref - MC-VIO) / ref (final trajectories), positive = less error.\n"
         "Detection: per frame, MC-VIO's detector state `conflict` against the rendered labels; in hindsight:\n"
         "its conflict intervals from where the evidence began to build up to the last frame with evidence;\n"
         "detected after: from the first labelled frame to MC-VIO's first detection.\n";
  for (const auto& r : results) {
    if (!r.mcvio_ride.valid) continue;
    const auto& m = r.mcvio_ride;
    out << "\n" << r.name << ": the ride carried the device " << fixed(m.truth_dz_m, 2) << " m up; reference "
        << fixed(r.reference_ride.estimate_dz_m, 2) << " m, MC-VIO " << fixed(m.estimate_dz_m, 2) << " m ("
        << fixed(m.dz_error_percent, 1) << " % off)";
    if (std::isfinite(m.secondary_dz_m))
      out << ";\n  the cabin's own motion (secondary frame, secondary.tum) " << fixed(m.secondary_dz_m, 2) << " m ("
          << fixed(m.secondary_dz_error_percent, 1) << " % off)";
    out << ".\n";
  }
  for (const auto& r : results) {
    out << "\n" << r.name << ":\n  report  " << r.report_dir << "/eval.md (and eval.json)\n  plots  ";
    for (const auto& p : r.plots) out << " " << fs::path(p).filename().string();
    out << " (in " << r.report_dir << ")\n  bag     " << r.bag_dir << " (" << r.bag_messages
        << " messages; `mcvio bag info " << r.bag_dir << "`)\n  rerun   mcvio run --dataset " << r.bag_dir
        << " --calib " << fs::path(r.bag_dir).parent_path().string() << "/data --mode imu --out "
        << fs::path(r.bag_dir).parent_path().string() << "/imu   (the estimator alone on the bag's recorded features)\n";
  }
  return out.str();
}

}  // namespace mcvio::cli
