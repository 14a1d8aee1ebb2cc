// Feature-level motion-conflict check: mcvio_sim's FeatureSimulator with a scenario -> estimator in
// a resolution mode; prints ATE (pos+yaw), ATE inside labelled conflict, per-frame detection
// TPR/FPR, the elevator's vertical displacement, and optionally a per-frame CSV.
//   [MCVIO_ESTIMATOR_CONFIG=options.yaml] conflict_check SCENARIO MODE [duration_s] [seed] [csv|-] [onset_s] [conflict_s]
//   [travel_m]   (travel as `mcvio bench`'s duration sweep sets it: 0.8 m/s x conflict_s elevator, 4 m/s vehicle)
// Environment: MCVIO_CLEAR_TRACK_LABELS=1 (no oracle labels, as `mcvio bench`), MCVIO_REIDENTIFY=p
// (re-identifying frontend model), MCVIO_DUMP_REVISIONS=file (the conflict window's revisions),
// MCVIO_DUMP_ERRORS=file (t, aligned position error xyz, label per frame).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "mcvio/estimator/sliding_window_estimator.hpp"
#include "mcvio/sim/feature_simulator.hpp"

using namespace mcvio;

namespace {

struct Align {
  Eigen::Matrix3d R;
  Eigen::Vector3d me, mg;
};

Align align4(const std::vector<Eigen::Vector3d>& est, const std::vector<Eigen::Vector3d>& gt) {
  const std::size_t n = est.size();
  Align a;
  a.me.setZero();
  a.mg.setZero();
  for (std::size_t i = 0; i < n; ++i) {
    a.me += est[i];
    a.mg += gt[i];
  }
  a.me /= double(n);
  a.mg /= double(n);
  double sn = 0, cs = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d e = est[i] - a.me, g = gt[i] - a.mg;
    sn += e.x() * g.y() - e.y() * g.x();
    cs += e.x() * g.x() + e.y() * g.y();
  }
  a.R = Eigen::AngleAxisd(std::atan2(sn, cs), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: conflict_check SCENARIO MODE [duration_s] [seed] [csv] [onset] [conflict_s] [travel_m]\n");
    return 2;
  }
  sim::SimulatorOptions so;
  so.scenario.kind = sim::scenarioKindFromString(argv[1]);
  so.duration_s = argc > 3 ? std::atof(argv[3]) : 60.0;
  so.seed = argc > 4 ? std::atoi(argv[4]) : 1;
  if (argc > 6) so.scenario.onset_s = std::atof(argv[6]);
  if (argc > 7) so.scenario.duration_s = std::atof(argv[7]);
  if (argc > 8) so.scenario.travel_m = std::atof(argv[8]);
  sim::FeatureSimulatorOptions fo;
  // A frontend that re-identifies lost landmarks, with this probability (FeatureSimulatorOptions).
  if (const char* reid = std::getenv("MCVIO_REIDENTIFY")) fo.reidentify_probability = std::atof(reid);
  auto seq = sim::simulateFeatureSequence(so, fo);
  {  // Tracks that came back: seen before, not in the previous frame (re-identified).
    std::set<std::uint64_t> seen, prev;
    int back = 0, fresh = 0;
    for (const auto& f : seq.frames) {
      std::set<std::uint64_t> cur;
      for (const auto& o : f.features)
        if (o.camera_index == 0) cur.insert(o.track_id);
      for (auto id : cur)
        if (prev.count(id) == 0) ++(seen.count(id) != 0 ? back : fresh);
      seen.insert(cur.begin(), cur.end());
      prev = std::move(cur);
    }
    std::printf("tracks: %d new, %d re-identified\n", fresh, back);
  }
  // The same observations without re-identification: a returning track gets a new id.
  if (const char* forget = std::getenv("MCVIO_FORGET_REID"); forget != nullptr && std::string(forget) == "1") {
    std::set<std::uint64_t> seen, prev;
    std::map<std::uint64_t, std::uint64_t> renamed;
    std::uint64_t next = 1ull << 40;
    for (auto& f : seq.frames) {
      std::set<std::uint64_t> cur;
      for (const auto& o : f.features)
        if (o.camera_index == 0) cur.insert(o.track_id);
      for (auto id : cur)
        if (prev.count(id) == 0 && seen.count(id) != 0) renamed[id] = next++;
        else if (prev.count(id) == 0) renamed.erase(id);
      for (auto& o : f.features) {
        const auto it = renamed.find(o.track_id);
        if (it != renamed.end()) o.track_id = it->second;
      }
      seen.insert(cur.begin(), cur.end());
      prev = std::move(cur);
    }
  }
  // cam0 tracks on a moving body per frame (the simulator's oracle labels), for the CSV.
  std::vector<int> moving_tracks;
  for (const auto& f : seq.frames)
    moving_tracks.push_back(int(std::count_if(f.features.begin(), f.features.end(), [](const FeatureObservation& o) {
      return o.camera_index == 0 && o.label == TrackLabel::kInconsistent;
    })));
  // As `mcvio bench` runs it (no oracle frontend): MCVIO_CLEAR_TRACK_LABELS=1.
  if (const char* clear = std::getenv("MCVIO_CLEAR_TRACK_LABELS"); clear != nullptr && std::string(clear) == "1")
    for (auto& f : seq.frames)
      for (auto& o : f.features) o.label = TrackLabel::kUnknown;
  estimator::EstimatorOptions eo;
  eo.observation_sigma_px = fo.pixel_noise_sigma;
  eo.conflict.mode = conflict::resolutionModeFromString(argv[2]);
  // Optional estimator options (e.g. conflict thresholds to try); the mode argument wins.
  if (const char* cfg = std::getenv("MCVIO_ESTIMATOR_CONFIG")) {
    eo = estimator::EstimatorOptions::fromYamlFile(cfg);
    eo.observation_sigma_px = fo.pixel_noise_sigma;  // as mcvio bench: the simulator's pixel noise
    eo.conflict.mode = conflict::resolutionModeFromString(argv[2]);
  }
  estimator::SlidingWindowEstimator est(eo, seq.calibration);
  std::ofstream csv;
  if (argc > 5 && std::string(argv[5]) != "-") csv.open(argv[5]);
  if (csv) csv << "t,state,chi2,tested,inconsistent,fraction,coherence,label,px,py,pz,gx,gy,gz,sec_valid,sz,bax,bay,baz,vx,vy,vz,drift,moving,split,score,tbax,tbay,tbaz,tvz,qerr_deg,residuals,landmarks,tilt_deg,tiltx,tilty,bgx,bgy,bgz,tbgx,tbgy,tbgz\n";
  std::size_t k = 0, g = 0, li = 0;
  std::vector<Eigen::Vector3d> pe, pg;
  std::vector<Timestamp> pt;
  double max_revision = 0;
  std::vector<char> in_conf;
  std::vector<double> cpu;
  int tp = 0, fn = 0, fp = 0, tn = 0;
  double sec_z_end = 0, gt_z_start = 0, gt_z_end = 0, est_z_start = 0, est_z_end = 0;
  bool seen_conflict = false;
  int invalid_covariance = 0;
  double max_sigma = 0;
  for (std::size_t fi = 0; fi < seq.frames.size(); ++fi) {
    const auto& f = seq.frames[fi];
    while (k < seq.imu.size() && seq.imu[k].t <= f.t) est.addImu(seq.imu[k++]);
    const auto out = est.addFrame(f);
    while (li + 1 < seq.labels.size() && seq.labels[li].t < f.t) ++li;
    const bool label = li < seq.labels.size() && seq.labels[li].t == f.t && seq.labels[li].in_conflict;
    if (!out.frame_accepted || out.status != estimator::EstimatorStatus::kTracking) continue;
    while (g + 1 < seq.ground_truth.size() && seq.ground_truth[g].t < f.t) ++g;
    if (seq.ground_truth[g].t != f.t) continue;
    const bool detected = out.conflict.state == estimator::ConflictReport::State::kConflict;
    (label ? (detected ? tp : fn) : (detected ? fp : tn))++;
    pe.push_back(out.p_WB);
    pt.push_back(f.t);
    // The conflict window re-estimates earlier frames: score the final trajectory, as mcvio bench does.
    for (const auto& rev : out.revised_poses) {
      const auto it = std::lower_bound(pt.begin(), pt.end(), rev.t);
      if (it == pt.end() || *it != rev.t) continue;
      const std::size_t i = static_cast<std::size_t>(it - pt.begin());
      max_revision = std::max(max_revision, (rev.p_WB - pe[i]).norm());
      if (const char* dump = std::getenv("MCVIO_DUMP_REVISIONS")) {
        static std::ofstream d(dump);
        d << rev.t << ' ' << pe[i].transpose() << ' ' << rev.p_WB.transpose() << ' ' << pg[i].transpose() << '\n';
      }
      pe[i] = rev.p_WB;
    }
    if (!out.revised_poses.empty() && std::getenv("MCVIO_PRINT_REVISIONS") != nullptr)
      std::printf("  t %.2f s: %zu poses revised, largest move so far %.3f m\n",
                  static_cast<double>(f.t - seq.frames.front().t) * 1e-9, out.revised_poses.size(), max_revision);
    pg.push_back(seq.ground_truth[g].p_WB);
    in_conf.push_back(label ? 1 : 0);
    cpu.push_back(out.timings.cpu_total_ms);
    if (out.covariance_valid)
      max_sigma = std::max(max_sigma, std::sqrt(out.pose_covariance.topLeftCorner<3, 3>().diagonal().maxCoeff()));
    else
      ++invalid_covariance;
    if (label && !seen_conflict) {
      seen_conflict = true;
      gt_z_start = seq.ground_truth[g].p_WB.z();
      est_z_start = out.p_WB.z();
    }
    if (label) {
      gt_z_end = seq.ground_truth[g].p_WB.z();
      est_z_end = out.p_WB.z();
      if (out.conflict.secondary_valid) sec_z_end = out.conflict.p_WS.z();
    }
    const auto& gt = seq.ground_truth[g];
    // Tilt error: the estimated and true "up" in the body, and the estimated one in the true world
    // frame (its horizontal part times g is the gravity the tilt leaks sideways).
    const Eigen::Vector3d up_est_B = out.q_WB.conjugate() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d up_true_B = gt.q_WB.conjugate() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d up_est_W = gt.q_WB * up_est_B;
    if (csv)
      csv << f.t << ',' << int(out.conflict.state) << ',' << out.conflict.propagated_chi2 << ','
          << out.conflict.landmarks_tested << ',' << out.conflict.landmarks_inconsistent << ','
          << out.conflict.inconsistent_fraction << ',' << out.conflict.coherence << ',' << int(label) << ','
          << out.p_WB.x() << ',' << out.p_WB.y() << ',' << out.p_WB.z() << ',' << seq.ground_truth[g].p_WB.x() << ','
          << seq.ground_truth[g].p_WB.y() << ',' << seq.ground_truth[g].p_WB.z() << ','
          << int(out.conflict.secondary_valid) << ',' << out.conflict.p_WS.z() << ',' << out.bias.accel.x() << ','
          << out.bias.accel.y() << ',' << out.bias.accel.z() << ',' << out.v_WB.x() << ',' << out.v_WB.y() << ','
          << out.v_WB.z() << ',' << out.conflict.accel_bias_drift << ',' << moving_tracks[fi] << ','
          << out.conflict.split_chi2 << ',' << out.conflict.evidence_score << ',' << gt.bias_accel.x() << ','
          << gt.bias_accel.y() << ',' << gt.bias_accel.z() << ',' << gt.v_WB.z() << ','
          << Eigen::AngleAxisd(gt.q_WB.conjugate() * out.q_WB).angle() * 180.0 / M_PI << ','
          << out.num_visual_residuals << ',' << out.num_landmarks << ','
          << std::acos(std::clamp(up_est_B.dot(up_true_B), -1.0, 1.0)) * 180.0 / M_PI << ',' << up_est_W.x() << ','
          << up_est_W.y() << ',' << out.bias.gyro.x() << ',' << out.bias.gyro.y() << ','
          << out.bias.gyro.z() << ',' << gt.bias_gyro.x() << ',' << gt.bias_gyro.y() << ',' << gt.bias_gyro.z() << '\n';
  }
  const auto a = align4(pe, pg);
  double sq = 0, sqc = 0;
  int nc = 0;
  std::ofstream errors;
  if (const char* path = std::getenv("MCVIO_DUMP_ERRORS")) errors.open(path);
  for (std::size_t i = 0; i < pe.size(); ++i) {
    const Eigen::Vector3d e = a.R * (pe[i] - a.me) + a.mg - pg[i];
    if (errors) errors << pt[i] << ' ' << e.transpose() << ' ' << int(in_conf[i]) << '\n';
    const double e2 = e.squaredNorm();
    sq += e2;
    if (in_conf[i]) {
      sqc += e2;
      ++nc;
    }
  }
  std::sort(cpu.begin(), cpu.end());
  std::printf("%s %s %.0fs seed %llu: tracked %zu resets %d ATE %.4f m ATE-in-conflict %.4f m (%d frames) "
              "TPR %.3f FPR %.4f (tp %d fn %d fp %d tn %d) median cpu %.2f ms\n",
              argv[1], argv[2], so.duration_s, (unsigned long long)so.seed, pe.size(), est.resetCount(),
              std::sqrt(sq / double(pe.size())), nc ? std::sqrt(sqc / nc) : 0.0, nc, tp + fn ? double(tp) / (tp + fn) : 0.0,
              fp + tn ? double(fp) / (fp + tn) : 0.0, tp, fn, fp, tn, cpu.empty() ? 0.0 : cpu[cpu.size() / 2]);
  std::printf("  pose covariance: %d frames singular or not finite, largest position sigma %.3f m\n",
              invalid_covariance, max_sigma);
  std::printf("  conflict-window revisions: largest move of a past pose %.3f m\n", max_revision);
  if (seen_conflict)
    std::printf("  vertical displacement during the labelled conflict: truth %.3f m, estimate %.3f m, secondary z %.3f m\n",
                gt_z_end - gt_z_start, est_z_end - est_z_start, sec_z_end);
  return 0;
}
