// The gamuts' boundaries in the exact table's coordinates (docs/DESIGN.md §14): the closed-form
// spectrum of a boundary point reproduces it (the test's own integration of the CSV tables)
// with every sample 0 or 1 but two; facets contain the solid; the locus polygon holds every
// sample's chromaticity and its edge spectra are two-sample lights of X+Y+Z = 1.

#include <gtest/gtest.h>

#include <random>

#include "core/gamut/gamut_boundary.h"
#include "spectralize/core/spectralizer.h"
#include "test_support.h"

namespace spectralize {
namespace {

// The test's own weights: the reference integration of each sample's unit spectrum.
std::vector<Xyz> own_weights(bool reflectance) {
  const WavelengthGrid grid;
  const Observer& obs = Observer::get("cie1931");
  const Illuminant d65 = Illuminant::get("D65");
  std::vector<Xyz> w;
  for (std::size_t k = 0; k < grid.size(); ++k) {
    std::vector<double> e(grid.size(), 0.0);
    e[k] = 1;
    w.push_back(test::reference_xyz(grid, e, obs, reflectance ? &d65.spd : nullptr));
  }
  return w;
}

Mat3 frame_of(const test::Mat3& m) {
  Mat3 f;
  for (int i = 0; i < 9; ++i) f[i] = m[i / 3][i % 3];
  return f;
}

TEST(SolidBoundary, BoundarySpectraReproduceTheirPointAndAreZeroOrOneButTwo) {
  SpectralizerSettings s;
  s.mode = Mode::reflectance;
  const Spectralizer sp(s);
  const std::vector<Xyz> w = own_weights(true);
  for (const test::Mat3& m : {test::kRec709ToXyz, test::kRec2020ToXyz}) {
    const Mat3 frame = scale_rows(sp.target_of({1, 1, 1}), frame_of(m));
    const SolidBoundary solid(sp.weights().columns(), frame);
    const Mat3 to_u = inverse(frame);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-1, 2);
    double worst = 0;
    for (int k = 0; k < 3000; ++k) {
      // A ray from mid grey through a random point meets the boundary at b.
      const Xyz grey{0.5, 0.5, 0.5}, p{u(rng), u(rng), u(rng)};
      const Xyz b = grey + solid.max_step(grey, p) * (p - grey);
      EXPECT_NEAR(solid.distance(b), 0.0, 1e-12);
      const BoundarySpectrum spectrum = solid.spectrum(b);
      std::vector<double> v(w.size());
      int fractional = 0;
      for (std::size_t i = 0; i < w.size(); ++i) {
        v[i] = spectrum.value(i);
        ASSERT_GE(v[i], 0.0);
        ASSERT_LE(v[i], 1.0);
        fractional += v[i] != 0 && v[i] != 1;
      }
      EXPECT_LE(fractional, 2);
      Xyz c;
      for (std::size_t i = 0; i < w.size(); ++i) c = c + v[i] * w[i];
      worst = std::max(worst, (mul(to_u, c) - b).max_abs());
    }
    std::printf("  boundary spectra: worst error %.2g (frame units)\n", worst);
    EXPECT_LE(worst, 1e-9);
  }
}

// Beyond ~650 nm zbar is 0: those samples are coplanar, and points of that facet (any mix of
// them) still get an exact spectrum with at most two fractional samples.
TEST(SolidBoundary, TheCoplanarZbarZeroFacetIsExact) {
  SpectralizerSettings s;
  s.mode = Mode::reflectance;
  const Spectralizer sp(s);
  const std::vector<Xyz> w = own_weights(true);
  const Mat3 frame = scale_rows(sp.target_of({1, 1, 1}), frame_of(test::kRec2020ToXyz));
  const SolidBoundary solid(sp.weights().columns(), frame);
  std::vector<std::size_t> flat;
  for (std::size_t k = 0; k < w.size(); ++k)
    if (sp.weights().columns()[k].Z == 0) flat.push_back(k);
  ASSERT_GT(flat.size(), 10u);
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 500; ++k) {
    std::vector<double> rho(w.size(), 0.0);
    const double scale = std::pow(10.0, -4 * u(rng));
    for (std::size_t i : flat) rho[i] = scale * u(rng);
    const Xyz t = sp.weights().integrate(rho);
    const BoundarySpectrum b = solid.spectrum(mul(inverse(frame), t));
    Xyz c;
    for (std::size_t i = 0; i < w.size(); ++i) c = c + b.value(i) * w[i];
    EXPECT_LE(test::rel_err(c, t), 1e-9);
  }
}

TEST(SolidBoundary, TheSolidLiesInsideEveryFacetAndBlackAndWhiteOnIt) {
  SpectralizerSettings s;
  s.mode = Mode::reflectance;
  const Spectralizer sp(s);
  const Mat3 frame = scale_rows(sp.target_of({1, 1, 1}), frame_of(test::kRec709ToXyz));
  const SolidBoundary solid(sp.weights().columns(), frame);
  EXPECT_GT(solid.planes().size(), 3000u);
  EXPECT_NEAR(solid.distance({0, 0, 0}), 0.0, 1e-15);
  EXPECT_NEAR(solid.distance(mul(inverse(frame), sp.weights().unit_white())), 0.0, 1e-12);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 300; ++k) {
    std::vector<double> rho(sp.settings().grid.size());
    for (double& r : rho) r = u(rng);
    EXPECT_LT(solid.distance(mul(inverse(frame), sp.weights().integrate(rho))), 1e-12);
  }
  // The sRGB cube lies inside the solid (docs/DESIGN.md §14).
  for (int c = 0; c < 8; ++c) {
    EXPECT_LE(solid.distance({double(c & 1), double((c >> 1) & 1), double(c >> 2)}), 1e-12) << c;
  }
}

TEST(LocusBoundary, EdgeSpectraAreTwoSampleLightsOfTheirChromaticity) {
  const Spectralizer sp{SpectralizerSettings{}};
  const std::vector<Xyz> w = own_weights(false);
  const LocusBoundary locus(sp.weights().columns(), sp.basis());
  for (const Xyz& c : sp.weights().columns()) {
    EXPECT_LE(locus.distance({c.X / c.sum(), c.Y / c.sum(), 0}), 1e-12);
  }
  const Xyz white{0.3127, 0.3290, 0};
  EXPECT_LT(locus.distance(white), -0.1);
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 2000; ++k) {
    const Xyz to{0.3127 + u(rng), 0.3290 + u(rng), 0};
    const Xyz b = white + locus.max_step(white, to) * (to - white);
    const BoundarySpectrum s = locus.spectrum(b);
    Xyz c;
    int nonzero = 0;
    for (std::size_t i = 0; i < w.size(); ++i) {
      ASSERT_GE(s.value(i), 0.0);
      nonzero += s.value(i) != 0;
      c = c + s.value(i) * w[i];
    }
    EXPECT_LE(nonzero, 2);
    EXPECT_NEAR(c.sum(), 1.0, 1e-9);
    EXPECT_NEAR(c.X / c.sum(), b.X, 1e-9);
    EXPECT_NEAR(c.Y / c.sum(), b.Y, 1e-9);
  }
}

}  // namespace
}  // namespace spectralize
