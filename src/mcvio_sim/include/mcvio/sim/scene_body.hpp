#pragma once
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mcvio/core/time.hpp"
#include "mcvio/sim/ride_profile.hpp"

namespace mcvio::sim {

/// A textured rectangle: corner `origin`, edges `size_u` along `axis_u` and `size_v` along
/// `axis_v` (unit, orthogonal), in the coordinates of the body that owns it. Visible from both
/// sides. Texture coordinates are (u / texel_size, v / texel_size) + texture_offset texels.
struct TexturedQuad {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis_u = Eigen::Vector3d::UnitX();
  Eigen::Vector3d axis_v = Eigen::Vector3d::UnitY();
  double size_u = 1.0;
  double size_v = 1.0;
  int texture = 0;               ///< index into Scene::textures()
  double texel_size = 0.005;     ///< [m per texel]
  Eigen::Vector2d texture_offset = Eigen::Vector2d::Zero();
  float brightness = 1.0f;       ///< reflectance factor (fixed shading of this face)
  /// 0: visible from both sides. +1 / -1: a face of a closed solid, seen only from the side
  /// facing +normal() / -normal(); the renderer skips it from the other side.
  int facing = 0;

  Eigen::Vector3d normal() const { return axis_u.cross(axis_v); }
};

/// How a rigid body of the scene moves.
enum class BodyMotion {
  kStatic,          ///< fixed in the world
  kRide,            ///< translates along a RideProfile (cabin, vehicle, person, drifting object)
  kDeviceAttached,  ///< rigidly attached to the device (a carried laptop)
};

/// A rigid group of quads that moves as one: the unit of "motion" in conflict labels and the
/// per-pixel id of the renderer.
struct SceneBody {
  std::string name;
  BodyMotion motion = BodyMotion::kStatic;
  RideProfile ride;                                            ///< for kRide
  Eigen::Isometry3d T_BF = Eigen::Isometry3d::Identity();     ///< kDeviceAttached: body in device frame
  Timestamp visible_from = std::numeric_limits<Timestamp>::min();
  Timestamp visible_until = std::numeric_limits<Timestamp>::max();
  /// The device rides this body (elevator cabin, vehicle): its world motion is added to the
  /// device's, so the camera sees the interior static while the IMU feels the ride.
  bool carries_device = false;
  std::vector<TexturedQuad> quads;
};

}  // namespace mcvio::sim
