#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mcvio::sim {

/// Kinds of procedural pattern, all rich in corners at several scales.
enum class TextureStyle : std::uint8_t {
  kClutter = 0,  ///< overlapping rectangles, blobs and marks from metres down to millimetres
  kTiles = 1,    ///< floor/ceiling tiles with grout, speckle and stains
  kBricks = 2,   ///< brick courses with varied bricks and small marks
  kPosters = 3,  ///< a plain wall with posters/panels carrying fine detail
};

/// A square, tileable (wrap-around), 8-bit grayscale texture with a full mip-map pyramid.
/// Sampling blends bilinear samples of the two levels bracketing the requested level of detail
/// (narrowed to the middle half of each octave to halve memory traffic), so distant surfaces are
/// pre-filtered instead of aliasing and level changes leave no seams. Levels are row-major: an
/// 8x8-blocked layout measured slower here (sampling is bound by arithmetic, not memory).
class MipmappedTexture {
 public:
  /// Builds a procedural texture of size x size texels (a power of two >= 16), reproducible for
  /// a seed.
  static MipmappedTexture generate(TextureStyle style, int size, std::uint64_t seed);

  /// Wraps an existing row-major level-0 image (size x size, power of two) and builds its pyramid.
  MipmappedTexture(int size, const std::vector<std::uint8_t>& level0);

  /// Intensity [0, 255] at texel coordinates (u, v) of level 0 (texel centres at +0.5), with
  /// lod = log2(texels per pixel); lod <= 0 samples level 0.
  float sample(float u, float v, float lod) const {
    const int last = static_cast<int>(levels_.size()) - 1;
    if (lod <= 0.0f) return bilinear(0, u, v);
    if (lod >= static_cast<float>(last)) return levels_.back()[0];
    const int l0 = static_cast<int>(lod);
    // Blend only in the middle of the octave ("brilinear"): continuous, and one level elsewhere.
    const float f = (lod - static_cast<float>(l0) - 0.25f) * 2.0f;
    const float s0 = 1.0f / static_cast<float>(1 << l0);
    if (f <= 0.0f) return bilinear(l0, u * s0, v * s0);
    const float b = bilinear(l0 + 1, u * s0 * 0.5f, v * s0 * 0.5f);
    if (f >= 1.0f) return b;
    const float a = bilinear(l0, u * s0, v * s0);
    return a + f * (b - a);
  }

  int size() const { return size_; }
  int levels() const { return static_cast<int>(levels_.size()); }
  /// Texel (x, y) of level l (0 <= x, y < size >> l).
  std::uint8_t texel(int l, int x, int y) const {
    return levels_[static_cast<size_t>(l)][index(size_ >> l, x, y)];
  }

 private:
  static size_t index(int n, int x, int y) { return static_cast<size_t>(y) * n + x; }

  float bilinear(int level, float x, float y) const {
    const int n = size_ >> level;
    const int mask = n - 1;
    const std::uint8_t* img = levels_[static_cast<size_t>(level)].data();
    // 24.8 fixed point: the integer part (floored by the arithmetic shift, also for negative
    // coordinates) wraps with the mask, the low 8 bits weight the neighbours.
    const int X = static_cast<int>((x - 0.5f) * 256.0f), Y = static_cast<int>((y - 0.5f) * 256.0f);
    const int x0 = (X >> 8) & mask, y0 = (Y >> 8) & mask;
    const int x1 = (x0 + 1) & mask, y1 = (y0 + 1) & mask;
    const int fx = X & 255, fy = Y & 255;
    const int a = img[index(n, x0, y0)], b = img[index(n, x1, y0)];
    const int c = img[index(n, x0, y1)], d = img[index(n, x1, y1)];
    const int top = (a << 8) + fx * (b - a), bottom = (c << 8) + fx * (d - c);
    return static_cast<float>((top << 8) + fy * (bottom - top)) * (1.0f / 65536.0f);
  }

  int size_ = 0;
  std::vector<std::vector<std::uint8_t>> levels_;  // row-major, level 0 first
};

}  // namespace mcvio::sim
