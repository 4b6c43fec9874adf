#include "figures/sphere_render.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "spectralize/core/error.h"

namespace spectralize::figures {

Xyz mul(const Mat3& m, const Rgb& c) {
  return {m[0][0] * c.r + m[0][1] * c.g + m[0][2] * c.b,
          m[1][0] * c.r + m[1][1] * c.g + m[1][2] * c.b,
          m[2][0] * c.r + m[2][1] * c.g + m[2][2] * c.b};
}

Rgb to_rgb(const Mat3& m, const Xyz& v) {
  const Xyz r = mul(m, Rgb{v.X, v.Y, v.Z});
  return {r.X, r.Y, r.Z};
}

SphereGeometry SphereGeometry::orthographic(int size, int supersample) {
  if (size < 2 || supersample < 1)
    throw Error("sphere image needs size >= 2 and supersample >= 1 (got " + std::to_string(size) +
                ", " + std::to_string(supersample) + ")");
  SphereGeometry g;
  g.size = size;
  const std::size_t n = static_cast<std::size_t>(size) * static_cast<std::size_t>(size);
  g.shading.assign(n, 0.0);
  g.coverage.assign(n, 0.0);
  const double samples = static_cast<double>(supersample) * supersample;
  // The left half (and the middle column of odd sizes) is computed, the right half mirrored, so
  // that mirror pixels are bit-identical.
  for (int y = 0; y < size; ++y)
    for (int x = 0; 2 * x < size; ++x) {
      double shade = 0, covered = 0;
      for (int sy = 0; sy < supersample; ++sy)
        for (int sx = 0; sx < supersample; ++sx) {
          // Subsample centres, symmetric about the pixel centre.
          const double u = 2 * (x + (sx + 0.5) / supersample) / size - 1;
          const double v = 1 - 2 * (y + (sy + 0.5) / supersample) / size;
          const double r2 = u * u + v * v;
          if (r2 >= 1) continue;
          // Light at the eye: irradiance and view both along n.v; Lambert gives n.v once.
          shade += std::sqrt(1 - r2);
          covered += 1;
        }
      for (const int px : {x, size - 1 - x}) {
        const std::size_t i = static_cast<std::size_t>(y) * size + px;
        g.shading[i] = shade / samples;
        g.coverage[i] = covered / samples;
      }
    }
  return g;
}

std::vector<Xyz> render_rgb(const SphereGeometry& g, const Rgb& albedo, const Rgb& light,
                            const Mat3& rgb_to_xyz) {
  // What an RGB renderer does: multiply the colours channel by channel.
  const Rgb reflected{albedo.r * light.r, albedo.g * light.g, albedo.b * light.b};
  std::vector<Xyz> out(g.shading.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double s = g.shading[i];
    out[i] = mul(rgb_to_xyz, Rgb{reflected.r * s, reflected.g * s, reflected.b * s});
  }
  return out;
}

std::vector<Xyz> render_spectral(const SphereGeometry& g, std::span<const double> reflectance,
                                 std::span<const Xyz> band_weights, const Xyz& calibration) {
  if (reflectance.size() != band_weights.size())
    throw Error("spectral render: " + std::to_string(reflectance.size()) +
                " reflectance samples but " + std::to_string(band_weights.size()) +
                " band weights");
  const std::size_t bands = reflectance.size();
  std::vector<double> radiance(bands);
  std::vector<Xyz> out(g.shading.size());
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double s = g.shading[i];
    if (s == 0) continue;
    // Radiance per band, then the observer's integral with the light folded in.
    for (std::size_t b = 0; b < bands; ++b) radiance[b] = reflectance[b] * s;
    Xyz xyz;
    for (std::size_t b = 0; b < bands; ++b) xyz = xyz + radiance[b] * band_weights[b];
    out[i] = hadamard(xyz, calibration);
  }
  return out;
}

std::vector<Xyz> split_halves(int size, const std::vector<Xyz>& left,
                              const std::vector<Xyz>& right) {
  std::vector<Xyz> out(left.size());
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * size + x;
      out[i] = 2 * x < size ? left[i] : right[i];
    }
  return out;
}

MirrorDifference mirror_delta_e(const SphereGeometry& g, const std::vector<Xyz>& split,
                                const Xyz& white) {
  MirrorDifference d;
  d.delta_e.assign(split.size(), 0.0);
  const int size = g.size;
  double sum = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; 2 * x < size - 1; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * size + x;
      const std::size_t j = static_cast<std::size_t>(y) * size + (size - 1 - x);
      if (g.coverage[i] == 0) continue;
      const double de = delta_e_2000(to_lab(split[i], white), to_lab(split[j], white));
      d.delta_e[i] = d.delta_e[j] = de;
      d.max = std::max(d.max, de);
      sum += de;
      ++d.pairs;
    }
  d.mean = d.pairs ? sum / static_cast<double>(d.pairs) : 0.0;
  return d;
}

}  // namespace spectralize::figures
