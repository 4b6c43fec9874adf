// ConvexGamut (include/spectralize/core/gamut.h, docs/DESIGN.md §5): the spectral locus (the cone
// of every non-negative spectrum's colour) and the reflectance solid (the colours of 0 <= rho <=
// 1) as half-spaces. Oracles: generators whose gamuts are known by hand (the unit axes: the
// octant and the unit cube); colours integrated here (test_support.h) of random spectra, which
// must be inside, and of support points (0/1 spectra maximising n . t) and single wavelengths,
// which lie on the boundary; bisection for the steps.

#include "spectralize/core/gamut.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "spectralize/core/colorimetry.h"
#include "spectralize/core/sample_weights.h"
#include "spectralize/core/wavelength_grid.h"
#include "test_support.h"

namespace spectralize {
namespace {

using test::reference_xyz;

const std::vector<Xyz> kAxes = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

// The default grid's weights: reflectance under D65 or emission.
struct Weights {
  WavelengthGrid grid;
  Illuminant d65 = Illuminant::get("D65");
  bool reflectance;
  SampleWeights w;
  explicit Weights(bool refl)
      : reflectance(refl), w(grid, Observer::get("cie1931"), refl ? &d65 : nullptr) {}
  // The colour of a spectrum by the test's own integration.
  Xyz colour(const std::vector<double>& s) const {
    return reference_xyz(grid, s, Observer::get("cie1931"), reflectance ? &d65.spd : nullptr);
  }
};

TEST(ConvexGamut, TheUnitAxesSpanTheOctantAndTheUnitCube) {
  const ConvexGamut cube = ConvexGamut::reflectance_solid(kAxes);
  const ConvexGamut octant = ConvexGamut::spectral_locus(kAxes);
  EXPECT_EQ(cube.scale(), 1.0);
  // The cube's six faces: normal +e_k at offset 1, -e_k at offset 0.
  ASSERT_EQ(cube.facets(), 6u);
  int plus = 0, minus = 0;
  for (std::size_t f = 0; f < cube.facets(); ++f) {
    const Xyz n = cube.normal(f);
    EXPECT_EQ(std::abs(n.X) + std::abs(n.Y) + std::abs(n.Z), 1.0) << f;
    EXPECT_EQ(n.max_abs(), 1.0);
    if (n.sum() > 0) {
      ++plus;
      EXPECT_EQ(cube.offset(f), 1.0);
    } else {
      ++minus;
      EXPECT_EQ(cube.offset(f), 0.0);
    }
  }
  EXPECT_EQ(plus, 3);
  EXPECT_EQ(minus, 3);
  // The octant's three faces through black, outward normals -e_k.
  ASSERT_EQ(octant.facets(), 3u);
  for (std::size_t f = 0; f < octant.facets(); ++f) {
    EXPECT_EQ(octant.normal(f).sum(), -1.0);
    EXPECT_EQ(octant.offset(f), 0.0);
  }
  for (const Xyz& in : {Xyz{0.5, 0.5, 0.5}, Xyz{1, 1, 1}, Xyz{0, 0, 0}, Xyz{1, 0, 0.3}}) {
    EXPECT_TRUE(cube.contains(in));
    EXPECT_TRUE(octant.contains(in));
  }
  // Just outside the cube (1e-9 is far beyond the 1e-12 tolerance); the octant is unbounded.
  for (const Xyz& out : {Xyz{1 + 1e-9, 0.5, 0.5}, Xyz{0.5, 1 + 1e-9, 0.5}, Xyz{0.5, 0.5, 1 + 1e-9},
                         Xyz{3, 0.5, 0.5}}) {
    EXPECT_FALSE(cube.contains(out)) << out.X << " " << out.Y << " " << out.Z;
    EXPECT_TRUE(octant.contains(out));
  }
  for (const Xyz& out : {Xyz{-1e-9, 0.5, 0.5}, Xyz{0.5, -1e-9, 0.5}, Xyz{0.5, 0.5, -1e-9}}) {
    EXPECT_FALSE(cube.contains(out));
    EXPECT_FALSE(octant.contains(out));
  }
  EXPECT_TRUE(octant.contains({1e6, 2e6, 1e-3}));
}

TEST(ConvexGamut, MaxStepIsTheFractionOfTheSegmentInside) {
  const ConvexGamut cube = ConvexGamut::reflectance_solid(kAxes);
  const ConvexGamut octant = ConvexGamut::spectral_locus(kAxes);
  // From the centre toward x = 2 the face x = 1 is a third of the way (0.5 / 1.5, to rounding).
  EXPECT_NEAR(cube.max_step({0.5, 0.5, 0.5}, {2, 0.5, 0.5}), 1.0 / 3, 1e-15);
  EXPECT_NEAR(cube.max_step({0.5, 0.5, 0.5}, {0.5, -0.5, 2}), 0.5 / 1.5, 1e-15);  // z = 1 first
  EXPECT_EQ(cube.max_step({0.5, 0.5, 0.5}, {0.9, 0.1, 0.7}), 1.0);  // inside: the whole way
  EXPECT_EQ(cube.max_step({1, 0.5, 0.5}, {2, 0.5, 0.5}), 0.0);      // on a face, going out
  EXPECT_EQ(cube.max_step({1, 0.5, 0.5}, {0, 0.5, 0.5}), 1.0);      // on a face, going in
  EXPECT_NEAR(octant.max_step({1, 1, 1}, {-1, 1, 1}), 0.5, 1e-15);
  EXPECT_EQ(octant.max_step({1, 1, 1}, {100, 1, 1}), 1.0);
}

TEST(ConvexGamut, ParallelAndZeroGeneratorsOnlyAddTheirLength) {
  // A repeated generator lengthens the solid along it (two samples of the same colour, each
  // up to 1), a zero one (a sample with no weight) changes nothing; the cone is the same.
  const std::vector<Xyz> g = {{1, 0, 0}, {1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const ConvexGamut box = ConvexGamut::reflectance_solid(g);
  const ConvexGamut octant = ConvexGamut::spectral_locus(g);
  EXPECT_EQ(box.scale(), 2.0);
  EXPECT_TRUE(box.contains({1.9, 0.5, 0.5}));
  EXPECT_TRUE(box.contains({2, 1, 1}));
  EXPECT_FALSE(box.contains({2 + 1e-9, 0.5, 0.5}));
  EXPECT_FALSE(box.contains({1.9, 1 + 1e-9, 0.5}));
  EXPECT_FALSE(box.contains({-1e-9, 0.5, 0.5}));
  EXPECT_TRUE(octant.contains({7, 0, 3}));
  EXPECT_FALSE(octant.contains({7, -1e-9, 3}));
  for (std::size_t f = 0; f < box.facets(); ++f) {
    const Xyz n = box.normal(f);
    EXPECT_NEAR(dot(n, n), 1.0, 1e-15);  // unit normals
  }
}

TEST(ConvexGamut, EveryReflectanceIsInsideTheSolidAndSupportPointsOnItsBoundary) {
  const Weights w(true);
  const ConvexGamut solid = ConvexGamut::reflectance_solid(w.w.columns());
  const std::size_t n = w.grid.size();
  std::mt19937 rng(41);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // Random reflectances: inside.
  for (int k = 0; k < 300; ++k) {
    std::vector<double> rho(n);
    const double top = u(rng);
    for (double& v : rho) v = top * u(rng);
    ASSERT_TRUE(solid.contains(w.colour(rho))) << k;
  }
  // Support points: for a direction n, the reflectance that is 1 where n . W_i > 0 and 0
  // elsewhere has the largest n . t of all reflectances, so its colour is on the boundary:
  // inside, 1e-7 of the white beyond it along n outside, and the ray from the grey of half the
  // white through it leaves the solid there (max_step toward twice as far: 0.5).
  const Xyz grey = 0.5 * w.colour(std::vector<double>(n, 1.0));
  std::normal_distribution<double> normal;
  for (int k = 0; k < 200; ++k) {
    Xyz dir{normal(rng), normal(rng), normal(rng)};
    dir = (1 / std::sqrt(dot(dir, dir))) * dir;
    std::vector<double> rho(n);
    for (std::size_t i = 0; i < n; ++i) rho[i] = dot(dir, w.w.columns()[i]) > 0 ? 1.0 : 0.0;
    const Xyz t = w.colour(rho);
    EXPECT_TRUE(solid.contains(t)) << k;
    EXPECT_FALSE(solid.contains(t + (1e-7 * grey.max_abs()) * dir)) << k;  // also at black
    EXPECT_NEAR(solid.max_step(grey, grey + 2.0 * (t - grey)), 0.5, 1e-9) << k;
  }
  // Brighter than the perfect reflector, or of negative luminance: outside.
  EXPECT_FALSE(solid.contains(2.0 * (1 + 1e-9) * grey));
  EXPECT_TRUE(solid.contains(2.0 * grey));
  EXPECT_FALSE(solid.contains({0.1, -1e-3, 0.1}));
}

TEST(ConvexGamut, EveryLightIsInsideTheLocusAndSingleWavelengthsOnItsBoundary) {
  const Weights w(false);
  const ConvexGamut locus = ConvexGamut::spectral_locus(w.w.columns());
  const std::size_t n = w.grid.size();
  std::mt19937 rng(43);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 300; ++k) {
    std::vector<double> phi(n);
    for (double& v : phi) v = std::pow(10.0, 8 * u(rng) - 4);  // spiky: 8 decades
    const Xyz t = w.colour(phi);
    for (double scale : {1e-6, 1.0, 1e6}) {
      ASSERT_TRUE(locus.contains(scale * t)) << k << " x " << scale;
    }
  }
  // A single wavelength (450..560 nm: there the sampled locus is strictly convex; from ~575 nm
  // on it is so nearly straight that not every 5 nm sample is a vertex of it) and a light of
  // two neighbouring samples are on the boundary: a relative 1e-7 beyond them, away from the
  // equal-energy white of the same luminance, is outside.
  const Xyz white = w.colour(std::vector<double>(n, 1.0));
  for (std::size_t i = 14; i <= 36; ++i) {
    for (std::size_t width : {1, 2}) {
      std::vector<double> phi(n, 0.0);
      for (std::size_t j = i; j < i + width; ++j) phi[j] = 1.0;
      const Xyz t = w.colour(phi);
      const Xyz centre = (t.Y / white.Y) * white;
      EXPECT_TRUE(locus.contains(t)) << w.grid[i] << " nm";
      EXPECT_FALSE(locus.contains(t + 1e-7 * (t - centre))) << w.grid[i] << " nm";
    }
  }
  EXPECT_FALSE(locus.contains({-1e-3, 1, 1}));  // xbar >= 0: no light has X < 0
  EXPECT_FALSE(locus.contains({0.3, -1e-3, 0.3}));
}

TEST(ConvexGamut, ContainmentIsRelativeToTheColourNearBlack) {
  // Near black both gamuts are the cone and the containment test is relative to the colour
  // (gamut.h: "to 1e-12 of |t|"): a colour a relative 1e-8 outside a single wavelength's
  // colour (460, 500, 550 nm: vertices of the locus) is outside at every scale down to 1e-6 of
  // it, one a relative 1e-8 inside is inside.
  for (bool reflectance : {true, false}) {
    const Weights w(reflectance);
    const ConvexGamut g = reflectance ? ConvexGamut::reflectance_solid(w.w.columns())
                                      : ConvexGamut::spectral_locus(w.w.columns());
    const std::size_t n = w.grid.size();
    const Xyz white = w.colour(std::vector<double>(n, 1.0));
    for (std::size_t i : {16, 24, 34}) {
      std::vector<double> phi(n, 0.0);
      phi[i] = 1.0;
      const Xyz t = w.colour(phi);
      const Xyz centre = (t.Y / white.Y) * white;
      for (double k : {1.0, 1e-3, 1e-6}) {
        SCOPED_TRACE((reflectance ? "solid, " : "locus, ") + std::to_string(w.grid[i]) +
                     " nm, scale " + std::to_string(k));
        EXPECT_FALSE(g.contains(k * (t + 1e-8 * (t - centre))));
        EXPECT_TRUE(g.contains(k * (t - 1e-8 * (t - centre))));
      }
    }
  }
}

TEST(ConvexGamut, MaxStepAgreesWithBisectionOnContainment) {
  // Rays from the grey of 30% luminance toward 24 hues: max_step is where contains() flips,
  // found by bisection (60 halvings), to 1e-9 of the segment.
  const Weights w(true);
  const ConvexGamut solid = ConvexGamut::reflectance_solid(w.w.columns());
  const Xyz white = w.colour(std::vector<double>(w.grid.size(), 1.0));
  const Xyz grey = 0.3 * white;
  const double x0 = white.X / white.sum(), y0 = white.Y / white.sum();
  for (int h = 0; h < 24; ++h) {
    const double a = 2 * M_PI * h / 24;
    const Xyz far = test::xyz_from_xy(x0 + 0.6 * std::cos(a), y0 + 0.6 * std::sin(a), 0.3);
    ASSERT_FALSE(solid.contains(far)) << h;
    double lo = 0, hi = 1;
    for (int k = 0; k < 60; ++k) {
      const double mid = 0.5 * (lo + hi);
      (solid.contains(grey + mid * (far - grey)) ? lo : hi) = mid;
    }
    const double s = solid.max_step(grey, far);
    EXPECT_NEAR(s, lo, 1e-9) << "hue " << h;
    EXPECT_TRUE(solid.contains(grey + s * (far - grey)));
  }
}

}  // namespace
}  // namespace spectralize
