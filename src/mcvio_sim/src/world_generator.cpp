#include "mcvio/sim/world_generator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mcvio/core/input_error.hpp"
#include "mcvio/sim/frame_riding_trajectory.hpp"
#include "mcvio/sim/scene_builder.hpp"
#include "mcvio/sim/sinusoid_trajectory.hpp"

namespace mcvio::sim {
namespace {

using Eigen::Vector3d;
const Vector3d kX = Vector3d::UnitX(), kY = Vector3d::UnitY(), kZ = Vector3d::UnitZ();

/// Device positions sampled along the trajectory, for bounds and clearance checks.
std::vector<Vector3d> samplePositions(const Trajectory& traj) {
  std::vector<Vector3d> out;
  const Timestamp step = fromSeconds(0.1);
  for (Timestamp t = traj.startTime(); t <= traj.endTime(); t += step)
    out.push_back(traj.evaluate(t).p_wb);
  return out;
}

Eigen::AlignedBox3d boundsOf(const std::vector<Vector3d>& pts) {
  Eigen::AlignedBox3d box;
  for (const auto& p : pts) box.extend(p);
  return box;
}

/// Smallest distance from any sampled device position to the box.
double clearance(const std::vector<Vector3d>& pts, const Eigen::AlignedBox3d& box) {
  double best = std::numeric_limits<double>::infinity();
  for (const auto& p : pts) best = std::min(best, box.exteriorDistance(p));
  return best;
}

/// Six faces of a room (inside view) with an optional door hole in the +x wall.
void addRoom(SceneBuilder& b, SceneBody& body, const Vector3d& lo, const Vector3d& hi,
             bool door_px, double door_y0, double door_y1, double door_h) {
  const Vector3d s = hi - lo;
  b.quad(body, lo, kX, kY, s.x(), s.y(), TextureStyle::kTiles, 0.008);                    // floor
  b.quad(body, {lo.x(), lo.y(), hi.z()}, kX, kY, s.x(), s.y(), TextureStyle::kTiles, 0.006);  // ceiling
  const TextureStyle styles[] = {TextureStyle::kPosters, TextureStyle::kBricks, TextureStyle::kClutter};
  auto style = [&] { return styles[static_cast<int>(b.uniform(0, 3)) % 3]; };
  b.quad(body, lo, kX, kZ, s.x(), s.z(), style(), 0.005);                        // -y wall
  b.quad(body, {lo.x(), hi.y(), lo.z()}, kX, kZ, s.x(), s.z(), style(), 0.005);  // +y wall
  b.quad(body, lo, kY, kZ, s.y(), s.z(), style(), 0.005);                        // -x wall
  if (door_px)
    b.wallWithHole(body, {hi.x(), lo.y(), lo.z()}, kY, kZ, s.y(), s.z(), door_y0 - lo.y(), 0.0,
                   door_y1 - lo.y(), door_h, style(), 0.005);
  else
    b.quad(body, {hi.x(), lo.y(), lo.z()}, kY, kZ, s.y(), s.z(), style(), 0.005);
}

/// Furniture against the walls of [lo, hi] and panels on them, kept clear of the trajectory.
void furnish(SceneBuilder& b, SceneBody& body, const Vector3d& lo, const Vector3d& hi,
             const std::vector<Vector3d>& path, double door_y0, double door_y1, bool door_px) {
  const Vector3d s = hi - lo;
  const int attempts = static_cast<int>(2.0 * (s.x() + s.y()));
  for (int k = 0; k < attempts; ++k) {
    const int wall = static_cast<int>(b.uniform(0, 4)) % 4;
    const double width = b.uniform(0.5, 1.8), depth = b.uniform(0.35, 0.9),
                 height = b.uniform(0.45, 2.1);
    Vector3d a, c;
    if (wall < 2) {  // along -y / +y walls
      const double x = b.uniform(lo.x() + 0.1, hi.x() - width - 0.1);
      const double y = wall == 0 ? lo.y() + 0.02 : hi.y() - depth - 0.02;
      a = {x, y, lo.z()};
      c = {x + width, y + depth, lo.z() + height};
    } else {  // along -x / +x walls
      const double y = b.uniform(lo.y() + 0.1, hi.y() - width - 0.1);
      const double x = wall == 2 ? lo.x() + 0.02 : hi.x() - depth - 0.02;
      if (wall == 3 && door_px && y < door_y1 + 0.3 && y + width > door_y0 - 0.3) continue;
      a = {x, y, lo.z()};
      c = {x + depth, y + width, lo.z() + height};
    }
    const Eigen::AlignedBox3d box(a, c);
    if (clearance(path, box) < 0.6) continue;
    b.box(body, a, c, b.uniform(0, 1) < 0.6 ? TextureStyle::kClutter : TextureStyle::kPosters, 0.003);
  }
  // Panels a few centimetres off the walls: extra depth edges and fine print.
  for (int k = 0; k < attempts / 2; ++k) {
    const int wall = static_cast<int>(b.uniform(0, 4)) % 4;
    const double w = b.uniform(0.6, 1.6), h = b.uniform(0.5, 1.2), z = lo.z() + b.uniform(0.9, 1.6);
    if (wall == 0) b.quad(body, {b.uniform(lo.x(), hi.x() - w), lo.y() + 0.03, z}, kX, kZ, w, h, TextureStyle::kPosters, 0.0015);
    if (wall == 1) b.quad(body, {b.uniform(lo.x(), hi.x() - w), hi.y() - 0.03, z}, kX, kZ, w, h, TextureStyle::kPosters, 0.0015);
    if (wall == 2) b.quad(body, {lo.x() + 0.03, b.uniform(lo.y(), hi.y() - w), z}, kY, kZ, w, h, TextureStyle::kPosters, 0.0015);
    if (wall == 3 && !door_px) b.quad(body, {hi.x() - 0.03, b.uniform(lo.y(), hi.y() - w), z}, kY, kZ, w, h, TextureStyle::kPosters, 0.0015);
  }
  // A pillar in the middle of the loop when the path leaves room for it.
  const Vector3d mid = 0.5 * (lo + hi);
  const Eigen::AlignedBox3d pillar(Vector3d(mid.x() - 0.25, mid.y() - 0.25, lo.z()),
                                   Vector3d(mid.x() + 0.25, mid.y() + 0.25, hi.z()));
  if (clearance(path, pillar) > 0.7) b.box(body, pillar.min(), pillar.max(), TextureStyle::kBricks, 0.004);
}

/// Office room around the path, a corridor through a door in the +x wall.
void buildOffice(SceneBuilder& b, Scene& scene, const std::vector<Vector3d>& path) {
  const Eigen::AlignedBox3d bounds = boundsOf(path);
  const Vector3d c = bounds.center();
  const Vector3d half = (0.5 * bounds.sizes()).cwiseMax(Vector3d(1.5, 1.0, 0.0));
  const Vector3d lo(c.x() - half.x() - 2.6, c.y() - half.y() - 2.6, bounds.min().z() - 1.2);
  const Vector3d hi(c.x() + half.x() + 2.6, c.y() + half.y() + 2.6, bounds.max().z() + 1.3);
  SceneBody world;
  world.name = "world";
  const double door_y0 = c.y() - 1.0, door_y1 = c.y() + 1.0, door_h = std::min(2.4, hi.z() - lo.z() - 0.2);
  addRoom(b, world, lo, hi, true, door_y0, door_y1, door_h);
  furnish(b, world, lo, hi, path, door_y0, door_y1, true);
  // Corridor beyond the door.
  const double len = 9.0, cw = 2.6, ch = door_h + 0.3;
  const Vector3d clo(hi.x(), c.y() - cw / 2, lo.z()), chi(hi.x() + len, c.y() + cw / 2, lo.z() + ch);
  b.quad(world, clo, kX, kY, len, cw, TextureStyle::kTiles, 0.008);
  b.quad(world, {clo.x(), clo.y(), chi.z()}, kX, kY, len, cw, TextureStyle::kTiles, 0.006);
  b.quad(world, clo, kX, kZ, len, ch, TextureStyle::kPosters, 0.005);
  b.quad(world, {clo.x(), chi.y(), clo.z()}, kX, kZ, len, ch, TextureStyle::kBricks, 0.005);
  b.quad(world, {chi.x(), clo.y(), clo.z()}, kY, kZ, cw, ch, TextureStyle::kPosters, 0.004);
  for (int k = 0; k < 4; ++k) {
    const double x = clo.x() + 1.0 + 2.0 * k + b.uniform(0, 0.8);
    const bool left = k % 2 == 0;
    const double y0 = left ? clo.y() + 0.02 : chi.y() - 0.5;
    b.box(world, {x, y0, clo.z()}, {x + b.uniform(0.4, 1.0), y0 + 0.48, clo.z() + b.uniform(0.6, 1.9)},
          TextureStyle::kClutter, 0.003);
  }
  scene.addBody(std::move(world));
}

/// Interior walls of a cabin or vehicle, with a window hole in the +x wall (and the side walls
/// when `side_windows`), sized so the solid part is about `coverage` of the wall.
void addCabin(SceneBuilder& b, SceneBody& body, const Vector3d& lo, const Vector3d& hi,
              double coverage, bool side_windows, TextureStyle wall_style) {
  const Vector3d s = hi - lo;
  b.quad(body, lo, kX, kY, s.x(), s.y(), TextureStyle::kTiles, 0.004);
  b.quad(body, {lo.x(), lo.y(), hi.z()}, kX, kY, s.x(), s.y(), TextureStyle::kClutter, 0.004);
  b.quad(body, lo, kY, kZ, s.y(), s.z(), wall_style, 0.003);  // back wall
  const double open = std::clamp(1.0 - coverage, 0.0, 0.85);
  const double k = std::sqrt(open);
  auto windowed = [&](const Vector3d& o, const Vector3d& eu, double su) {
    if (open < 1e-3) {
      b.quad(body, o, eu, kZ, su, s.z(), wall_style, 0.003);
      return;
    }
    const double wu = k * su, wv = k * s.z();
    const double u0 = 0.5 * (su - wu), v0 = std::min(0.55 * s.z(), s.z() - wv - 0.05);
    b.wallWithHole(body, o, eu, kZ, su, s.z(), u0, std::max(0.05, v0), u0 + wu,
                   std::max(0.05, v0) + wv, wall_style, 0.003);
  };
  windowed({hi.x(), lo.y(), lo.z()}, kY, s.y());
  if (side_windows) {
    windowed(lo, kX, s.x());
    windowed({lo.x(), hi.y(), lo.z()}, kX, s.x());
  } else {
    b.quad(body, lo, kX, kZ, s.x(), s.z(), wall_style, 0.003);
    b.quad(body, {lo.x(), hi.y(), lo.z()}, kX, kZ, s.x(), s.z(), TextureStyle::kPosters, 0.002);
  }
}

Eigen::AlignedBox3d interiorAround(const Eigen::AlignedBox3d& bounds, const Vector3d& min_size,
                                   double margin, double below, double above) {
  const Vector3d c = bounds.center();
  Vector3d half = 0.5 * bounds.sizes() + Vector3d::Constant(margin);
  half = half.cwiseMax(0.5 * min_size);
  return {Vector3d(c.x() - half.x(), c.y() - half.y(), bounds.min().z() - below),
          Vector3d(c.x() + half.x(), c.y() + half.y(), bounds.max().z() + above)};
}

void buildElevator(SceneBuilder& b, Scene& scene, const std::vector<Vector3d>& path,
                   const RideProfile& ride, double coverage, double travel) {
  const Eigen::AlignedBox3d in = interiorAround(boundsOf(path), {2.2, 2.2, 0}, 0.8, 1.25, 0.9);
  const Vector3d lo = in.min(), hi = in.max();
  SceneBody shaft;
  shaft.name = "shaft";
  const Vector3d slo(lo.x() - 0.6, lo.y() - 0.6, lo.z() - 3.0);
  const Vector3d shi(hi.x() + 0.6, hi.y() + 0.6, hi.z() + std::abs(travel) + 3.0);
  const Vector3d ss = shi - slo;
  b.quad(shaft, slo, kY, kZ, ss.y(), ss.z(), TextureStyle::kBricks, 0.006);
  b.quad(shaft, {shi.x(), slo.y(), slo.z()}, kY, kZ, ss.y(), ss.z(), TextureStyle::kBricks, 0.006);
  b.quad(shaft, slo, kX, kZ, ss.x(), ss.z(), TextureStyle::kClutter, 0.006);
  b.quad(shaft, {slo.x(), shi.y(), slo.z()}, kX, kZ, ss.x(), ss.z(), TextureStyle::kClutter, 0.006);
  for (double z = slo.z() + 1.0; z < shi.z(); z += 3.0)  // floor landings seen through the glass
    b.box(shaft, {shi.x() - 0.25, slo.y(), z}, {shi.x(), shi.y(), z + 0.3}, TextureStyle::kTiles, 0.004);
  scene.addBody(std::move(shaft));

  SceneBody cabin;
  cabin.name = "elevator_cabin";
  cabin.motion = BodyMotion::kRide;
  cabin.ride = ride;
  cabin.carries_device = true;
  addCabin(b, cabin, lo, hi, coverage, false, TextureStyle::kPosters);
  // Hand rails and a control panel: depth structure inside the cabin.
  b.box(cabin, {lo.x() + 0.02, lo.y(), lo.z() + 0.9}, {lo.x() + 0.08, hi.y(), lo.z() + 0.95}, TextureStyle::kClutter, 0.002);
  b.box(cabin, {lo.x(), lo.y() + 0.02, lo.z() + 0.9}, {hi.x(), lo.y() + 0.08, lo.z() + 0.95}, TextureStyle::kClutter, 0.002);
  b.box(cabin, {hi.x() - 0.05, hi.y() - 0.5, lo.z() + 1.0}, {hi.x(), hi.y() - 0.2, lo.z() + 1.6}, TextureStyle::kPosters, 0.001);
  scene.addBody(std::move(cabin));
}

void buildVehicle(SceneBuilder& b, Scene& scene, const std::vector<Vector3d>& path,
                  const RideProfile& ride, double coverage, double travel) {
  const Eigen::AlignedBox3d in = interiorAround(boundsOf(path), {3.0, 1.8, 0}, 0.6, 0.85, 0.35);
  const Vector3d lo = in.min(), hi = in.max();
  const double ground = lo.z() - 0.35;
  SceneBody street;
  street.name = "street";
  const double x0 = lo.x() - 30.0, x1 = hi.x() + std::abs(travel) + 60.0;
  b.quad(street, {x0, -14.0, ground}, kX, kY, x1 - x0, 28.0, TextureStyle::kTiles, 0.006);
  for (int side = -1; side <= 1; side += 2) {
    for (double x = x0; x < x1;) {
      const double len = b.uniform(6.0, 16.0), setback = b.uniform(0.0, 2.5), h = b.uniform(5.0, 12.0);
      const double y_near = side * (9.0 + setback);
      const double y_far = side * (15.0 + setback);
      b.box(street, {x, std::min(y_near, y_far), ground}, {std::min(x + len, x1), std::max(y_near, y_far), ground + h},
            b.uniform(0, 1) < 0.5 ? TextureStyle::kBricks : TextureStyle::kPosters, 0.008);
      x += len + b.uniform(0.0, 3.0);
    }
    for (double x = x0 + 5.0; x < x1; x += b.uniform(8.0, 16.0)) {  // poles and parked cars
      b.box(street, {x, side * 6.5 - 0.08, ground}, {x + 0.16, side * 6.5 + 0.08, ground + 4.0}, TextureStyle::kClutter, 0.003);
      if (b.uniform(0, 1) < 0.5) {
        const double yc = side * 5.0;
        b.box(street, {x + 1.0, yc - 0.9, ground}, {x + 5.2, yc + 0.9, ground + 1.4}, TextureStyle::kClutter, 0.004);
      }
    }
  }
  b.quad(street, {x1, -14.0, ground}, kY, kZ, 28.0, 14.0, TextureStyle::kPosters, 0.01);
  b.quad(street, {x0, -14.0, ground}, kY, kZ, 28.0, 14.0, TextureStyle::kBricks, 0.01);
  scene.addBody(std::move(street));

  SceneBody vehicle;
  vehicle.name = "vehicle_interior";
  vehicle.motion = BodyMotion::kRide;
  vehicle.ride = ride;
  vehicle.carries_device = true;
  addCabin(b, vehicle, lo, hi, coverage, true, TextureStyle::kClutter);
  const double dash_top = lo.z() + 0.2 * (hi.z() - lo.z()) + 0.25;
  b.box(vehicle, {hi.x() - 0.4, lo.y(), lo.z()}, {hi.x(), hi.y(), dash_top}, TextureStyle::kPosters, 0.0015);
  scene.addBody(std::move(vehicle));
}

/// Optical axis of cam0 and its horizontal direction at time t.
Vector3d horizontalViewDirection(const Trajectory& traj, Timestamp t, const CameraCalibration& cam0) {
  const KinematicState s = traj.evaluate(t);
  Vector3d f = s.q_wb * (cam0.T_BC.linear() * kZ);
  f.z() = 0;
  if (f.norm() < 1e-6) f = kX;
  return f.normalized();
}

}  // namespace

SimulatedWorld WorldGenerator::generate(const Inputs& in) {
  const ScenarioOptions& sc = in.scenario;
  if (in.end <= in.start) throw InputError("scenario: sequence end must be after its start");
  SimulatedWorld w;
  SceneBuilder b(w.scene, in.seed, in.texture_size);
  w.motion_name = toString(sc.kind);
  const Timestamp onset = in.start + fromSeconds(sc.onset_s);
  const Timestamp duration = fromSeconds(sc.duration_s);

  std::shared_ptr<const Trajectory> local = in.recorded;
  if (!local) {
    switch (sc.kind) {
      case ScenarioKind::kElevator:
        local = std::make_shared<SinusoidTrajectory>(
            SinusoidTrajectory::Options::handHeld({0, 0, 1.4}, {0.3, 0.3, 0.12}, 0.12), in.start, in.end);
        break;
      case ScenarioKind::kVehicle: {
        auto o = SinusoidTrajectory::Options::handHeld({0.2, 0, 1.1}, {0.15, 0.15, 0.08}, 0.0);
        o.yaw = {{0.45, 0.04, 0.0}, {0.1, 0.25, 1.0}, {0.02, 1.2, 0.4}};
        local = std::make_shared<SinusoidTrajectory>(o, in.start, in.end);
        break;
      }
      default:
        local = std::make_shared<SinusoidTrajectory>(
            SinusoidTrajectory::Options::loop({0, 0, 1.55}, {3.0, 2.2, 0.35}, 26.0), in.start, in.end);
    }
  }
  w.trajectory_in_frame = local;
  w.trajectory = local;
  const std::vector<Vector3d> path = samplePositions(*local);

  switch (sc.kind) {
    case ScenarioKind::kElevator: {
      const double travel = sc.travel_m != 0.0 ? sc.travel_m : 12.0;
      w.device_ride = RideProfile(onset, duration, kZ, travel);
      w.device_rides = true;
      buildElevator(b, w.scene, path, w.device_ride, sc.coverage, travel);
      w.conflict_bodies = {1};
      break;
    }
    case ScenarioKind::kVehicle: {
      const double travel = sc.travel_m != 0.0 ? sc.travel_m : 4.0 * sc.duration_s;
      w.device_ride = RideProfile(onset, duration, kX, travel);
      w.device_rides = true;
      buildVehicle(b, w.scene, path, w.device_ride, sc.coverage, travel);
      w.conflict_bodies = {1};
      break;
    }
    default: buildOffice(b, w.scene, path);
  }
  if (w.device_rides)
    w.trajectory = std::make_shared<FrameRidingTrajectory>(local, w.device_ride);

  const double floor_z = boundsOf(path).min().z() - 1.2;
  const Timestamp mid = onset + duration / 2;
  switch (sc.kind) {
    case ScenarioKind::kSelfOcclusion: {
      SceneBody laptop;
      laptop.name = "carried_laptop";
      laptop.motion = BodyMotion::kDeviceAttached;
      laptop.visible_from = onset;
      laptop.visible_until = onset + duration;
      // Lid 0.3 m in front of cam0, centred between the two cameras, tilted back a little.
      const double z = 0.3, c = std::clamp(sc.coverage, 0.05, 1.0);
      const double wd = std::min(0.6, 2.0 * 0.95 * z * std::sqrt(c)), ht = std::min(0.4, 2.0 * 0.6 * z * std::sqrt(c));
      const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.15, kX).toRotationMatrix();
      const Vector3d eu = tilt * kX, ev = tilt * kY;
      const Vector3d centre(0.055, 0.02, z);
      const Vector3d corner = centre - 0.5 * wd * eu - 0.5 * ht * ev;
      b.quad(laptop, corner, eu, ev, wd, ht, TextureStyle::kPosters, 0.0006);
      laptop.T_BF = in.cam0.T_BC;
      w.conflict_bodies = {w.scene.addBody(std::move(laptop))};
      break;
    }
    case ScenarioKind::kPedestrian: {
      const KinematicState s = local->evaluate(mid);
      const Vector3d cam = s.p_wb;
      const Vector3d f = horizontalViewDirection(*local, mid, in.cam0);
      const double wall = w.scene.castRay(cam, f, mid, Eigen::Isometry3d::Identity());
      const double area = 0.45 * 1.78;
      const double want = std::sqrt(area / (1.7 * std::clamp(sc.coverage, 0.02, 1.0)));
      const double d_max = std::max(0.8, 0.75 * std::min(wall, 20.0));
      const Vector3d side = kZ.cross(f).normalized();
      // Walk path for a crossing at distance d, and whether the device stays clear of it.
      auto walk = [&](double d, Vector3d* start, double* len) {
        *len = sc.travel_m != 0.0 ? sc.travel_m : 2.0 * (1.0 * d + 0.8);
        *start = Vector3d(cam.x() + d * f.x() - 0.5 * *len * side.x(), cam.y() + d * f.y() - 0.5 * *len * side.y(), floor_z);
        const RideProfile ride(onset, duration, side, *len);
        for (Timestamp t = onset; t <= onset + duration; t += fromSeconds(0.05)) {
          const Vector3d p = *start + ride.displacement(t);
          const Vector3d dev = local->evaluate(t).p_wb;
          if (Eigen::Vector2d(dev.x() - p.x(), dev.y() - p.y()).norm() < 0.75) return false;
        }
        return true;
      };
      double d = std::clamp(want, 0.8, d_max), len = 0;
      Vector3d start;
      while (!walk(d, &start, &len) && d + 0.2 <= d_max) d += 0.2;
      walk(d, &start, &len);
      SceneBody person;
      person.name = "pedestrian";
      person.motion = BodyMotion::kRide;
      person.ride = RideProfile(onset, duration, side, len);
      person.visible_from = onset;
      person.visible_until = onset + duration;
      // Legs, torso, arms and head: a person-sized silhouette with clothes-like texture.
      auto part = [&](double x0, double y0, double z0, double x1, double y1, double z1, TextureStyle st, double texel) {
        b.box(person, start + Vector3d(x0, y0, z0), start + Vector3d(x1, y1, z1), st, texel);
      };
      part(-0.17, -0.08, 0.0, -0.03, 0.08, 0.86, TextureStyle::kBricks, 0.0015);
      part(0.03, -0.08, 0.0, 0.17, 0.08, 0.86, TextureStyle::kBricks, 0.0015);
      part(-0.22, -0.13, 0.86, 0.22, 0.13, 1.48, TextureStyle::kClutter, 0.0015);
      part(-0.32, -0.06, 0.9, -0.23, 0.06, 1.45, TextureStyle::kTiles, 0.0015);
      part(0.23, -0.06, 0.9, 0.32, 0.06, 1.45, TextureStyle::kTiles, 0.0015);
      part(-0.05, -0.05, 1.48, 0.05, 0.05, 1.54, TextureStyle::kPosters, 0.001);
      part(-0.1, -0.11, 1.54, 0.1, 0.11, 1.78, TextureStyle::kPosters, 0.001);
      w.conflict_bodies = {w.scene.addBody(std::move(person))};
      break;
    }
    case ScenarioKind::kSlowObject: {
      const KinematicState s = local->evaluate(mid);
      const Vector3d cam = s.p_wb;
      const Vector3d f = horizontalViewDirection(*local, mid, in.cam0);
      const Vector3d side = kZ.cross(f).normalized();
      const double wall = std::min(w.scene.castRay(cam, f, mid, Eigen::Isometry3d::Identity()), 12.0);
      const double travel = sc.travel_m != 0.0 ? sc.travel_m : 0.08 * sc.duration_s;
      // Place the object where it stays clear of the device path for the whole drift.
      double best_d = 0.55 * wall, best_clear = -1, best_a = 1.0;
      for (double frac = 0.3; frac <= 0.86; frac += 0.05) {
        const double d = frac * wall;
        const double a = std::clamp(d * std::sqrt(1.7 * std::clamp(sc.coverage, 0.02, 1.0)) * 0.8, 0.5, 2.2);
        const Vector3d base = cam + d * f;
        double cl = std::numeric_limits<double>::infinity();
        for (double u = 0; u <= 1.0; u += 0.25) {
          const Vector3d p = base + u * travel * side;
          cl = std::min(cl, clearance(path, Eigen::AlignedBox3d(Vector3d(p.x() - a / 2, p.y() - a / 2, floor_z),
                                                                 Vector3d(p.x() + a / 2, p.y() + a / 2, floor_z + 1.3 * a))));
        }
        const double score = std::min(cl, 0.5) - 0.1 * std::abs(frac - 0.55);
        if (score > best_clear) {
          best_clear = score;
          best_d = d;
          best_a = a;
        }
      }
      const Vector3d p = cam + best_d * f;
      SceneBody obj;
      obj.name = "slow_object";
      obj.motion = BodyMotion::kRide;
      obj.ride = RideProfile(onset, duration, side, travel);
      b.box(obj, Vector3d(p.x() - best_a / 2, p.y() - best_a / 2, floor_z),
            Vector3d(p.x() + best_a / 2, p.y() + best_a / 2, floor_z + 1.3 * best_a), TextureStyle::kPosters, 0.002);
      w.conflict_bodies = {w.scene.addBody(std::move(obj))};
      break;
    }
    default: break;
  }
  return w;
}

}  // namespace mcvio::sim
