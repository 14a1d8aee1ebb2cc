#pragma once
#include <memory>
#include <vector>

#include "mcvio/sim/mipmapped_texture.hpp"
#include "mcvio/sim/scene_body.hpp"

namespace mcvio::sim {

/// The simulated world: textures and rigid bodies made of textured quads. Body 0 is usually the
/// static world. At most 254 bodies (the renderer's id image is 8-bit, 255 = nothing hit).
class Scene {
 public:
  static constexpr int kMaxBodies = 254;

  int addTexture(MipmappedTexture texture);
  int addBody(SceneBody body);

  const std::vector<MipmappedTexture>& textures() const { return textures_; }
  const std::vector<SceneBody>& bodies() const { return bodies_; }
  SceneBody& body(int i) { return bodies_.at(static_cast<size_t>(i)); }
  const SceneBody& body(int i) const { return bodies_.at(static_cast<size_t>(i)); }

  /// World pose of body i at time t, given the device (IMU) pose T_WB at that time.
  Eigen::Isometry3d bodyPose(int i, Timestamp t, const Eigen::Isometry3d& T_WB) const;
  bool visible(int i, Timestamp t) const;
  /// True when body i is visible and moves relative to the inertial world at t: it is a
  /// conflicting motion for a camera that sees it.
  bool movingInWorld(int i, Timestamp t) const;

  /// Distance along the unit ray origin + s * dir to the first visible quad at time t (device at
  /// T_WB), ignoring body `skip_body`; +inf when nothing is hit. *hit_body receives its body.
  double castRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, Timestamp t,
                 const Eigen::Isometry3d& T_WB, int skip_body = -1, int* hit_body = nullptr) const;

 private:
  std::vector<MipmappedTexture> textures_;
  std::vector<SceneBody> bodies_;
};

}  // namespace mcvio::sim
