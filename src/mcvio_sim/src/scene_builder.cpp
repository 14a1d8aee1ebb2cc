#include "mcvio/sim/scene_builder.hpp"

#include <algorithm>
#include <cmath>

namespace mcvio::sim {

SceneBuilder::SceneBuilder(Scene& scene, std::uint64_t seed, int texture_size, int per_style)
    : scene_(scene), rng_(seed), by_style_(4) {
  for (int s = 0; s < 4; ++s)
    for (int k = 0; k < per_style; ++k)
      by_style_[static_cast<size_t>(s)].push_back(scene_.addTexture(MipmappedTexture::generate(
          static_cast<TextureStyle>(s), texture_size, seed * 131 + static_cast<std::uint64_t>(s * 17 + k))));
}

int SceneBuilder::pickTexture(TextureStyle style) {
  const auto& list = by_style_[static_cast<size_t>(style)];
  return list[std::uniform_int_distribution<size_t>(0, list.size() - 1)(rng_)];
}

void SceneBuilder::quad(SceneBody& body, const Eigen::Vector3d& origin,
                        const Eigen::Vector3d& axis_u, const Eigen::Vector3d& axis_v,
                        double size_u, double size_v, TextureStyle style, double texel_size,
                        int facing) {
  if (size_u <= 1e-6 || size_v <= 1e-6) return;
  TexturedQuad q;
  q.origin = origin;
  q.axis_u = axis_u.normalized();
  q.axis_v = axis_v.normalized();
  q.size_u = size_u;
  q.size_v = size_v;
  q.texture = pickTexture(style);
  q.texel_size = texel_size;
  q.facing = facing;
  const int n = scene_.textures()[static_cast<size_t>(q.texture)].size();
  q.texture_offset = {std::floor(uniform(0, n)), std::floor(uniform(0, n))};
  // Fixed diffuse shading from one key light plus ambient, so faces of a box differ.
  const Eigen::Vector3d light = Eigen::Vector3d(0.4, 0.25, 0.88).normalized();
  q.brightness = static_cast<float>(0.6 + 0.4 * std::abs(q.normal().dot(light)));
  body.quads.push_back(q);
}

void SceneBuilder::wallWithHole(SceneBody& body, const Eigen::Vector3d& origin,
                                const Eigen::Vector3d& axis_u, const Eigen::Vector3d& axis_v,
                                double size_u, double size_v, double u0, double v0, double u1,
                                double v1, TextureStyle style, double texel_size) {
  const Eigen::Vector3d eu = axis_u.normalized(), ev = axis_v.normalized();
  u0 = std::clamp(u0, 0.0, size_u);
  u1 = std::clamp(u1, u0, size_u);
  v0 = std::clamp(v0, 0.0, size_v);
  v1 = std::clamp(v1, v0, size_v);
  quad(body, origin, eu, ev, u0, size_v, style, texel_size);                      // left
  quad(body, origin + u1 * eu, eu, ev, size_u - u1, size_v, style, texel_size);   // right
  quad(body, origin + u0 * eu, eu, ev, u1 - u0, v0, style, texel_size);           // below
  quad(body, origin + u0 * eu + v1 * ev, eu, ev, u1 - u0, size_v - v1, style, texel_size);  // above
}

void SceneBuilder::box(SceneBody& body, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                       TextureStyle style, double texel_size) {
  const Eigen::Vector3d s = hi - lo;
  const Eigen::Vector3d X = Eigen::Vector3d::UnitX(), Y = Eigen::Vector3d::UnitY(),
                        Z = Eigen::Vector3d::UnitZ();
  // X x Z = -Y, Y x Z = +X, X x Y = +Z: `facing` points each face outwards.
  quad(body, lo, X, Z, s.x(), s.z(), style, texel_size, +1);                           // -y face
  quad(body, lo + Eigen::Vector3d(0, s.y(), 0), X, Z, s.x(), s.z(), style, texel_size, -1);  // +y
  quad(body, lo, Y, Z, s.y(), s.z(), style, texel_size, -1);                           // -x
  quad(body, lo + Eigen::Vector3d(s.x(), 0, 0), Y, Z, s.y(), s.z(), style, texel_size, +1);  // +x
  quad(body, lo, X, Y, s.x(), s.y(), style, texel_size, -1);                           // bottom
  quad(body, lo + Eigen::Vector3d(0, 0, s.z()), X, Y, s.x(), s.y(), style, texel_size, +1);  // top
}

}  // namespace mcvio::sim
