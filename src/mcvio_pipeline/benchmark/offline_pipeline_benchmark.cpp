// Speed, memory and accuracy of `mcvio run` (runOffline) on 60 s clean sequences: the rendered
// office (`none`), semi-real V1_01 (rendered along the real ground truth with the real IMU) and
// the real standing V1_01 excerpt; and on a 30 s rendered elevator (a 12 m ride from 10 to 22 s,
// MC-VIO `auto`; more seeds and the vehicle with --ride-seeds / --ride-scenarios), whose per-frame output (what /mcvio/odometry published, before the conflict
// window revised the ride) is measured too: its ATE and whether its covariance covers its error
// during the ride. Renders the sequences once into a folder and reuses them.
// Each render and each run happens in a child process, so the peak memory (getrusage) is the
// run's own. Prints one Markdown table.
//
//   mcvio_pipeline_benchmark [--data DIR] [--seconds S] [--sequential] [--only NAME]
//                            [--config FILE | --defaults] [--ride-seeds LIST] [--ride-scenarios LIST]
// The run configuration is share/mcvio_pipeline/config/vio_pipeline.yaml unless --config names
// another or --defaults asks for the built-in defaults.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../test/clean_sequences.hpp"
#include "../test/run_accuracy.hpp"
#include "mcvio/dataset/euroc_dataset.hpp"
#include "mcvio/pipeline/offline_run.hpp"
#include "mcvio/sim/simulator.hpp"

using namespace mcvio;
namespace fs = std::filesystem;

namespace {

struct Sequence {
  std::string name;
  std::string dataset_dir;
  std::string description;    // how it was made; a render is reused only if this matches
  std::function<void()> render;  // empty: the dataset exists already
  std::string mode;              // empty: the config's
  double conflict_from_s = 0, conflict_to_s = 0;  // the labelled conflict, after the first frame
};

// Mean and median NEES of the samples from `from_s` to `to_s` after the first (NaN without samples):
// the mean follows the few frames around an onset the detector has not found yet, the median
// the rest.
std::pair<double, double> neesOver(const pipeline::sequences::RunAccuracy& a, double from_s, double to_s) {
  std::vector<double> v;
  if (!a.nees_samples.empty()) {
    const Timestamp t0 = a.nees_samples.front().t;
    for (const auto& s : a.nees_samples) {
      const double t = toSeconds(s.t - t0);
      if (t >= from_s && t <= to_s) v.push_back(s.nees);
    }
  }
  if (v.empty()) return {std::nan(""), std::nan("")};
  double sum = 0;
  for (double x : v) sum += x;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return {sum / static_cast<double>(v.size()), v[v.size() / 2]};
}

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a + " " + b + " " + c;
}

// Runs `fn` in a child process; false if it failed.
bool inChild(const std::function<void()>& fn) {
  std::cout.flush();
  std::cerr.flush();
  const pid_t pid = fork();
  if (pid < 0) return false;
  if (pid == 0) {
    try {
      fn();
    } catch (const std::exception& e) {
      std::cerr << "error: " << e.what() << "\n";
      _exit(1);
    }
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

void ensureRendered(const Sequence& s) {
  if (!s.render) return;
  const std::string stamp = s.dataset_dir + "/mcvio_benchmark_stamp.txt";
  std::ifstream in(stamp);
  std::string have;
  std::getline(in, have);
  if (have == s.description && fs::exists(s.dataset_dir + "/mav0/cam1/data.csv")) {
    std::cerr << s.name << ": reusing " << s.dataset_dir << "\n";
    return;
  }
  std::cerr << s.name << ": rendering into " << s.dataset_dir << " ...\n";
  if (!inChild(s.render)) throw std::runtime_error("rendering " + s.name + " failed");
  std::ofstream(stamp) << s.description << "\n";
}

// The run and its evaluation, in a child; results in OUT/benchmark.json.
void runOne(const Sequence& s, const std::string& out, bool pipelined, const std::string& config) {
  pipeline::OfflineRunOptions o;
  o.mode = s.mode;
  o.dataset_dir = s.dataset_dir;
  o.output_dir = out;
  o.progress = isatty(2);
  o.pipelined = pipelined;
  o.config_file = config;
  pipeline::sequences::CovarianceLog covariances;
  o.on_frame = [&](std::size_t, const pipeline::VioFrameResult& r) { covariances.add(r); };
  const auto sum = pipeline::runOffline(o);
  const auto gt = dataset::EurocDataset::open(s.dataset_dir).groundTruth();
  const auto a = pipeline::sequences::evaluateRun(out + "/trajectory.tum", gt, covariances);
  pipeline::sequences::writeNeesCsv(a, out + "/nees.csv");
  nlohmann::json j = {{"frames", sum.frames},
                            {"poses", a.poses},
                            {"resets", sum.resets},
                            {"ate_pos_yaw", a.ate_pos_yaw_rmse},
                            {"ate_se3", a.ate_se3_rmse},
                            {"rpe_1s", a.rpe_1s_translation_rmse},
                            {"rpe_1s_deg", a.rpe_1s_rotation_rmse_deg},
                            {"nees", a.position_nees},
                            {"nees_whole_run_alignment", a.position_nees_whole_run_alignment},
                            {"backend_ms", sum.backend_median_cpu_ms},
                            {"frontend_ms", sum.frontend_median_cpu_ms},
                            {"loader_ms", sum.loader_median_cpu_ms},
                            {"wall_s", sum.wall_seconds},
                            {"cpu_s", sum.cpu_seconds},
                            {"data_s", sum.data_seconds},
                            {"realtime", sum.realtimeFactor()},
                            {"rss_mb", sum.peak_rss_mb}};
  if (s.conflict_to_s > s.conflict_from_s) {
    // trajectory_online.tum exists only when a conflict window revised poses; else it is trajectory.tum.
    const std::string online_tum = fs::exists(out + "/trajectory_online.tum") ? out + "/trajectory_online.tum" : out + "/trajectory.tum";
    const auto online = pipeline::sequences::evaluateRun(online_tum, gt, covariances);
    pipeline::sequences::writeNeesCsv(online, out + "/nees_online.csv");
    const auto [inside_mean, inside_median] = neesOver(online, s.conflict_from_s, s.conflict_to_s);
    const auto [after_mean, after_median] = neesOver(online, s.conflict_to_s, 1e9);
    j["conflict"] = {{"ate_pos_yaw_online", online.ate_pos_yaw_rmse},
                     {"nees_online", online.position_nees},
                     {"nees_online_in_conflict", inside_mean},
                     {"nees_online_in_conflict_median", inside_median},
                     {"nees_online_after", after_mean},
                     {"nees_online_after_median", after_median}};
  }
  std::ofstream(out + "/benchmark.json") << j.dump(2) << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::string data = "/tmp/mcvio_pipeline_benchmark", only, config = MCVIO_PIPELINE_CONFIG;
  double seconds = 60.0;
  bool pipelined = true;
  std::vector<int> ride_seeds{1};
  std::vector<std::string> ride_scenarios{"elevator"};
  const auto split = [](const std::string& list) {
    std::vector<std::string> items;
    std::stringstream in(list);
    for (std::string item; std::getline(in, item, ',');)
      if (!item.empty()) items.push_back(item);
    return items;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--data" && i + 1 < argc) data = argv[++i];
    else if (a == "--seconds" && i + 1 < argc) seconds = std::stod(argv[++i]);
    else if (a == "--only" && i + 1 < argc) only = argv[++i];
    else if (a == "--config" && i + 1 < argc) config = argv[++i];
    else if (a == "--defaults") config = "defaults";
    else if (a == "--sequential") pipelined = false;
    else if (a == "--ride-seeds" && i + 1 < argc) {
      ride_seeds.clear();
      for (const auto& item : split(argv[++i])) {
        const int seed = std::atoi(item.c_str());
        if (seed <= 0) {
          std::cerr << "--ride-seeds: '" << item << "' is not a positive seed\n";
          return 2;
        }
        ride_seeds.push_back(seed);
      }
    } else if (a == "--ride-scenarios" && i + 1 < argc) {
      ride_scenarios = split(argv[++i]);
      for (const auto& kind : ride_scenarios)
        if (kind != "elevator" && kind != "vehicle") {
          std::cerr << "--ride-scenarios: '" << kind << "' is not elevator or vehicle\n";
          return 2;
        }
    }
    else {
      std::cerr << "usage: " << argv[0]
                << " [--data DIR] [--seconds S] [--sequential] [--only NAME] [--config FILE | --defaults]"
                   " [--ride-seeds 1,4,5] [--ride-scenarios elevator,vehicle]\n";
      return 2;
    }
  }
  fs::create_directories(data);
  if (config == "defaults") {
    // An empty configuration file keeps every built-in default (runOffline without one ships its own).
    config = data + "/built_in_defaults.yaml";
    std::ofstream(config) << "{}\n";
  }
  std::ostringstream secs;
  secs << seconds;
  std::vector<Sequence> sequences;
  {
    Sequence s;
    s.name = "rendered_none_" + secs.str() + "s";
    s.dataset_dir = data + "/" + s.name;
    s.description = "none seed 1 duration " + secs.str() + " png level " +
                    std::to_string(pipeline::sequences::renderedNone(seconds, 1).png_compression);
    s.render = [dir = s.dataset_dir, seconds] {
      auto o = pipeline::sequences::renderedNone(seconds, 1);
      o.output_dir = dir;
      sim::Simulator(o).writeDataset();
    };
    sequences.push_back(s);
  }
  // The rides: a 30 s rendered elevator (and vehicle, with --ride-scenarios) per seed, MC-VIO auto.
  for (const std::string& kind : ride_scenarios)
    for (const int seed : ride_seeds) {
      Sequence s;
      s.name = "rendered_" + kind + "_30s" + (seed == 1 ? std::string() : "_seed" + std::to_string(seed));
      s.dataset_dir = data + "/" + s.name;
      s.mode = "auto";
      s.conflict_from_s = 10;
      s.conflict_to_s = 22;
      s.description = kind + " seed " + std::to_string(seed) + " duration 30 onset 10 ride 12 s png level " +
                      std::to_string(pipeline::sequences::renderedNone(30, seed).png_compression);
      const sim::ScenarioKind scenario = kind == "vehicle" ? sim::ScenarioKind::kVehicle : sim::ScenarioKind::kElevator;
      s.render = [dir = s.dataset_dir, seed, scenario] {
        auto o = pipeline::sequences::renderedNone(30, seed);
        o.scenario.kind = scenario;
        o.scenario.onset_s = 10;
        o.scenario.duration_s = 12;
        o.output_dir = dir;
        sim::Simulator(o).writeDataset();
      };
      sequences.push_back(s);
    }
  const auto excerpt = pipeline::sequences::realExcerptDir();
  if (!excerpt.empty()) {
    Sequence s;
    s.name = "semi_real_v101_" + secs.str() + "s";
    s.dataset_dir = data + "/" + s.name;
    s.description = "semi-real V1_01 first " + secs.str() + " s from " + excerpt + " png level " +
                    std::to_string(sim::SimulatorOptions{}.png_compression);
    s.render = [dir = s.dataset_dir, excerpt, seconds, data] {
      auto o = pipeline::sequences::semiRealV101(excerpt, data + "/semi_real_csv", seconds);
      o.output_dir = dir;
      sim::Simulator(o).writeDataset();
    };
    sequences.push_back(s);
    Sequence r;
    r.name = "real_v101_excerpt_standing";
    r.dataset_dir = excerpt;
    sequences.push_back(r);
  } else {
    std::cerr << "no $MCVIO_SHARED_DIR/data/euroc_V1_01_excerpt: semi-real and real rows skipped\n";
  }

  const std::string load_before = loadAverage();
  std::vector<std::pair<std::string, nlohmann::json>> rows;
  for (const auto& s : sequences) {
    if (!only.empty()) {
      const auto names = split(only);  // a comma-separated list
      if (std::find(names.begin(), names.end(), s.name) == names.end()) continue;
    }
    ensureRendered(s);
    const std::string out = data + "/run_" + s.name + (pipelined ? "" : "_sequential") +
                            (config.empty() ? "" : "_" + fs::path(config).stem().string());
    std::cerr << s.name << ": running (" << (pipelined ? "pipelined" : "sequential") << "), load " << loadAverage() << "\n";
    if (!inChild([&] { runOne(s, out, pipelined, config); })) {
      std::cerr << s.name << ": run failed\n";
      continue;
    }
    std::ifstream in(out + "/benchmark.json");
    rows.emplace_back(s.name, nlohmann::json::parse(in));
  }

  std::cout << "\n" << (pipelined ? "pipelined" : "sequential") << " runOffline"
            << ", config " << config << "; load average before " << load_before
            << ", after " << loadAverage() << " (2 cores)\n\n";
  std::cout << "| sequence | frames | poses | resets | ATE pos+yaw [m] | ATE SE3 [m] | RPE 1 s [m / deg] | NEES pos (first pose / whole run aligned) "
               "| backend median [ms CPU] | frontend median [ms CPU] | decode median [ms CPU] | wall [s] | CPU [s] "
               "| real-time factor | peak RSS [MB] |\n";
  std::cout << "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  std::cout << std::fixed;
  for (const auto& [name, j] : rows) {
    std::cout << "| " << name << " | " << j["frames"] << " | " << j["poses"] << " | " << j["resets"] << " | "
              << std::setprecision(3) << j["ate_pos_yaw"].get<double>() << " | " << j["ate_se3"].get<double>() << " | "
              << j["rpe_1s"].get<double>() << " / " << std::setprecision(2) << j["rpe_1s_deg"].get<double>() << " | "
              << j["nees"].get<double>() << " / " << j["nees_whole_run_alignment"].get<double>() << " | "
              << std::setprecision(1) << j["backend_ms"].get<double>() << " | "
              << j["frontend_ms"].get<double>() << " | " << j["loader_ms"].get<double>() << " | "
              << j["wall_s"].get<double>() << " | " << j["cpu_s"].get<double>() << " | " << std::setprecision(2)
              << j["realtime"].get<double>() << "x | " << std::setprecision(0) << j["rss_mb"].get<double>() << " |\n";
  }
  bool any_conflict = false;
  for (const auto& [name, j] : rows) any_conflict = any_conflict || j.contains("conflict");
  if (any_conflict) {
    std::cout << "\nMC-VIO (auto) per-frame output, NEES of the position aligned at the first pose (3 = consistent):\n\n"
              << "| sequence | ATE pos+yaw final / per frame [m] | NEES per frame in the conflict, mean / median | "
                 "after it, mean / median | whole run, mean |\n|---|---|---|---|---|\n";
    // A figure without samples is null in the JSON (NaN).
    const auto num = [](const nlohmann::json& v, int digits) {
      if (!v.is_number()) return std::string("n/a");
      std::ostringstream os;
      os << std::fixed << std::setprecision(digits) << v.get<double>();
      return os.str();
    };
    for (const auto& [name, j] : rows) {
      if (!j.contains("conflict")) continue;
      const auto& c = j["conflict"];
      std::cout << "| " << name << " | " << num(j["ate_pos_yaw"], 3) << " / " << num(c["ate_pos_yaw_online"], 3) << " | "
                << num(c["nees_online_in_conflict"], 2) << " / " << num(c["nees_online_in_conflict_median"], 2) << " | "
                << num(c["nees_online_after"], 2) << " / " << num(c["nees_online_after_median"], 2) << " | "
                << num(c["nees_online"], 2) << " |\n";
    }
  }
  return rows.empty() ? 1 : 0;
}
