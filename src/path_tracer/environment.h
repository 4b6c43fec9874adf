#pragma once
// The light: an environment map in latitude-longitude layout (the testimages/ HDRIs), constant
// over each texel, sampled in proportion to each texel's luminance times its solid angle.
// Geometry and probabilities only: what the texels emit at each wavelength is a SpectralTexture.

#include <cstdint>
#include <vector>

#include "path_tracer/scene.h"
#include "spectralize/core/xyz.h"

namespace spectralize::path_tracer {

/// A direction drawn from the map, with its texel and its probability density per steradian.
struct EnvironmentSample {
  Vec3 direction;
  std::uint32_t texel = 0;
  double pdf = 0;
};

class Environment {
 public:
  /// A width x height map (row 0 looks up, +y; column 0 looks along -z, then towards +x)
  /// whose texel t emits radiance of colour xyz[t]. Throws Error for a map smaller than 2 x 2,
  /// a wrong number of texels, or one with no positive luminance. Cost: O(texels).
  Environment(int width, int height, std::vector<Xyz> xyz);

  /// The texel a direction (unit length) looks at. Cost: O(1).
  std::uint32_t texel(const Vec3& direction) const;
  /// A direction with probability proportional to luminance x solid angle: a texel from the
  /// marginal and conditional tables by (u1, u2), a uniform point inside it by (u3, u4).
  /// Cost: O(log texels).
  EnvironmentSample sample(double u1, double u2, double u3, double u4) const;
  /// The density sample() draws `direction` with, per steradian. Cost: O(1).
  double pdf(const Vec3& direction) const;
  /// The XYZ a white Lambertian surface facing up (+y), unshadowed, reflects: (1/pi) times the
  /// integral of the map's radiance over the upper hemisphere, weighted by the cosine; the
  /// white of CIELAB for the renders. Cost: O(texels).
  Xyz white_up() const;

  int width() const { return w_; }
  int height() const { return h_; }

 private:
  Vec3 direction_of(double u, double v) const;
  int w_, h_;
  std::vector<Xyz> xyz_;
  std::vector<double> row_cdf_;     // h + 1 values, 0 .. 1
  std::vector<double> column_cdf_;  // per row, w + 1 values, 0 .. 1
  std::vector<double> texel_pmf_;   // probability of each texel
};

}  // namespace spectralize::path_tracer
