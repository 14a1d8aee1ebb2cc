#include "mcvio/sim/mipmapped_texture.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace mcvio::sim {
namespace {

/// Float canvas with wrap-around drawing so the texture tiles seamlessly.
class Canvas {
 public:
  explicit Canvas(int size, float value) : n_(size), px_(static_cast<size_t>(size) * size, value) {}
  int size() const { return n_; }

  float& at(int x, int y) {
    x = ((x % n_) + n_) % n_;
    y = ((y % n_) + n_) % n_;
    return px_[static_cast<size_t>(y) * n_ + x];
  }

  void rect(int x0, int y0, int w, int h, float v) {
    for (int y = y0; y < y0 + h; ++y)
      for (int x = x0; x < x0 + w; ++x) at(x, y) = v;
  }

  void outline(int x0, int y0, int w, int h, int t, float v) {
    rect(x0, y0, w, t, v);
    rect(x0, y0 + h - t, w, t, v);
    rect(x0, y0, t, h, v);
    rect(x0 + w - t, y0, t, h, v);
  }

  void ellipse(int cx, int cy, int rx, int ry, float v) {
    for (int y = -ry; y <= ry; ++y)
      for (int x = -rx; x <= rx; ++x) {
        const double a = static_cast<double>(x) / rx, b = static_cast<double>(y) / ry;
        if (a * a + b * b <= 1.0) at(cx + x, cy + y) = v;
      }
  }

  void checker(int x0, int y0, int cells_x, int cells_y, int cell, float v0, float v1) {
    for (int j = 0; j < cells_y; ++j)
      for (int i = 0; i < cells_x; ++i)
        rect(x0 + i * cell, y0 + j * cell, cell, cell, ((i + j) & 1) ? v1 : v0);
  }

  std::vector<std::uint8_t> quantize() const {
    std::vector<std::uint8_t> out(px_.size());
    for (size_t i = 0; i < px_.size(); ++i)
      out[i] = static_cast<std::uint8_t>(std::clamp(std::lround(px_[i]), 0L, 255L));
    return out;
  }

 private:
  int n_;
  std::vector<float> px_;
};

class Painter {
 public:
  Painter(Canvas& c, std::uint64_t seed) : c_(c), rng_(seed) {}

  /// Uniform in [lo, hi]; lo when the range is empty (tiny textures shrink every scale).
  int uniformInt(int lo, int hi) {
    return hi <= lo ? lo : std::uniform_int_distribution<int>(lo, hi)(rng_);
  }
  float uniform(float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(rng_); }
  bool chance(double p) { return std::bernoulli_distribution(p)(rng_); }

  /// A value that contrasts with `base` by at least `min_contrast`.
  float contrasting(float base, float min_contrast) {
    const float delta = uniform(min_contrast, 130.0f);
    const float up = base + delta, down = base - delta;
    if (up > 245.0f) return std::max(down, 10.0f);
    if (down < 10.0f) return std::min(up, 245.0f);
    return chance(0.5) ? up : down;
  }

  /// Random rectangles, blobs, checker patches and outlines of about `scale` texels.
  void clutter(int scale, double density, float base) {
    const int n = c_.size();
    const int count = static_cast<int>(density * n * n / (static_cast<double>(scale) * scale)) + 1;
    for (int k = 0; k < count; ++k) {
      const int x = uniformInt(0, n - 1), y = uniformInt(0, n - 1);
      const int w = std::max(2, static_cast<int>(scale * uniform(0.4f, 1.6f)));
      const int h = std::max(2, static_cast<int>(scale * uniform(0.4f, 1.6f)));
      const float v = contrasting(base, 35.0f);
      const double kind = uniform(0.0f, 1.0f);
      if (kind < 0.55) {
        c_.rect(x, y, w, h, v);
      } else if (kind < 0.75) {
        c_.ellipse(x, y, std::max(1, w / 2), std::max(1, h / 2), v);
      } else if (kind < 0.87) {
        const int cell = std::max(2, scale / uniformInt(2, 5));
        c_.checker(x, y, std::max(2, w / cell), std::max(2, h / cell), cell, v,
                   contrasting(v, 50.0f));
      } else {
        c_.outline(x, y, w, h, std::max(1, scale / 10), v);
      }
    }
  }

  /// Rows of short dark dashes, like printed text.
  void textBlock(int x0, int y0, int w, int h, int line, float ink) {
    for (int y = y0 + line; y + line / 2 < y0 + h; y += 2 * line) {
      int x = x0 + uniformInt(0, line);
      const int end = x0 + w - uniformInt(0, w / 3);
      while (x < end) {
        const int word = uniformInt(line, 5 * line);
        c_.rect(x, y, std::min(word, end - x), std::max(1, line / 2 + 1), ink);
        x += word + uniformInt(line / 2 + 1, line + 1);
      }
    }
  }

  void poster(int x0, int y0, int w, int h) {
    const float paper = uniform(150.0f, 235.0f);
    c_.rect(x0, y0, w, h, paper);
    c_.outline(x0, y0, w, h, std::max(2, w / 60), contrasting(paper, 60.0f));
    const int margin = std::max(3, w / 12);
    const int iw = w - 2 * margin, ih = h - 2 * margin;
    if (iw < 8 || ih < 8) return;
    // Picture area, then text below it.
    const int ph = ih / 2;
    const float pic = contrasting(paper, 50.0f);
    c_.rect(x0 + margin, y0 + margin, iw, ph, pic);
    const int blobs = uniformInt(3, 8);
    for (int b = 0; b < blobs; ++b) {
      const int r = std::max(2, iw / uniformInt(6, 14));
      const int cx = x0 + margin + uniformInt(r, std::max(r, iw - r));
      const int cy = y0 + margin + uniformInt(r, std::max(r, ph - r));
      if (chance(0.5))
        c_.ellipse(cx, cy, r, r * uniformInt(1, 2), contrasting(pic, 40.0f));
      else
        c_.rect(cx - r, cy - r, 2 * r, r, contrasting(pic, 40.0f));
    }
    if (chance(0.4)) {
      const int cell = std::max(2, iw / 16);
      c_.checker(x0 + margin, y0 + margin + ph - 2 * cell, 8, 2, cell, 20.0f, 230.0f);
    }
    textBlock(x0 + margin, y0 + margin + ph + margin / 2, iw, ih - ph - margin / 2,
              std::max(2, w / 40), contrasting(paper, 90.0f));
  }

 private:
  Canvas& c_;
  std::mt19937_64 rng_;
};

void paintClutter(Canvas& c, Painter& p) {
  const int n = c.size();
  const float base = p.uniform(80.0f, 170.0f);
  c.rect(0, 0, n, n, base);
  const int scales[] = {n / 3, n / 6, n / 12, n / 24, n / 48, n / 96};
  const double density[] = {0.5, 0.5, 0.45, 0.35, 0.25, 0.15};
  for (int i = 0; i < 6; ++i) p.clutter(std::max(2, scales[i]), density[i], base);
}

void paintTiles(Canvas& c, Painter& p) {
  const int n = c.size();
  const int tiles = 1 << p.uniformInt(2, 3);  // 4 or 8 tiles per texture edge
  const int t = n / tiles;
  const float base = p.uniform(110.0f, 190.0f);
  for (int j = 0; j < tiles; ++j)
    for (int i = 0; i < tiles; ++i) {
      const float shade = base + p.uniform(-35.0f, 35.0f);
      c.rect(i * t, j * t, t, t, shade);
      if (p.chance(0.25)) {  // a patterned tile
        const int cell = std::max(1, t / (2 * p.uniformInt(1, 3)));
        c.checker(i * t, j * t, t / cell, t / cell, cell, shade, p.contrasting(shade, 40.0f));
      }
    }
  p.clutter(std::max(2, n / 40), 0.25, base);   // scuffs and objects
  p.clutter(std::max(2, n / 150), 0.08, base);  // speckle
  const int grout = std::max(2, n / 200);
  const float grout_value = base - 70.0f;
  for (int k = 0; k < tiles; ++k) {
    c.rect(k * t, 0, grout, n, grout_value);
    c.rect(0, k * t, n, grout, grout_value);
  }
}

void paintBricks(Canvas& c, Painter& p) {
  const int n = c.size();
  const int rows = 16;
  const int h = n / rows;
  const int len = 2 * h;
  const float mortar = p.uniform(150.0f, 200.0f);
  c.rect(0, 0, n, n, mortar);
  const int joint = std::max(2, h / 8);
  for (int r = 0; r < rows; ++r) {
    const int offset = (r & 1) ? len / 2 : 0;
    for (int x = 0; x < n; x += len) {
      const float v = p.uniform(60.0f, 140.0f);
      c.rect(x + offset + joint, r * h + joint, len - joint, h - joint, v);
      if (p.chance(0.3)) c.rect(x + offset + p.uniformInt(joint, len / 2), r * h + p.uniformInt(joint, h / 2),
                                p.uniformInt(2, len / 4), p.uniformInt(2, h / 3), p.contrasting(v, 30.0f));
    }
  }
  p.clutter(std::max(2, n / 12), 0.08, mortar);  // signs, pipes
}

void paintPosters(Canvas& c, Painter& p) {
  const int n = c.size();
  const float wall = p.uniform(90.0f, 180.0f);
  c.rect(0, 0, n, n, wall);
  p.clutter(std::max(2, n / 100), 0.06, wall);  // marks on the paint
  const int posters = p.uniformInt(4, 7);
  for (int k = 0; k < posters; ++k) {
    const int w = p.uniformInt(n / 7, n / 3);
    const int h = static_cast<int>(w * p.uniform(0.8f, 1.5f));
    p.poster(p.uniformInt(0, n - 1), p.uniformInt(0, n - 1), w, h);
  }
  p.clutter(std::max(2, n / 20), 0.12, wall);  // switches, frames, boxes
}

bool isPowerOfTwo(int n) { return n > 0 && (n & (n - 1)) == 0; }

}  // namespace

MipmappedTexture MipmappedTexture::generate(TextureStyle style, int size, std::uint64_t seed) {
  if (!isPowerOfTwo(size) || size < 16)
    throw std::invalid_argument("MipmappedTexture: size must be a power of two >= 16");
  Canvas canvas(size, 128.0f);
  Painter painter(canvas, seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(style));
  switch (style) {
    case TextureStyle::kClutter: paintClutter(canvas, painter); break;
    case TextureStyle::kTiles: paintTiles(canvas, painter); break;
    case TextureStyle::kBricks: paintBricks(canvas, painter); break;
    case TextureStyle::kPosters: paintPosters(canvas, painter); break;
  }
  return MipmappedTexture(size, canvas.quantize());
}

MipmappedTexture::MipmappedTexture(int size, const std::vector<std::uint8_t>& level0) : size_(size) {
  if (!isPowerOfTwo(size) || level0.size() != static_cast<size_t>(size) * size)
    throw std::invalid_argument("MipmappedTexture: level 0 must be size x size, power of two");
  std::vector<std::vector<std::uint8_t>> rows{level0};
  for (int n = size / 2; n >= 1; n /= 2) {
    const auto& prev = rows.back();
    const int pn = 2 * n;
    std::vector<std::uint8_t> next(static_cast<size_t>(n) * n);
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        const size_t i = static_cast<size_t>(2 * y) * pn + 2 * x;
        next[static_cast<size_t>(y) * n + x] =
            static_cast<std::uint8_t>((prev[i] + prev[i + 1] + prev[i + pn] + prev[i + pn + 1] + 2) / 4);
      }
    rows.push_back(std::move(next));
  }
  levels_ = std::move(rows);
}

}  // namespace mcvio::sim
