#include "mcvio/sim/scene.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace mcvio::sim {

int Scene::addTexture(MipmappedTexture texture) {
  textures_.push_back(std::move(texture));
  return static_cast<int>(textures_.size()) - 1;
}

int Scene::addBody(SceneBody body) {
  if (static_cast<int>(bodies_.size()) >= kMaxBodies)
    throw std::length_error("Scene: too many bodies");
  for (const auto& q : body.quads)
    if (q.texture < 0 || q.texture >= static_cast<int>(textures_.size()))
      throw std::out_of_range("Scene: quad of body '" + body.name + "' uses a missing texture");
  bodies_.push_back(std::move(body));
  return static_cast<int>(bodies_.size()) - 1;
}

Eigen::Isometry3d Scene::bodyPose(int i, Timestamp t, const Eigen::Isometry3d& T_WB) const {
  const SceneBody& b = body(i);
  switch (b.motion) {
    case BodyMotion::kStatic: return Eigen::Isometry3d::Identity();
    case BodyMotion::kRide: {
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.translation() = b.ride.displacement(t);
      return T;
    }
    case BodyMotion::kDeviceAttached: return T_WB * b.T_BF;
  }
  return Eigen::Isometry3d::Identity();
}

bool Scene::visible(int i, Timestamp t) const {
  const SceneBody& b = body(i);
  return t >= b.visible_from && t < b.visible_until;
}

bool Scene::movingInWorld(int i, Timestamp t) const {
  if (!visible(i, t)) return false;
  const SceneBody& b = body(i);
  switch (b.motion) {
    case BodyMotion::kStatic: return false;
    case BodyMotion::kRide: return b.ride.moving(t);
    case BodyMotion::kDeviceAttached: return true;
  }
  return false;
}

double Scene::castRay(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, Timestamp t,
                      const Eigen::Isometry3d& T_WB, int skip_body, int* hit_body) const {
  double best = std::numeric_limits<double>::infinity();
  if (hit_body) *hit_body = -1;
  for (int b = 0; b < static_cast<int>(bodies_.size()); ++b) {
    if (b == skip_body || !visible(b, t)) continue;
    const Eigen::Isometry3d T_FW = bodyPose(b, t, T_WB).inverse();
    const Eigen::Vector3d o = T_FW * origin;
    const Eigen::Vector3d d = T_FW.linear() * dir;
    for (const TexturedQuad& q : bodies_[static_cast<size_t>(b)].quads) {
      const Eigen::Vector3d n = q.normal();
      const double den = n.dot(d);
      if (std::abs(den) < 1e-12) continue;
      const double s = n.dot(q.origin - o) / den;
      if (s <= 0 || s >= best) continue;
      const Eigen::Vector3d p = o + s * d - q.origin;
      const double u = p.dot(q.axis_u), v = p.dot(q.axis_v);
      if (u < 0 || u > q.size_u || v < 0 || v > q.size_v) continue;
      best = s;
      if (hit_body) *hit_body = b;
    }
  }
  return best;
}

}  // namespace mcvio::sim
