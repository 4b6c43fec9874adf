// Observers, illuminants and SampleWeights: the CIE data the library embeds, and the sample
// weights that make W . phi equal the reference integration of docs/DESIGN.md §3. The oracle is the
// 1 nm trapezoid loop of test_support.h, written from the definition.

#include "spectralize/core/sample_weights.h"

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <string>
#include <vector>

#include "spectralize/core/colorimetry.h"
#include "spectralize/core/error.h"
#include "test_support.h"

namespace spectralize {
namespace {

using test::chromaticity;
using test::expect_error_mentioning;
using test::raw_integral;
using test::reference_norm;
using test::reference_xyz;
using test::rel_err;

// Index of wavelength `nm` on the 1 nm reference table.
std::size_t at(int nm) {
  return static_cast<std::size_t>(nm - 360);
}

// XYZ of an illuminant itself (a light with that SPD), integrated on the full 1 nm table.
Xyz illuminant_xyz(const Observer& obs, const Illuminant& il) {
  Xyz s;
  for (int nm = 360; nm <= 830; ++nm) {
    const double tau = (nm == 360 || nm == 830) ? 0.5 : 1.0;
    for (int c = 0; c < 3; ++c) s[c] += tau * obs.cmf[c][at(nm)] * il.spd[at(nm)];
  }
  return s;
}

// --- Observers ---

TEST(Observer, LoadsBothStandardObserversOnThe1nmTable) {
  const Observer& o2 = Observer::get("cie1931");
  const Observer& o10 = Observer::get("cie1964");
  EXPECT_EQ(o2.name, "cie1931");
  EXPECT_EQ(o10.name, "cie1964");
  for (const Observer* o : {&o2, &o10})
    for (const auto& c : o->cmf) {
      ASSERT_EQ(c.size(), 471u);  // 360..830 nm at 1 nm
      for (double v : c) {
        EXPECT_GE(v, 0.0);  // colour-matching functions are non-negative
      }
    }
  // Published CIE table values (CIE 015:2018 tables; exact in the data, so 1e-12).
  EXPECT_NEAR(o2.cmf[1][at(555)], 1.0, 1e-12);  // ybar peaks at 555 nm with value 1
  EXPECT_NEAR(o2.cmf[0][at(600)], 1.0622, 1e-12);
  EXPECT_NEAR(o2.cmf[2][at(445)], 1.7826, 1e-12);
  EXPECT_NEAR(o10.cmf[1][at(555)], 0.99911, 1e-12);
  EXPECT_NEAR(o10.cmf[0][at(600)], 1.12399, 1e-12);
  // Aliases resolve to the same cached tables.
  EXPECT_EQ(&Observer::get("CIE1931"), &o2);
  EXPECT_EQ(&Observer::get("cie1964_10"), &o10);
}

TEST(Observer, YIntegralIsPbrtsConstant) {
  const Observer& o2 = Observer::get("cie1931");
  // pbrt-v4's CIE_Y_integral = 106.856895 (sum of ybar on the 1 nm table); 1e-3 covers the
  // trapezoid's halved end points (ybar there is ~4e-6).
  EXPECT_NEAR(o2.y_integral, 106.856895, 1e-3);
  // And it is K = sum tau ybar as docs/DESIGN.md §3 defines it, to summation rounding.
  for (const char* name : {"cie1931", "cie1964"}) {
    const Observer& o = Observer::get(name);
    EXPECT_NEAR(o.y_integral, test::y_integral(o), 1e-12 * o.y_integral) << name;
  }
}

TEST(Observer, UnknownNameListsTheValidOnes) {
  expect_error_mentioning([] { (void)Observer::get("cie2006"); }, {"cie2006", "cie1931", "cie1964"},
                          "unknown observer");
}

// --- Illuminants ---

TEST(Illuminant, StandardIlluminantsLoadOnTheReferenceTable) {
  for (const char* name : {"D65", "D50", "A", "E", "C", "FL2", "FL11", "D55"}) {
    SCOPED_TRACE(name);
    Illuminant il = Illuminant::get(name);
    ASSERT_EQ(il.spd.size(), 471u);
    for (double v : il.spd) {
      EXPECT_TRUE(std::isfinite(v));
      EXPECT_GE(v, 0.0);  // a spectral power distribution is non-negative
    }
  }
  EXPECT_EQ(Illuminant::get("d65").name, "D65");  // names are case-insensitive
}

TEST(Illuminant, TablesAreNormalisedTo100At560nm) {
  // CIE normalisation of D65, D50 and A: 100 at 560 nm (exact in the 1 nm tables, so 1e-6).
  for (const char* name : {"D65", "D50", "A"}) {
    EXPECT_NEAR(Illuminant::get(name).spd[at(560)], 100.0, 1e-6) << name;
  }
  // E is equal energy.
  for (double v : Illuminant::get("E").spd) {
    EXPECT_EQ(v, Illuminant::get("E").spd[0]);
  }
}

TEST(Illuminant, ChromaticitiesMatchCie015) {
  const Observer& o2 = Observer::get("cie1931");
  struct Case {
    const char* name;
    double x, y, tol;
  } cases[] = {
      // CIE 015:2018 Table T.3 / T.8 values (CIE 1931 2°). 1e-4 for the 1 nm tables (the
      // published values are rounded to 5 digits); 2e-4 for D55 (built here from S0..S2 at 5 nm,
      // interpolated to 1 nm, which shifts the 5th digit) and for C (5 nm table).
      {"D65", 0.31272, 0.32903, 1e-4}, {"A", 0.44757, 0.40745, 1e-4},
      {"D50", 0.34567, 0.35850, 1e-4}, {"E", 1.0 / 3, 1.0 / 3, 1e-4},
      {"D55", 0.33242, 0.34743, 2e-4}, {"C", 0.31006, 0.31616, 2e-4},
  };
  for (const auto& c : cases) {
    auto xy = chromaticity(illuminant_xyz(o2, Illuminant::get(c.name)));
    EXPECT_NEAR(xy[0], c.x, c.tol) << c.name;
    EXPECT_NEAR(xy[1], c.y, c.tol) << c.name;
  }
  // 10° observer: D65 is (0.31382, 0.33100) (CIE 015:2018 Table T.3).
  auto xy10 = chromaticity(illuminant_xyz(Observer::get("cie1964"), Illuminant::get("D65")));
  EXPECT_NEAR(xy10[0], 0.31382, 1e-4);
  EXPECT_NEAR(xy10[1], 0.33100, 1e-4);
}

TEST(Illuminant, UnknownNameListsTheValidOnes) {
  expect_error_mentioning([] { (void)Illuminant::get("D99x"); }, {"D99x", "D65", "FL2"},
                          "unknown illuminant");
  expect_error_mentioning([] { (void)Illuminant::get("D30"); }, {"D40"}, "daylight below 4000 K");
}

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
