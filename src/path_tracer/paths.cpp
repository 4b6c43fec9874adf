#include "path_tracer/paths.h"

#include <cmath>
#include <numbers>

namespace spectralize::path_tracer {

namespace {

std::uint64_t splitmix64(std::uint64_t& x) {
  std::uint64_t z = (x += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

constexpr std::uint64_t kPathStream = 1, kWavelengthStream = 2;

// A direction about `n` with density cos(theta) / pi (Malley's method: a uniform point on the
// disc lifted to the hemisphere).
Vec3 cosine_direction(const Vec3& n, double u1, double u2) {
  const double r = std::sqrt(u1), phi = 2 * std::numbers::pi * u2;
  const double a = r * std::cos(phi), b = r * std::sin(phi), c = std::sqrt(std::max(0.0, 1 - u1));
  // An orthonormal frame around n.
  const Vec3 t =
      std::abs(n.x) > 0.5 ? normalize(cross(n, Vec3{0, 1, 0})) : normalize(cross(n, Vec3{1, 0, 0}));
  const Vec3 s = cross(n, t);
  return normalize(a * t + b * s + c * n);
}

}  // namespace

SampleStream::SampleStream(std::uint64_t pixel, std::uint64_t sample, std::uint64_t stream) {
  // Chained hashes: distinct (pixel, sample, stream) give unrelated states.
  std::uint64_t x = pixel;
  x = splitmix64(x) + sample;
  x = splitmix64(x) + stream;
  state_ = splitmix64(x);
}

double SampleStream::next() {
  // 53 random bits: a double in [0, 1).
  return static_cast<double>(splitmix64(state_) >> 11) * 0x1.0p-53;
}

double wavelength_offset(std::uint64_t pixel, std::uint64_t sample) {
  return SampleStream(pixel, sample, kWavelengthStream).next();
}

PathRecord trace_path(const Scene& scene, const Environment& env, int px, int py, int size,
                      std::uint64_t sample) {
  const std::uint64_t pixel = static_cast<std::uint64_t>(py) * size + px;
  SampleStream rng(pixel, sample, kPathStream);
  PathRecord path;
  const double jx = rng.next(), jy = rng.next();
  Ray ray = scene.camera_ray(px + jx, py + jy, size);
  for (int depth = 0; depth < kMaxVertices; ++depth) {
    const std::optional<Hit> hit = scene.intersect(ray);
    if (!hit) {
      // Only camera rays see the environment directly; later misses are counted by the light
      // estimates at the vertices (next-event estimation alone, no double counting).
      if (depth == 0) path.terms[path.term_count++] = {env.texel(ray.direction), 0, 1.0f};
      break;
    }
    path.vertex_texel[path.vertices++] = hit->texel;
    // Light estimate: rho / pi * L * cos / pdf, unshadowed.
    const double u1 = rng.next(), u2 = rng.next(), u3 = rng.next(), u4 = rng.next();
    const EnvironmentSample light = env.sample(u1, u2, u3, u4);
    const double cosine = dot(hit->normal, light.direction);
    if (cosine > 0 && light.pdf > 0 && !scene.occluded({hit->point, light.direction}))
      path.terms[path.term_count++] = {light.texel, static_cast<std::uint32_t>(depth + 1),
                                       static_cast<float>(cosine / (std::numbers::pi * light.pdf))};
    // The bounce: cosine-distributed, so the Lambertian weight is rho alone.
    const double b1 = rng.next(), b2 = rng.next();
    ray = {hit->point, cosine_direction(hit->normal, b1, b2)};
  }
  return path;
}

}  // namespace spectralize::path_tracer
