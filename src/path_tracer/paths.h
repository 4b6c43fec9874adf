#pragma once
// Path sampling, separated from the spectra. With Lambertian surfaces and no dispersion a path's
// geometry does not depend on wavelength, so a path is traced once into a record: the texels it
// hits and its light terms (next-event estimates of the environment, or the environment seen
// directly). Any set of spectra then evaluates the same record at any wavelengths: the renders
// being compared share their paths exactly, and differ only by their spectra and wavelengths.

#include <array>
#include <cstdint>

#include "path_tracer/environment.h"
#include "path_tracer/scene.h"

namespace spectralize::path_tracer {

/// Surface vertices per path at most (the path ends after the last one's light estimate).
inline constexpr int kMaxVertices = 3;

/// One light estimate: environment texel `texel`'s radiance times `weight` times the
/// reflectances of the path's first `depth` vertices.
struct LightTerm {
  std::uint32_t texel = 0;
  std::uint32_t depth = 0;
  float weight = 0;
};

/// A traced path: the surface texel of each vertex, and its light terms by increasing depth.
struct PathRecord {
  std::array<std::uint32_t, kMaxVertices> vertex_texel{};
  int vertices = 0;
  std::array<LightTerm, kMaxVertices + 1> terms{};
  int term_count = 0;
};

/// Uniform random numbers in [0, 1) for one (pixel, sample): a counter-based generator
/// (SplitMix64 of the pixel, the sample and a stream), so any render draws the same numbers for
/// the same path whatever the order or the threads.
class SampleStream {
 public:
  SampleStream(std::uint64_t pixel, std::uint64_t sample, std::uint64_t stream);
  /// The next number. Cost: O(1).
  double next();

 private:
  std::uint64_t state_;
};

/// Traces sample `sample` of pixel (px, py) of a size x size image: a jittered camera ray; at
/// each surface vertex one environment sample (a light term when unshadowed) and a
/// cosine-distributed bounce; a camera ray that misses sees the environment (a term of depth 0).
/// Cost: O(kMaxVertices) rays.
PathRecord trace_path(const Scene& scene, const Environment& environment, int px, int py, int size,
                      std::uint64_t sample);

/// The wavelength offset of sample `sample` of pixel `pixel` (a stream of its own, so the
/// wavelengths do not depend on the path's length). Cost: O(1).
double wavelength_offset(std::uint64_t pixel, std::uint64_t sample);

}  // namespace spectralize::path_tracer
