// The environment map's sampling: the density is normalised over the sphere (the test's own
// numerical integral), sample() draws texels in proportion to luminance times solid angle and
// reports the density pdf() gives, and a white surface under uniform radiance L reflects L.

#include "path_tracer/environment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "../test_support.h"

namespace spectralize::path_tracer {
namespace {

constexpr double kPi = std::numbers::pi;

std::vector<Xyz> random_map(int w, int h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.01, 3.0);
  std::vector<Xyz> m(static_cast<std::size_t>(w) * h);
  for (Xyz& v : m) {
    const double y = u(rng);
    v = {0.9 * y, y, 1.1 * y};
  }
  return m;
}

Vec3 direction(double theta, double phi) {
  return {std::sin(phi) * std::sin(theta), std::cos(theta), -std::cos(phi) * std::sin(theta)};
}

TEST(Environment, DensityIntegratesToOneOverTheSphere) {
  const Environment env(16, 8, random_map(16, 8, 7));
  // Midpoint rule over (theta, phi), dOmega = sin theta dtheta dphi.
  const int n = 800;
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double theta = (i + 0.5) * kPi / n, phi = (j + 0.5) * kPi / n;
      sum += env.pdf(direction(theta, phi)) * std::sin(theta) * (kPi / n) * (kPi / n);
    }
  EXPECT_NEAR(sum, 1.0, 1e-3);
}

TEST(Environment, SamplesFollowLuminanceTimesSolidAngle) {
  const int w = 8, h = 4;
  std::vector<Xyz> map(static_cast<std::size_t>(w) * h, Xyz{1, 1, 1});
  map[1 * w + 5] = {20, 20, 20};  // one bright texel in the upper half
  const Environment env(w, h, map);
  // The probability of texel (x, y): Y times its solid angle (2 pi / w)(cos a - cos b), normalised.
  std::vector<double> want(map.size());
  double total = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double omega = 2 * kPi / w * (std::cos(kPi * y / h) - std::cos(kPi * (y + 1) / h));
      want[y * w + x] = map[y * w + x].Y * omega;
      total += want[y * w + x];
    }
  std::vector<int> count(map.size(), 0);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  const int n = 400000;
  for (int i = 0; i < n; ++i) {
    const EnvironmentSample s = env.sample(u(rng), u(rng), u(rng), u(rng));
    ++count[s.texel];
    if (i < 2000) {
      EXPECT_EQ(env.texel(s.direction), s.texel);
      EXPECT_NEAR(s.pdf, env.pdf(s.direction), 1e-9 * s.pdf);
      EXPECT_NEAR(dot(s.direction, s.direction), 1.0, 1e-12);
    }
  }
  // Rows are weighted by the texel-centre sine, which for 4 rows symmetric about the horizon
  // is in exact proportion to the rows' solid angles; frequencies within 5 sigma.
  for (std::size_t t = 0; t < map.size(); ++t) {
    const double p = want[t] / total;
    EXPECT_NEAR(count[t] / static_cast<double>(n), p, 5 * std::sqrt(p * (1 - p) / n)) << t;
  }
}

TEST(Environment, IrradianceEstimatorIsUnbiased) {
  // E[cos+ L / pdf] over sample() is the irradiance of an upward surface, pi times white_up().
  const Environment env(32, 16, random_map(32, 16, 11));
  std::vector<Xyz> map = random_map(32, 16, 11);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  double sum = 0;
  const int n = 400000;
  for (int i = 0; i < n; ++i) {
    const EnvironmentSample s = env.sample(u(rng), u(rng), u(rng), u(rng));
    if (s.direction.y > 0) sum += s.direction.y * map[s.texel].Y / s.pdf;
  }
  EXPECT_NEAR(sum / n, kPi * env.white_up().Y, 0.01 * kPi * env.white_up().Y);
}

TEST(Environment, WhiteSurfaceUnderUniformRadianceReflectsIt) {
  const Environment env(64, 32, std::vector<Xyz>(64 * 32, Xyz{0.5, 0.6, 0.7}));
  const Xyz w = env.white_up();
  EXPECT_NEAR(w.X, 0.5, 1e-12);
  EXPECT_NEAR(w.Y, 0.6, 1e-12);
  EXPECT_NEAR(w.Z, 0.7, 1e-12);
}

TEST(Environment, TexelsOfDirections) {
  const Environment env(8, 4, std::vector<Xyz>(32, Xyz{1, 1, 1}));
  EXPECT_LT(env.texel({0, 1, 0}), 8u);                            // straight up: row 0
  EXPECT_EQ(env.texel(normalize({0, 0.01, -1})), 1u * 8 + 0);     // -z above the horizon: column 0
  EXPECT_EQ(env.texel(normalize({1, -0.01, 0})), 2u * 8 + 2);     // +x below it: a quarter round
  EXPECT_EQ(env.texel(normalize({-0.01, -1.2, 1})), 3u * 8 + 4);  // +z, down: half round
}

TEST(Environment, RefusesMapsWithoutLight) {
  test::expect_error_mentioning([] { Environment(4, 2, std::vector<Xyz>(8, Xyz{})); },
                                {"positive luminance"}, "dark");
  auto seven_texels = [] { Environment(4, 2, std::vector<Xyz>(7, Xyz{1, 1, 1})); };
  test::expect_error_mentioning(seven_texels, {"4 x 2", "7"}, "size");
}

}  // namespace
}  // namespace spectralize::path_tracer
