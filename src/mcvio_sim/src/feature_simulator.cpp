#include "mcvio/sim/feature_simulator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <yaml-cpp/yaml.h>

#include "mcvio/sim/simulator.hpp"
#include "mcvio/core/yaml_fields.hpp"
#include "mcvio/core/yaml_file.hpp"

namespace mcvio::sim {
namespace {

struct Track {
  std::uint64_t id;
  std::size_t landmark;
};

struct LostTrack {
  Track track;
  Timestamp since;  ///< when it ended
};
constexpr Timestamp kNeverTracked = std::numeric_limits<Timestamp>::min();

}  // namespace

FeatureSimulatorOptions FeatureSimulatorOptions::fromYaml(const YAML::Node& node) {
  FeatureSimulatorOptions o;
  YamlFields f(node, "features.");
  f.get("target_tracks", &o.target_tracks);
  f.get("mean_track_length", &o.mean_track_length);
  f.get("pixel_noise_sigma", &o.pixel_noise_sigma);
  f.get("landmark_density", &o.landmark_density);
  f.get("min_landmarks_per_body", &o.min_landmarks_per_body);
  f.get("grid_cols", &o.grid_cols);
  f.get("grid_rows", &o.grid_rows);
  f.get("image_border_px", &o.image_border_px);
  f.get("max_depth_m", &o.max_depth_m);
  f.get("reidentify_probability", &o.reidentify_probability);
  f.get("reidentify_min_age_s", &o.reidentify_min_age_s);
  f.get("reidentify_max_age_s", &o.reidentify_max_age_s);
  f.rejectUnknown();
  o.validate();
  return o;
}

void FeatureSimulatorOptions::validate() const {
  auto need = [](bool ok, const char* key, const char* rule) {
    if (!ok) throw InputError(std::string("option 'features.") + key + "' " + rule);
  };
  need(target_tracks >= 1 && target_tracks <= 5000, "target_tracks", "must be in [1, 5000]");
  need(mean_track_length >= 1, "mean_track_length", "must be at least 1 frame");
  need(pixel_noise_sigma >= 0 && pixel_noise_sigma < 20, "pixel_noise_sigma", "must be in [0, 20)");
  need(landmark_density > 0 && landmark_density <= 1000, "landmark_density", "must be in (0, 1000]");
  need(min_landmarks_per_body >= 0 && min_landmarks_per_body <= 100000, "min_landmarks_per_body",
       "must be in [0, 100000]");
  need(grid_cols >= 1 && grid_cols <= 64, "grid_cols", "must be in [1, 64]");
  need(grid_rows >= 1 && grid_rows <= 64, "grid_rows", "must be in [1, 64]");
  need(image_border_px >= 0 && image_border_px < 100, "image_border_px", "must be in [0, 100)");
  need(max_depth_m > 0.5, "max_depth_m", "must be above 0.5");
  need(reidentify_probability >= 0 && reidentify_probability <= 1, "reidentify_probability", "must be in [0, 1]");
  need(reidentify_max_age_s > 0 && reidentify_max_age_s <= 600, "reidentify_max_age_s", "must be in (0, 600]");
  need(reidentify_min_age_s >= 0 && reidentify_min_age_s < reidentify_max_age_s, "reidentify_min_age_s",
       "must be >= 0 and below reidentify_max_age_s");
}

FeatureSimulator::FeatureSimulator(SimulatorOptions sim, FeatureSimulatorOptions features)
    : sim_(std::move(sim)), features_(features) {
  sim_.validate();
  features_.validate();
}

FeatureSequence FeatureSimulator::run() const {
  const Simulator sim(sim_);
  const Scene& scene = sim.world().scene;
  const FeatureSimulatorOptions& fo = features_;
  std::mt19937_64 rng(sim_.seed * 0x2545F4914F6CDD1DULL + 17);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> normal(0.0, 1.0);

  // Landmarks scattered over every surface, in the coordinates of their body.
  std::vector<LandmarkTruth> landmarks;
  for (int b = 0; b < static_cast<int>(scene.bodies().size()); ++b) {
    const SceneBody& body = scene.body(b);
    double area = 0;
    for (const auto& q : body.quads) area += q.size_u * q.size_v;
    if (area <= 0) continue;
    const double count = std::min(60000.0, std::max(fo.landmark_density * area,
                                                    static_cast<double>(fo.min_landmarks_per_body)));
    for (const auto& q : body.quads) {
      const double expected = count * q.size_u * q.size_v / area;
      int n = static_cast<int>(expected);
      if (unit(rng) < expected - n) ++n;
      for (int k = 0; k < n; ++k) {
        LandmarkTruth l;
        l.body = b;
        l.p_body = q.origin + unit(rng) * q.size_u * q.axis_u + unit(rng) * q.size_v * q.axis_v;
        l.static_in_world = body.motion == BodyMotion::kStatic;
        landmarks.push_back(l);
      }
    }
  }

  FeatureSequence out;
  out.calibration = sim.calibration();
  out.imu = sim.imu();
  out.ground_truth = sim.groundTruth();
  if (landmarks.empty()) return out;

  const StereoRigCalibration& rig = sim.calibration();
  const int cells = fo.grid_cols * fo.grid_rows;
  const int cell_cap = (fo.target_tracks + cells - 1) / cells + 1;
  const double end_probability = 1.0 / fo.mean_track_length;
  std::vector<Track> tracks;
  // Each landmark's last track and when it ended, for re-identification.
  std::vector<LostTrack> lost_track(landmarks.size(), LostTrack{{0, 0}, kNeverTracked});
  std::mt19937_64 reid_rng(sim_.seed * 0x9E3779B97F4A7C15ULL + 29);
  std::uniform_real_distribution<double> reidentify(0.0, 1.0);
  const Timestamp min_age = fromSeconds(fo.reidentify_min_age_s), max_age = fromSeconds(fo.reidentify_max_age_s);
  std::vector<char> tracked(landmarks.size(), 0);
  std::uniform_int_distribution<std::size_t> pick(0, landmarks.size() - 1);

  for (std::size_t k = 0; k < sim.frameTimes().size(); ++k) {
    const Timestamp t = sim.frameTimes()[k];
    const Eigen::Isometry3d T_WB = sim.bodyPose(t);
    std::vector<Eigen::Isometry3d> body_pose(scene.bodies().size());
    std::vector<char> body_visible(scene.bodies().size());
    for (int b = 0; b < static_cast<int>(body_pose.size()); ++b) {
      body_pose[static_cast<size_t>(b)] = scene.bodyPose(b, t, T_WB);
      body_visible[static_cast<size_t>(b)] = scene.visible(b, t);
    }
    Eigen::Isometry3d T_CW[2], T_WC[2];
    for (int c = 0; c < 2; ++c) {
      T_WC[c] = T_WB * rig.camera(c).T_BC;
      T_CW[c] = T_WC[c].inverse();
    }
    // Pixel of landmark i in camera c if it is in the image, in range and not occluded.
    auto observe = [&](std::size_t i, int c, Eigen::Vector2d* px) {
      const LandmarkTruth& l = landmarks[i];
      if (!body_visible[static_cast<size_t>(l.body)]) return false;
      const Eigen::Vector3d p_w = body_pose[static_cast<size_t>(l.body)] * l.p_body;
      const Eigen::Vector3d p_c = T_CW[c] * p_w;
      if (p_c.z() < 0.1 || p_c.norm() > fo.max_depth_m) return false;
      if (!rig.camera(c).model.project(p_c, px) || !rig.camera(c).model.isInImage(*px, fo.image_border_px))
        return false;
      const Eigen::Vector3d origin = T_WC[c].translation();
      const double dist = (p_w - origin).norm();
      const double hit = scene.castRay(origin, (p_w - origin) / dist, t, T_WB);
      return hit >= dist - 1e-4 * std::max(1.0, dist);
    };
    auto cellOf = [&](const Eigen::Vector2d& px) {
      const int cx = std::clamp(static_cast<int>(px.x() * fo.grid_cols / rig.cam0.model.width()), 0, fo.grid_cols - 1);
      const int cy = std::clamp(static_cast<int>(px.y() * fo.grid_rows / rig.cam0.model.height()), 0, fo.grid_rows - 1);
      return cy * fo.grid_cols + cx;
    };

    std::vector<int> cell_count(static_cast<size_t>(cells), 0);
    std::vector<std::pair<Track, Eigen::Vector2d>> alive;
    for (const Track& tr : tracks) {
      Eigen::Vector2d px;
      if (unit(rng) < end_probability || !observe(tr.landmark, 0, &px)) {
        tracked[tr.landmark] = 0;
        lost_track[tr.landmark] = {tr, t};
        continue;
      }
      ++cell_count[static_cast<size_t>(cellOf(px))];
      alive.emplace_back(tr, px);
    }
    int attempts = 60 * std::max(0, fo.target_tracks - static_cast<int>(alive.size()));
    while (static_cast<int>(alive.size()) < fo.target_tracks && attempts-- > 0) {
      const std::size_t i = pick(rng);
      if (tracked[i]) continue;
      Eigen::Vector2d px;
      if (!observe(i, 0, &px)) continue;
      const int cell = cellOf(px);
      if (cell_count[static_cast<size_t>(cell)] >= cell_cap) continue;
      ++cell_count[static_cast<size_t>(cell)];
      tracked[i] = 1;
      // Detected again: recognised (its old id back) or a new track. Its own random stream, so
      // that the observations do not depend on reidentify_probability, only the ids.
      const LostTrack& lost = lost_track[i];
      const bool recognised = lost.since != kNeverTracked && lost.since <= t - min_age &&
                              lost.since >= t - max_age && reidentify(reid_rng) < fo.reidentify_probability;
      const Track tr = recognised ? lost.track : Track{static_cast<std::uint64_t>(out.track_truth.size()), i};
      if (!recognised) out.track_truth.push_back(landmarks[i]);
      alive.emplace_back(tr, px);
    }

    FeatureFrame frame;
    frame.t = t;
    frame.frame_index = static_cast<std::uint32_t>(k);
    tracks.clear();
    int inconsistent = 0;
    for (const auto& [tr, px0] : alive) {
      tracks.push_back(tr);
      const LandmarkTruth& l = landmarks[tr.landmark];
      const TrackLabel label = scene.movingInWorld(l.body, t) ? TrackLabel::kInconsistent : TrackLabel::kConsistent;
      if (label == TrackLabel::kInconsistent) ++inconsistent;
      for (int c = 0; c < 2; ++c) {
        Eigen::Vector2d px = px0;
        if (c == 1 && !observe(tr.landmark, 1, &px)) continue;
        FeatureObservation o;
        o.track_id = tr.id;
        o.camera_index = static_cast<std::uint8_t>(c);
        o.pixel = px + fo.pixel_noise_sigma * Eigen::Vector2d(normal(rng), normal(rng));
        if (!rig.camera(c).model.unproject(o.pixel, &o.normalized)) continue;
        o.label = label;
        frame.features.push_back(o);
      }
    }
    dataset::ConflictLabel cl;
    cl.t = t;
    cl.in_conflict = inconsistent > 0;
    cl.motion = cl.in_conflict ? sim.world().motion_name : "none";
    cl.covered_fraction = alive.empty() ? 0.0 : static_cast<double>(inconsistent) / alive.size();
    out.labels.push_back(cl);
    out.frames.push_back(std::move(frame));
  }
  return out;
}

FeatureSequence simulateFeatureSequence(const SimulatorOptions& sim,
                                        const FeatureSimulatorOptions& features) {
  return FeatureSimulator(sim, features).run();
}

}  // namespace mcvio::sim
