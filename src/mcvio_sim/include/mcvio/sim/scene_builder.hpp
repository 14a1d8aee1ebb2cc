#pragma once
#include <cstdint>
#include <random>
#include <vector>

#include "mcvio/sim/scene.hpp"

namespace mcvio::sim {

/// Adds textured geometry (rooms, walls with openings, boxes, panels) to a Scene, choosing
/// procedural textures, texture offsets and face shading reproducibly from a seed.
class SceneBuilder {
 public:
  /// Creates `per_style` textures of each TextureStyle, `texture_size` texels square.
  SceneBuilder(Scene& scene, std::uint64_t seed, int texture_size = 1024, int per_style = 3);

  /// One textured rectangle (see TexturedQuad) with a texture of `style`.
  void quad(SceneBody& body, const Eigen::Vector3d& origin, const Eigen::Vector3d& axis_u,
            const Eigen::Vector3d& axis_v, double size_u, double size_v, TextureStyle style,
            double texel_size, int facing = 0);
  /// A rectangle with a rectangular hole [u0, u1] x [v0, v1] (metres along the axes): up to four
  /// quads around it (a door or a window).
  void wallWithHole(SceneBody& body, const Eigen::Vector3d& origin, const Eigen::Vector3d& axis_u,
                    const Eigen::Vector3d& axis_v, double size_u, double size_v, double u0,
                    double v0, double u1, double v1, TextureStyle style, double texel_size);
  /// Axis-aligned box with six faces.
  void box(SceneBody& body, const Eigen::Vector3d& min, const Eigen::Vector3d& max,
           TextureStyle style, double texel_size);

  /// Picks a random number in [lo, hi) from the builder's generator.
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }

 private:
  int pickTexture(TextureStyle style);
  Scene& scene_;
  std::mt19937_64 rng_;
  std::vector<std::vector<int>> by_style_;
};

}  // namespace mcvio::sim
