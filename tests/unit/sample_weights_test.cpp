// SampleWeights: the sample weights that make W . phi equal the reference integration of
// docs/DESIGN.md §3 (the observers and illuminants they rest on are in colorimetry_test.cpp).
// The oracle is the 1 nm trapezoid loop of test_support.h, written from the definition.

#include "spectralize/core/sample_weights.h"

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <string>
#include <vector>

#include "spectralize/core/colorimetry.h"
#include "test_support.h"

namespace spectralize {
namespace {

using test::chromaticity;
using test::illuminant_xyz;
using test::raw_integral;
using test::reference_norm;
using test::reference_xyz;
using test::rel_err;

// --- piecewise_linear ---

TEST(SampleWeights, PiecewiseLinearInterpolatesAndIsZeroOutside) {
  WavelengthGrid g(380, 400, 10);
  std::vector<double> v = {1, 3, 7};
  // Exact in binary arithmetic.
  EXPECT_EQ(piecewise_linear(g, v, 380), 1.0);
  EXPECT_EQ(piecewise_linear(g, v, 385), 2.0);
  EXPECT_EQ(piecewise_linear(g, v, 397.5), 6.0);
  EXPECT_EQ(piecewise_linear(g, v, 400), 7.0);
  EXPECT_EQ(piecewise_linear(g, v, 379.9), 0.0);
  EXPECT_EQ(piecewise_linear(g, v, 400.1), 0.0);
}

// --- SampleWeights against the independent reference integration ---

TEST(SampleWeights, WeightsReproduceTheReferenceIntegration) {
  // 400:701:7 stands in for 400:700:7, which is not a grid (300/7 steps).
  const char* grids[] = {"380:780:5", "380:780:10",    "360:830:1",
                         "400:701:7", "380.5:779.5:3", "380:780:0.5"};
  std::mt19937 rng(20240611);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  for (const char* gtext : grids) {
    const WavelengthGrid grid = WavelengthGrid::parse(gtext);
    for (const char* oname : {"cie1931", "cie1964"}) {
      const Observer& obs = Observer::get(oname);
      for (const char* iname : {"", "D65", "A"}) {
        SCOPED_TRACE(std::string(gtext) + " " + oname + " " + (*iname ? iname : "emission"));
        std::unique_ptr<Illuminant> il;
        if (*iname) il = std::make_unique<Illuminant>(Illuminant::get(iname));
        const std::vector<double>* spd = il ? &il->spd : nullptr;
        SampleWeights w(grid, obs, il.get());
        ASSERT_EQ(w.columns().size(), grid.size());
        // The normalisation is K (emission) or the raw Y of rho == 1 on the grid (reflectance), to
        // summation rounding.
        const double norm = reference_norm(grid, obs, spd);
        EXPECT_NEAR(w.normalisation(), norm, 1e-12 * norm);
        for (int trial = 0; trial < 5; ++trial) {
          // Random spectra, including a spiky one (values spread over 6 decades).
          std::vector<double> phi(grid.size());
          for (double& v : phi) v = trial < 4 ? u01(rng) : std::pow(10.0, 6 * u01(rng) - 3);
          const Xyz want = reference_xyz(grid, phi, obs, spd);
          // Same sums in a different order: 1e-12 relative is ~1000x double rounding.
          EXPECT_LE(rel_err(w.integrate(phi), want), 1e-12);
          EXPECT_LE(rel_err(integrate_reference(grid, phi, obs, il.get(), w.normalisation()), want),
                    1e-12);
        }
        // The constant spectrum 1 is the unit white.
        std::vector<double> ones(grid.size(), 1.0);
        EXPECT_LE(rel_err(w.unit_white(), reference_xyz(grid, ones, obs, spd)), 1e-12);
      }
    }
  }
}

TEST(SampleWeights, EmissionConstantOneHasLuminanceOne) {
  // On the full 360:830:1 table, phi == 1 gives Y = sum tau ybar / K = 1 (K normalisation).
  for (const char* oname : {"cie1931", "cie1964"}) {
    SampleWeights w(WavelengthGrid::parse("360:830:1"), Observer::get(oname), nullptr);
    std::vector<double> ones(471, 1.0);
    EXPECT_NEAR(w.integrate(ones).Y, 1.0, 1e-12) << oname;
  }
}

TEST(SampleWeights, ReflectanceWhiteHasLuminanceOneAndTheIlluminantsChromaticity) {
  const WavelengthGrid full = WavelengthGrid::parse("360:830:1");
  for (const char* oname : {"cie1931", "cie1964"})
    for (const char* iname : {"D65", "A", "D50", "FL2", "E"}) {
      SCOPED_TRACE(std::string(oname) + " " + iname);
      const Observer& obs = Observer::get(oname);
      Illuminant il = Illuminant::get(iname);
      SampleWeights w(full, obs, &il);
      // rho == 1 reflects the illuminant itself: Y = 1 by the normalisation, and its
      // chromaticity is the illuminant's (1e-12: summation rounding).
      EXPECT_NEAR(w.unit_white().Y, 1.0, 1e-12);
      auto got = chromaticity(w.unit_white()), want = chromaticity(illuminant_xyz(obs, il));
      EXPECT_NEAR(got[0], want[0], 1e-12);
      EXPECT_NEAR(got[1], want[1], 1e-12);
    }
  // On every grid, also those that do not cover 360..830 nm, rho == 1 has Y = 1 (docs/DESIGN.md §3:
  // "normalised so that rho == 1 gives Y = 1"); 1e-12: summation rounding.
  for (const char* gtext : {"380:780:5", "380:780:10", "400:701:7", "380.5:779.5:3", "380:780:0.5"})
    for (const char* iname : {"D65", "A"}) {
      Illuminant il = Illuminant::get(iname);
      SampleWeights w(WavelengthGrid::parse(gtext), Observer::get("cie1931"), &il);
      EXPECT_NEAR(w.unit_white().Y, 1.0, 1e-12) << gtext << " " << iname;
    }
}

TEST(SampleWeights, OnThe1nmTableTheWeightsAreTheTableValues) {
  // With one sample per table point, each tent is a delta on its own table point, so
  // W_i = tau_i * cmf(lambda_i) * E(lambda_i) / norm. 1e-12 relative to the largest weight.
  const WavelengthGrid full = WavelengthGrid::parse("360:830:1");
  for (const char* oname : {"cie1931", "cie1964"})
    for (const char* iname : {"", "D65", "A"}) {
      SCOPED_TRACE(std::string(oname) + " " + (*iname ? iname : "emission"));
      const Observer& obs = Observer::get(oname);
      std::unique_ptr<Illuminant> il;
      if (*iname) il = std::make_unique<Illuminant>(Illuminant::get(iname));
      const std::vector<double>* spd = il ? &il->spd : nullptr;
      const double norm = reference_norm(full, obs, spd);
      SampleWeights w(full, obs, il.get());
      double largest = 0;
      for (const Xyz& c : w.columns()) largest = std::max(largest, c.max_abs());
      for (std::size_t k = 0; k < 471; ++k) {
        const double tau = (k == 0 || k == 470) ? 0.5 : 1.0;
        const double e = spd ? (*spd)[k] : 1.0;
        for (int c = 0; c < 3; ++c) {
          ASSERT_NEAR(w.columns()[k][c], tau * obs.cmf[c][k] * e / norm, 1e-12 * largest)
              << "k=" << k << " c=" << c;
        }
      }
    }
}

TEST(SampleWeights, SamplesOffTheTablePointsCarryNoWeightOnAHalfNanometreGrid) {
  // On 360:830:0.5 the half-integer samples' tents vanish on every 1 nm table point, so the
  // reference integration cannot see them: their weight vectors must be exactly zero.
  SampleWeights w(WavelengthGrid::parse("360:830:0.5"), Observer::get("cie1931"), nullptr);
  ASSERT_EQ(w.columns().size(), 941u);
  for (std::size_t i = 1; i < 941; i += 2) {
    EXPECT_EQ(w.columns()[i], Xyz{}) << "sample " << i;
  }
  // ... and a spectrum that is non-zero only there has zero colour (raw_integral agrees).
  std::vector<double> odd(941, 0.0);
  for (std::size_t i = 1; i < 941; i += 2) odd[i] = 1.0;
  Xyz raw = raw_integral(360, 0.5, odd, Observer::get("cie1931"), nullptr);
  EXPECT_EQ(raw, Xyz{});
  EXPECT_EQ(w.integrate(odd), Xyz{});
}

}  // namespace
}  // namespace spectralize
