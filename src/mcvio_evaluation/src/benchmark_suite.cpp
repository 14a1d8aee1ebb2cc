#include "mcvio/evaluation/benchmark_suite.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <mutex>
#include <numeric>
#include <thread>
#include <utility>

#include "mcvio/evaluation/evaluator.hpp"
#include "mcvio/evaluation/mode_run_recorder.hpp"
#include "mcvio/evaluation/report_writer.hpp"
#include "mcvio/evaluation/ride_measurement.hpp"
#include "mcvio/sim/feature_simulator.hpp"

namespace mcvio::evaluation {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kNaN = BenchmarkRun::kNaN;

double secondsSince(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return kNaN;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double mean(const std::vector<double>& v) {
  return v.empty() ? kNaN : std::accumulate(v.begin(), v.end(), 0.0) / double(v.size());
}

std::string formatSeconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", s);
  return buf;
}

const std::vector<std::string> kDetectorColumns = {
    "timestamp_ns",          "state",     "propagated_chi2",   "propagated_threshold", "landmarks_tested",
    "landmarks_inconsistent", "inconsistent_fraction", "coherence", "interval_start_ns", "resolution_mode",
    "interval_onset_ns",     "interval_end_ns", "evidence_score"};

std::string fmt(const char* format, double v) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

}  // namespace

bool BenchmarkChecks::allPass() const {
  for (const auto* c :
       {&ate_reduction, &rpe_reduction, &clean_ate, &detection, &ride_displacement, &secondary_motion, &vehicle_motion,
        &cost})
    if (c->has_value() && !**c) return false;
  return true;
}

const BenchmarkRun* BenchmarkSequenceResult::find(const std::string& mode) const {
  for (const auto& r : runs)
    if (r.mode == mode) return &r;
  return nullptr;
}

BenchmarkSuite::BenchmarkSuite(BenchmarkOptions options) : options_(std::move(options)) { options_.validate(); }

std::vector<BenchmarkSequence> BenchmarkSuite::plan() const {
  std::vector<BenchmarkSequence> plan;
  for (const auto& scenario : options_.scenarios) {
    for (const auto seed : options_.seeds) {
      BenchmarkSequence s;
      s.scenario = scenario;
      s.seed = seed;
      s.duration_s = options_.sequence_duration_s;
      s.onset_s = options_.onset_s;
      s.conflict_duration_s = scenario == "none" ? 0.0 : options_.conflict_duration_s;
      s.name = scenario + "_s" + std::to_string(seed);
      plan.push_back(s);
    }
  }
  for (const auto& scenario : options_.sweep_scenarios) {
    if (options_.sweep_durations_s.empty()) break;
    for (const double d : options_.sweep_durations_s) {
      BenchmarkSequence s;
      s.scenario = scenario;
      s.seed = options_.seeds.front();
      s.onset_s = options_.onset_s;
      s.conflict_duration_s = d;
      s.duration_s = options_.onset_s + d + options_.sweep_tail_s;
      const double speed = scenario == "elevator" ? options_.sweep_elevator_speed_mps : options_.sweep_vehicle_speed_mps;
      // travel 0 would mean "scenario default"; a micrometre keeps the scene with no ride.
      s.travel_m = d > 0 ? speed * d : 1e-6;
      s.sweep = true;
      s.name = "sweep_" + scenario + "_" + formatSeconds(d) + "s_s" + std::to_string(s.seed);
      plan.push_back(s);
    }
  }
  return plan;
}

BenchmarkSequenceResult BenchmarkSuite::runSequence(const BenchmarkSequence& sequence,
                                                    const std::function<void(const std::string&)>& on_run) const {
  sim::SimulatorOptions so;
  so.seed = sequence.seed;
  so.duration_s = sequence.duration_s;
  so.scenario.kind = sim::scenarioKindFromString(sequence.scenario);
  so.scenario.onset_s = sequence.onset_s;
  so.scenario.duration_s = sequence.conflict_duration_s;
  so.scenario.travel_m = sequence.travel_m;
  so.validate();
  const auto t_sim = Clock::now();
  sim::FeatureSequence seq = sim::simulateFeatureSequence(so, options_.features);
  const double simulate_s = secondsSince(t_sim);
  if (!options_.oracle_track_labels) {
    for (auto& f : seq.frames)
      for (auto& o : f.features) o.label = TrackLabel::kUnknown;
  }
  std::vector<StampedPose> gt_poses;
  gt_poses.reserve(seq.ground_truth.size());
  for (const auto& g : seq.ground_truth) {
    if (!gt_poses.empty() && g.t <= gt_poses.back().t) continue;
    gt_poses.push_back({g.t, g.p_WB, g.q_WB.normalized()});
  }
  const Trajectory ground_truth(std::move(gt_poses), sequence.name + " ground truth");
  const ConflictLabelTimeline labels(seq.labels, sequence.name + " labels");

  // The modes' estimators take each frame in turn, so that their CPU per frame is measured under
  // the same host load.
  const std::vector<BenchmarkModeRun> runs =
      ModeRunRecorder::runInTurn(seq, options_.modes, options_.estimator, options_.features.pixel_noise_sigma);
  for (const auto& run : runs) {
    if (!on_run) break;
    std::string line = sequence.name + " " + run.mode + ": " + std::to_string(run.estimate.size()) + "/" +
                       std::to_string(run.frames) + " frames tracked";
    if (run.estimate.size() >= 2) {
      const AteResult quick = computeAte(run.estimate, ground_truth, Alignment::kPositionYaw);
      line += ", ATE pos+yaw " + fmt("%.3f", quick.translation.rmse) + " m";
    }
    line += ", " + fmt("%.2f", median(run.cpu_ms)) + " ms/frame, " + fmt("%.1f", run.wall_s) + " s";
    on_run(line);
  }
  BenchmarkSequenceResult result = evaluateSequence(sequence, ground_truth, labels, runs, options_);
  result.frames = seq.frames.size();
  result.simulate_s = simulate_s;
  return result;
}

BenchmarkSequenceResult BenchmarkSuite::evaluateSequence(const BenchmarkSequence& sequence, const Trajectory& ground_truth,
                                                         const ConflictLabelTimeline& labels,
                                                         const std::vector<BenchmarkModeRun>& runs,
                                                         const BenchmarkOptions& options) {
  BenchmarkSequenceResult result;
  result.sequence = sequence;
  result.frames = labels.labels().size();
  result.conflict_frames = labels.conflictFrames();
  const double label_tolerance_s = 0.02;

  EvaluationOptions eo;
  eo.baseline = "reference";
  eo.rpe_delta_s = options.rpe_delta_s;
  eo.detection.label_tolerance_s = label_tolerance_s;
  // A mode that never tracked has no poses; the Evaluator needs every estimate to have some.
  std::vector<EstimateInput> evaluable;
  for (const auto& run : runs) {
    if (run.estimate.size() < 2) continue;
    EstimateInput in;
    in.name = run.mode;
    in.trajectory = run.estimate;
    if (run.estimate_online.size() >= 2) in.online_trajectory = run.estimate_online;
    in.detector = DetectorLog(run.detector, kDetectorColumns, run.mode);
    evaluable.push_back(std::move(in));
  }
  std::optional<EvaluationReport> report;
  if (std::any_of(evaluable.begin(), evaluable.end(), [](const EstimateInput& e) { return e.name == "reference"; }))
    report = Evaluator(eo).evaluate(ground_truth, evaluable, labels);

  const bool elevator = sequence.scenario == "elevator" && sequence.hasConflict();
  const bool vehicle = sequence.scenario == "vehicle" && sequence.hasConflict();
  for (const auto& pass : runs) {
    BenchmarkRun run;
    run.mode = pass.mode;
    run.frames = pass.frames;
    run.tracked_frames = pass.estimate.size();
    run.resets = pass.resets;
    run.wall_s = pass.wall_s;
    run.cpu_median_ms = median(pass.cpu_ms);
    run.cpu_mean_ms = mean(pass.cpu_ms);
    run.conflict_mean_ms = mean(pass.conflict_ms);
    const EstimateEvaluation* e = report ? report->find(run.mode) : nullptr;
    if (e) {
      run.ate_posyaw_m = e->ate_posyaw.translation.rmse;
      run.ate_posyaw_online_m = e->onlineAtePosYawRmse();
      run.ate_se3_m = e->ate_se3.translation.rmse;
      if (e->has_conflict_split) run.ate_posyaw_in_conflict_m = e->ate_posyaw_in_conflict.rmse;
      run.rpe_translation_m = e->rpe_time.translation.rmse;
      run.rpe_rotation_deg = e->rpe_time.rotation.rmse;
      if (e->detection) {
        const auto& d = *e->detection;
        run.tp = d.counts.tp;
        run.fp = d.counts.fp;
        run.tn = d.counts.tn;
        run.fn = d.counts.fn;
        run.tpr = d.counts.tpr();
        run.fpr = d.counts.fpr();
        if (d.has_hindsight) {
          run.hindsight_tpr = d.hindsight.tpr();
          run.hindsight_fpr = d.hindsight.fpr();
        }
        const IntervalDetection span = d.labelledSpan();
        run.onset_delay_s = span.onset_delay_s;
        run.release_lag_s = span.release_lag_s;
        for (const auto& roc : d.roc) {
          if (roc.score == "propagated_chi2_ratio") run.auc_propagated = roc.auc;
          if (roc.score == "inconsistent_fraction") run.auc_fraction = roc.auc;
          if (roc.score == "evidence_score") run.auc_evidence = roc.auc;
          if (roc.positives == 0 || roc.negatives == 0) continue;
          for (const auto& p : roc.points) {
            if (p.fpr <= options.targets.max_fpr && (!std::isfinite(run.roc_best_tpr) || p.tpr > run.roc_best_tpr)) {
              run.roc_best_tpr = p.tpr;
              run.roc_best_score = roc.score;
            }
          }
        }
      }
    }
    if (elevator || vehicle) {
      // The vehicle's travel needs the alignment's yaw; the elevator's heights do not.
      const Eigen::Matrix3d R_gt_est = e ? Eigen::Matrix3d(e->ate_posyaw.T_gt_est.linear()) : Eigen::Matrix3d::Identity();
      const RideMeasurement ride =
          RideMeasurement::measure(pass.estimate, pass.secondary, ground_truth, labels, R_gt_est, label_tolerance_s);
      if (elevator) {
        run.ride_truth_dz_m = ride.truth_dz_m;
        run.ride_estimate_dz_m = ride.estimate_dz_m;
        run.ride_error_percent = ride.dz_error_percent;
        run.secondary_dz_m = ride.secondary_dz_m;
        run.secondary_error_percent = ride.secondary_dz_error_percent;
      } else if (e) {
        run.travel_truth_m = ride.travel_truth_m;
        run.secondary_travel_m = ride.secondary_travel_m;
        run.secondary_travel_error_percent = ride.secondary_travel_error_percent;
      }
    }
    result.runs.push_back(run);
  }

  if (const BenchmarkRun* ref = result.find("reference")) {
    const double base = ref->cpu_mean_ms - (std::isfinite(ref->conflict_mean_ms) ? ref->conflict_mean_ms : 0.0);
    for (auto& run : result.runs) {
      run.ate_reduction_percent = ReportWriter::relativeReduction(ref->ate_posyaw_m, run.ate_posyaw_m);
      run.ate_in_conflict_reduction_percent =
          ReportWriter::relativeReduction(ref->ate_posyaw_in_conflict_m, run.ate_posyaw_in_conflict_m);
      run.rpe_reduction_percent = ReportWriter::relativeReduction(ref->rpe_translation_m, run.rpe_translation_m);
      if (std::isfinite(base) && base > 0 && std::isfinite(run.cpu_mean_ms))
        run.added_cost_percent = 100.0 * (run.cpu_mean_ms - base) / base;
    }
  }
  return result;
}

BenchmarkResult BenchmarkSuite::run(const Progress& progress) const {
  const auto t0 = Clock::now();
  const std::vector<BenchmarkSequence> sequences = plan();
  BenchmarkResult result;
  result.options = options_;
  result.sequences.resize(sequences.size());
  const std::size_t total = sequences.size() * options_.modes.size();
  std::atomic<std::size_t> next{0};
  std::size_t done = 0;
  std::mutex mutex;
  std::exception_ptr error;
  auto worker = [&] {
    for (;;) {
      const std::size_t i = next++;
      if (i >= sequences.size()) return;
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (error) return;
      }
      try {
        result.sequences[i] = runSequence(sequences[i], [&](const std::string& line) {
          std::lock_guard<std::mutex> lock(mutex);
          ++done;
          if (progress) progress(done, total, line);
        });
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error) error = std::current_exception();
        return;
      }
    }
  };
  const int jobs = std::min<int>(options_.jobs, int(sequences.size()));
  if (jobs <= 1) {
    worker();
  } else {
    std::vector<std::thread> threads;
    for (int j = 0; j < jobs; ++j) threads.emplace_back(worker);
    for (auto& t : threads) t.join();
  }
  if (error) std::rethrow_exception(error);
  applyTargets(result);
  result.wall_s = secondsSince(t0);
  return result;
}

void BenchmarkSuite::applyTargets(BenchmarkResult& result) {
  const BenchmarkTargets& t = result.options.targets;
  using Applies = std::function<bool(const BenchmarkSequenceResult&)>;
  const Applies conflict = [](const BenchmarkSequenceResult& s) { return s.sequence.hasConflict() && s.conflict_frames > 0; };
  const Applies clean = [](const BenchmarkSequenceResult& s) { return s.sequence.scenario == "none"; };
  const Applies every = [](const BenchmarkSequenceResult&) { return true; };
  const Applies elevator = [conflict](const BenchmarkSequenceResult& s) {
    return s.sequence.scenario == "elevator" && conflict(s);
  };
  const Applies vehicle = [conflict](const BenchmarkSequenceResult& s) {
    return s.sequence.scenario == "vehicle" && conflict(s);
  };
  struct Spec {
    std::string name;
    Applies applies;
    std::function<double(const BenchmarkRun&)> value;
    bool higher_is_better;
    double threshold;
  };
  auto pct = [](double v) { return fmt("%g", v); };
  const std::vector<Spec> specs = {
      {"conflict ATE reduction >= " + pct(t.conflict_ate_reduction_percent) + "%", conflict,
       [](const BenchmarkRun& r) { return r.ate_reduction_percent; }, true, t.conflict_ate_reduction_percent},
      {"conflict RPE reduction >= " + pct(t.conflict_rpe_reduction_percent) + "%", conflict,
       [](const BenchmarkRun& r) { return r.rpe_reduction_percent; }, true, t.conflict_rpe_reduction_percent},
      {"clean ATE increase <= " + pct(t.clean_max_ate_increase_percent) + "%", clean,
       [](const BenchmarkRun& r) { return -r.ate_reduction_percent; }, false, t.clean_max_ate_increase_percent},
      {"detection TPR >= " + pct(t.min_tpr) + " (conflict sequences)", conflict,
       [](const BenchmarkRun& r) { return r.tpr; }, true, t.min_tpr},
      {"detection FPR <= " + pct(t.max_fpr) + " (all sequences)", every,
       [](const BenchmarkRun& r) { return r.fpr; }, false, t.max_fpr},
      {"elevator ride displacement error <= " + pct(t.ride_displacement_tolerance_percent) + "%", elevator,
       [](const BenchmarkRun& r) { return r.ride_error_percent; }, false, t.ride_displacement_tolerance_percent},
      {"elevator cabin (secondary) motion error <= " + pct(t.secondary_motion_tolerance_percent) + "%", elevator,
       [](const BenchmarkRun& r) { return r.secondary_error_percent; }, false, t.secondary_motion_tolerance_percent},
      {"vehicle (secondary) motion error <= " + pct(t.secondary_motion_tolerance_percent) + "%", vehicle,
       [](const BenchmarkRun& r) { return r.secondary_travel_error_percent; }, false, t.secondary_motion_tolerance_percent},
      {"added backend CPU <= " + pct(t.max_added_cost_percent) + "%", every,
       [](const BenchmarkRun& r) { return r.added_cost_percent; }, false, t.max_added_cost_percent},
      // The same detection targets against the conflict intervals in hindsight (onset where the
      // evidence built up, end at the last evidence); reported, the per-run checks stay online.
      {"detection TPR in hindsight >= " + pct(t.min_tpr) + " (conflict sequences)", conflict,
       [](const BenchmarkRun& r) { return r.hindsight_tpr; }, true, t.min_tpr},
      {"detection FPR in hindsight <= " + pct(t.max_fpr) + " (all sequences)", every,
       [](const BenchmarkRun& r) { return r.hindsight_fpr; }, false, t.max_fpr},
  };
  auto passes = [](const Spec& spec, double v) {
    return std::isfinite(v) && (spec.higher_is_better ? v >= spec.threshold : v <= spec.threshold);
  };

  // Per run: the targets that apply (the sweep is reported as a curve, not checked).
  for (auto& sr : result.sequences) {
    for (auto& r : sr.runs) {
      BenchmarkChecks c;
      if (r.mode != "reference" && !sr.sequence.sweep) {
        auto check = [&](const Spec& spec) -> std::optional<bool> {
          if (!spec.applies(sr)) return std::nullopt;
          return passes(spec, spec.value(r));
        };
        c.ate_reduction = check(specs[0]);
        c.rpe_reduction = check(specs[1]);
        c.clean_ate = check(specs[2]);
        const auto tpr_ok = check(specs[3]);
        const auto fpr_ok = check(specs[4]);
        c.detection = fpr_ok.value_or(true) && tpr_ok.value_or(true);
        c.ride_displacement = check(specs[5]);
        c.secondary_motion = check(specs[6]);
        c.vehicle_motion = check(specs[7]);
        c.cost = check(specs[8]);
      }
      r.checks = c;
    }
  }

  // Per target and mode: how many runs pass, and the least favourable one (unmeasured first).
  result.targets.clear();
  for (const auto& spec : specs) {
    for (const auto& mode : result.options.modes) {
      if (mode == "reference") continue;
      BenchmarkTargetSummary sum;
      sum.target = spec.name;
      sum.mode = mode;
      for (const auto& sr : result.sequences) {
        if (sr.sequence.sweep || !spec.applies(sr)) continue;
        const BenchmarkRun* r = sr.find(mode);
        if (!r) continue;
        const double v = spec.value(*r);
        ++sum.total;
        if (passes(spec, v)) ++sum.passed;
        const bool have = !sum.worst_sequence.empty();
        const bool worse = !have || (std::isfinite(sum.worst) &&
                                     (!std::isfinite(v) || (spec.higher_is_better ? v < sum.worst : v > sum.worst)));
        if (worse) {
          sum.worst = v;
          sum.worst_sequence = sr.sequence.name;
        }
      }
      if (sum.total > 0) result.targets.push_back(sum);
    }
  }
}

}  // namespace mcvio::evaluation
