// Spectralizer: the user-visible promises of docs/DESIGN.md §1-§5. Every spectrum reproduces its
// (possibly gamut-mapped) colour exactly under the reference integration, is non-negative, and a
// reflectance never exceeds 1. Exactness is checked with test_support.h's own 1 nm trapezoid
// integration; targets are recomputed here from the RGB matrices and the white balance of eq. 6.

#include "spectralize/core/spectralizer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "spectralize/core/error.h"
#include "spectralizer_checks.h"
#include "test_support.h"

namespace spectralize {
namespace {

using namespace test;  // NOLINT: the checks of spectralizer_checks.h

// --- The colour-space matrices of the test ---

TEST(Spectralizer, AcescgMatrixMapsAcesWhiteToD65) {
  // Sanity of the Bradford-derived ACEScg -> XYZ-D65 matrix built in test_support.h: (1,1,1)
  // is the ACES white, adapted to D65 (1e-9: the derivation is a few 3x3 products in double).
  const Xyz w = test::mul(test::acescg_to_xyz_d65(), {1, 1, 1});
  EXPECT_NEAR(w.X, 0.3127 / 0.3290, 1e-9);
  EXPECT_NEAR(w.Y, 1.0, 1e-9);
  EXPECT_NEAR(w.Z, 0.3583 / 0.3290, 1e-9);
  // The written-out Rec.709 and Rec.2020 matrices map (1,1,1) to D65 as well (1e-12).
  for (const Mat3* m : {&test::kRec709ToXyz, &test::kRec2020ToXyz}) {
    const Xyz v = test::mul(*m, {1, 1, 1});
    EXPECT_NEAR(v.X, 0.3127 / 0.3290, 1e-12);
    EXPECT_NEAR(v.Y, 1.0, 1e-12);
    EXPECT_NEAR(v.Z, 0.3583 / 0.3290, 1e-12);
  }
}

// --- The paper's examples ---

TEST(Spectralizer, PapersLightExample) {
  // A light of Linear Rec.709 RGB (6000, 5000, 1000), default grid and edge filter.
  const Spectralizer sp = make(Mode::emission);
  const Reference ref = reference_of(sp);
  const Xyz xyz = test::rgb(test::kRec709ToXyz, 6000, 5000, 1000);
  const SpectrumResult r = sp.spectralize(xyz);
  ASSERT_EQ(r.status, Outcome::exact) << r.message;
  const Xyz got = integrate(sp, ref, r.values);
  EXPECT_LE(rel_err(got, xyz), 1e-5);       // the light's colour, exactly (DESIGN §3 float bar)
  EXPECT_LE(rel_err(got, r.target), 1e-9);  // and the reported target, to double rounding
  for (double v : r.values) {
    EXPECT_GE(v, 0.0);
  }
  // Edge peaks removed: no sample in 380-400 or 760-780 nm above the mean over 400-700 nm.
  const double ratio = edge_peak_ratio(sp.settings().grid, r.values);
  EXPECT_LE(ratio, 1.0) << "edge sample / mid mean = " << ratio;
  std::printf("  light: L %.0f, dropped %.0f, edge ratio %.3f\n", r.detail("admissible"),
              r.detail("dropped"), ratio);
}

TEST(Spectralizer, PapersSurfaceExample) {
  // A diffuse surface of Linear Rec.709 RGB (0.21, 0.72, 0.15) under D65.
  const Spectralizer sp = make(Mode::reflectance);
  const Reference ref = reference_of(sp);
  const Xyz xyz = test::rgb(test::kRec709ToXyz, 0.21, 0.72, 0.15);
  const SpectrumResult r = sp.spectralize(xyz);
  ASSERT_EQ(r.status, Outcome::exact) << r.message;
  const Xyz got = integrate(sp, ref, r.values);
  EXPECT_LE(rel_err(got, expected_target(sp, ref, xyz)), 1e-5);
  EXPECT_LE(rel_err(got, r.target), 1e-9);
  for (double v : r.values) {
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 1.0 + 1e-12);
  }
  std::printf("  surface: L %.0f, dropped %.0f, bounded %.0f, edge ratio %.3f\n",
              r.detail("admissible"), r.detail("dropped"), r.detail("bounded"),
              edge_peak_ratio(sp.settings().grid, r.values));
}

// --- Random colours in four RGB spaces ---

TEST(Spectralizer, TenThousandRandomColoursPerSpaceAndModeAt10nm) {
  // 10 nm grid to keep 80k solves within the CI budget (the 5 nm grid is covered below).
  for (Mode mode : {Mode::emission, Mode::reflectance}) {
    const Spectralizer sp = make(mode, "380:780:10");
    for (const Space& s : spaces()) {
      SCOPED_TRACE(std::string(s.name) + " " + std::string(to_string(mode)));
      const Tally t = run_random(sp, s, 10000, 1234);
      const Bounds b = expected_out(s.name, mode);
      EXPECT_GE(static_cast<double>(t.out), b.lo * 10000);
      EXPECT_LE(static_cast<double>(t.out), b.hi * 10000);
    }
  }
}

TEST(Spectralizer, FiveHundredRandomColoursPerSpaceAndModeAt5nm) {
  for (Mode mode : {Mode::emission, Mode::reflectance}) {
    const Spectralizer sp = make(mode);
    for (const Space& s : spaces()) {
      SCOPED_TRACE(std::string(s.name) + " " + std::string(to_string(mode)));
      const Tally t = run_random(sp, s, 500, 99);
      const Bounds b = expected_out(s.name, mode);
      // 500 samples: the share's standard error is ~1.3% at 10%, within the bounds' slack.
      EXPECT_GE(static_cast<double>(t.out), b.lo * 500);
      EXPECT_LE(static_cast<double>(t.out), b.hi * 500);
    }
  }
}

TEST(Spectralizer, EmissionOutsideTheLocusIsTrulyOutside) {
  // Independent check of the out_of_gamut verdict in emission: a non-negative spectrum exists
  // iff some triple of samples has a non-negative partial solution (Caratheodory), so for a
  // flagged colour no triple may have all three Cramer densities >= 0. ACEScg, 10 nm.
  const Spectralizer sp = make(Mode::emission, "380:780:10");
  const auto& c = sp.weights().columns();
  const Mat3 m = test::acescg_to_xyz_d65();
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int flagged = 0;
  for (int n = 0; n < 3000 && flagged < 25; ++n) {
    const Xyz xyz = test::rgb(m, u(rng), u(rng), u(rng));
    if (!out_of_gamut(sp.spectralize(xyz).status)) continue;
    ++flagged;
    auto cols = [](const Xyz& a, const Xyz& b, const Xyz& d) {
      return Mat3{{{a.X, b.X, d.X}, {a.Y, b.Y, d.Y}, {a.Z, b.Z, d.Z}}};
    };
    int admissible = 0;
    for (std::size_t i = 0; i < c.size(); ++i)
      for (std::size_t j = i + 1; j < c.size(); ++j)
        for (std::size_t k = j + 1; k < c.size(); ++k) {
          const double det = test::det3(cols(c[i], c[j], c[k]));
          if (det == 0) continue;
          // Relative slack 1e-12: a colour within rounding of the boundary is not "inside".
          const double tol = -1e-12 * xyz.max_abs();
          if (test::det3(cols(xyz, c[j], c[k])) / det >= tol &&
              test::det3(cols(c[i], xyz, c[k])) / det >= tol &&
              test::det3(cols(c[i], c[j], xyz)) / det >= tol)
            ++admissible;
        }
    EXPECT_EQ(admissible, 0) << "flagged XYZ (" << xyz.X << ", " << xyz.Y << ", " << xyz.Z << ")";
  }
  EXPECT_GT(flagged, 0);  // ACEScg's cube reaches outside the locus (its green primary)
}

TEST(Spectralizer, DefaultFilterRemovesEdgePeaks) {
  // 10,000 random sRGB lights (5,000 uniform in linear RGB, 5,000 uniform in sRGB-encoded
  // values), 5 nm, default filter: no sample in 380-400 or 760-780 nm above the mean over
  // 400-700 nm (the end samples of the unfiltered average are ~4000x the mean).
  const Spectralizer sp = make(Mode::emission);
  ASSERT_EQ(sp.settings().filter, default_edge_filter());
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto decode = [](double v) {
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
  };
  double worst = 0;
  int above = 0;
  Xyz worst_rgb;
  for (int n = 0; n < 10000; ++n) {
    Xyz rgb{u(rng), u(rng), u(rng)};
    if (n % 2) rgb = Xyz{decode(rgb.X), decode(rgb.Y), decode(rgb.Z)};
    const SpectrumResult r = sp.spectralize(test::mul(test::kRec709ToXyz, rgb));
    ASSERT_EQ(r.status, Outcome::exact);
    const double ratio = edge_peak_ratio(sp.settings().grid, r.values);
    if (ratio > 1.0) ++above;
    if (ratio > worst) worst = ratio, worst_rgb = rgb;
  }
  std::printf(
      "  default filter %s: worst edge/mid ratio %.3f at linear sRGB (%.3f, %.3f, %.3f); %d of "
      "10000 above 1\n",
      default_edge_filter().to_string().c_str(), worst, worst_rgb.X, worst_rgb.Y, worst_rgb.Z,
      above);
  EXPECT_LE(worst, 1.0) << above
                        << " of 10000 colours have an edge sample above the 400-700 nm mean";
}

// --- Special colours ---

TEST(Spectralizer, WhiteSurfaceIsPerfectReflector) {
  // Input white of a D65 space becomes rho == 1 exactly under any reference illuminant (white
  // balance of eq. 6); 1e-9: the exact projection's tolerance is 1e-13 of the target.
  for (const char* il : {"D65", "A", "D50"}) {
    SCOPED_TRACE(il);
    const Spectralizer sp = make(Mode::reflectance, "380:780:5", "cie1931", il);
    const SpectrumResult r = sp.spectralize(test::rgb(test::kRec709ToXyz, 1, 1, 1));
    EXPECT_EQ(r.status, Outcome::exact) << r.message;
    for (double v : r.values) {
      EXPECT_NEAR(v, 1.0, 1e-9);
    }
    // Mid grey is a reflectance too (inside the solid, not on its boundary).
    const SpectrumResult g = sp.spectralize(test::rgb(test::kRec709ToXyz, 0.5, 0.5, 0.5));
    EXPECT_EQ(g.status, Outcome::exact) << g.message;
  }
}

TEST(Spectralizer, BlackIsAZeroSpectrum) {
  for (Mode mode : {Mode::emission, Mode::reflectance}) {
    const Spectralizer sp = make(mode);
    const SpectrumResult r = sp.spectralize(Xyz{});
    EXPECT_EQ(r.status, Outcome::black) << to_string(mode);
    ASSERT_EQ(r.values.size(), 81u);
    for (double v : r.values) {
      EXPECT_EQ(v, 0.0);
    }
  }
}

TEST(Spectralizer, EmissionIsScaleInvariant) {
  // docs/DESIGN.md §4: the spectrum of k XYZ is k times the spectrum of XYZ (the admissible set and
  // the filter depend on chromaticity only). 1e-9 relative to the largest sample.
  const Spectralizer sp = make(Mode::emission);
  for (const Xyz& rgb : {Xyz{0.21, 0.72, 0.15}, Xyz{0.8, 0.3, 0.2}, Xyz{0.2, 0.4, 0.9}}) {
    const Xyz xyz = test::mul(test::kRec709ToXyz, rgb);
    const SpectrumResult base = sp.spectralize(xyz);
    ASSERT_EQ(base.status, Outcome::exact);
    for (double k : {1e-4, 0.37, 1e3, 1e6}) {
      const SpectrumResult r = sp.spectralize(k * xyz);
      ASSERT_EQ(r.status, Outcome::exact);
      std::vector<double> scaled = base.values;
      for (double& v : scaled) v *= k;
      EXPECT_LE(rel_err(r.values, scaled), 1e-9)
          << "k = " << k << ", rgb " << rgb.X << " " << rgb.Y;
    }
  }
}

TEST(Spectralizer, EmissionIsExactAcrossTheFloatRange) {
  // Scene-linear float pixels range from denormals to FLT_MAX (3.4e38); the XYZ of any finite
  // float colour must get an exact, finite spectrum. 1e-5: the float exactness bar (DESIGN §3).
  const Spectralizer sp = make(Mode::emission);
  const Reference ref = reference_of(sp);
  const Xyz base = test::rgb(test::kRec709ToXyz, 0.21, 0.72, 0.15);
  for (double k : {1e-40, 1e-30, 1e-10, 1e10, 1e30, 1e35, 1e38}) {
    SCOPED_TRACE(::testing::Message() << "k = " << k);
    const SpectrumResult r = sp.spectralize(k * base);
    EXPECT_EQ(r.status, Outcome::exact) << r.message;
    bool finite = true;
    for (double v : r.values) finite = finite && std::isfinite(v) && v >= 0;
    EXPECT_TRUE(finite);
    if (finite) {
      EXPECT_LE(rel_err(integrate(sp, ref, r.values), k * base), 1e-5);
    }
  }
}

TEST(Spectralizer, NarrowGridNeverReportsAnInexactSpectrum) {
  // On 500:600:10 the spectral locus of the grid is a thin sliver along the 500-600 nm arc that
  // excludes D65 white. Whatever the status, a colour that is not black/invalid must come back
  // with an exact spectrum of an in-gamut target (never "ok" with a wrong spectrum).
  const Spectralizer sp = make(Mode::emission, "500:600:10");
  const Reference ref = reference_of(sp);
  for (const Xyz& rgb : {Xyz{0, 1, 0}, Xyz{1, 1, 1}, Xyz{1, 0, 0}, Xyz{0.2, 0.5, 0.9}}) {
    SCOPED_TRACE(::testing::Message() << "rgb " << rgb.X << " " << rgb.Y << " " << rgb.Z);
    const Xyz xyz = test::mul(test::kRec709ToXyz, rgb);
    const SpectrumResult r = sp.spectralize(xyz);
    ASSERT_TRUE(r.status == Outcome::exact || out_of_gamut(r.status)) << to_string(r.status);
    EXPECT_TRUE(sp.in_gamut(r.target)) << to_string(r.status) << ": " << r.message;
    EXPECT_LE(rel_err(integrate(sp, ref, r.values), r.target), 1e-5)
        << to_string(r.status) << ": " << r.message;
    if (r.status == Outcome::exact) {
      EXPECT_LE(rel_err(r.target, xyz), 1e-6);
    }
  }
}

TEST(Spectralizer, InvalidInputGivesInvalidAndAZeroSpectrum) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (Mode mode : {Mode::emission, Mode::reflectance}) {
    const Spectralizer sp = make(mode);
    for (const Xyz& xyz : {Xyz{nan, 0.5, 0.5}, Xyz{0.5, inf, 0.5}, Xyz{0.5, 0.5, -inf},
                           Xyz{0.1, -0.2, 0.1}, Xyz{-1, -1, -1}}) {
      SCOPED_TRACE(::testing::Message() << to_string(mode) << " XYZ (" << xyz.X << ", " << xyz.Y
                                        << ", " << xyz.Z << ")");
      const SpectrumResult r = sp.spectralize(xyz);  // must not throw
      // NaN or infinite: no colour; finite with Y < 0: out of gamut, mapped to black.
      EXPECT_EQ(r.status, xyz.finite() ? Outcome::negative : Outcome::invalid);
      EXPECT_FALSE(r.message.empty());
      ASSERT_EQ(r.values.size(), 81u);
      for (double v : r.values) {
        EXPECT_EQ(v, 0.0);
      }
    }
  }
}

TEST(Spectralizer, NegativeComponentWithPositiveLuminanceIsMappedNotRejected) {
  // Rec.709 (-0.1, 0.5, 0.2): Y > 0 but outside the cube; HDR maps contain such pixels.
  for (Mode mode : {Mode::emission, Mode::reflectance}) {
    SCOPED_TRACE(std::string(to_string(mode)));
    const Spectralizer sp = make(mode);
    const Reference ref = reference_of(sp);
    for (const Xyz& rgb : {Xyz{-0.1, 0.5, 0.2}, Xyz{0.5, -0.05, 0.3}, Xyz{-0.3, 0.1, 1.0}}) {
      const Xyz xyz = test::mul(test::kRec709ToXyz, rgb);
      ASSERT_GT(xyz.Y, 0.0);
      const SpectrumResult r = sp.spectralize(xyz);
      EXPECT_TRUE(r.status == Outcome::exact || out_of_gamut(r.status)) << to_string(r.status);
      Tally t;
      check_result(sp, ref, xyz, r, t);
      EXPECT_TRUE(sp.in_gamut(r.target));
    }
  }
}

TEST(Spectralizer, ReflectanceBrighterThanWhiteIsDimmed) {
  // No reflectance reflects more than rho == 1: Y > 1 is out of gamut, dimmed to Y <= 1.
  const Spectralizer sp = make(Mode::reflectance);
  const Reference ref = reference_of(sp);
  for (const Xyz& rgb : {Xyz{2, 2, 2}, Xyz{3, 0.5, 0.2}, Xyz{1.2, 1.1, 1.0}}) {
    SCOPED_TRACE(::testing::Message() << "rgb " << rgb.X << " " << rgb.Y << " " << rgb.Z);
    const Xyz xyz = test::mul(test::kRec709ToXyz, rgb);
    const SpectrumResult r = sp.spectralize(xyz);
    EXPECT_TRUE(out_of_gamut(r.status));
    EXPECT_LE(r.target.Y, 1.0 + 1e-12);
    for (double v : r.values) {
      EXPECT_GE(v, 0.0);
      EXPECT_LE(v, 1.0 + 1e-12);
    }
    EXPECT_LE(rel_err(integrate(sp, ref, r.values), r.target), 1e-5);
    // Dimming keeps the hue: the chromaticity (white balanced, as the target is) is unchanged
    // to the gamut margin, so a bright red stays red rather than turning white.
    const Xyz wb = sp.target_of(xyz);
    EXPECT_NEAR(r.target.X / r.target.sum(), wb.X / wb.sum(), 1e-6);
    EXPECT_NEAR(r.target.Y / r.target.sum(), wb.Y / wb.sum(), 1e-6);
  }
}

TEST(Spectralizer, BrightColourOutsideTheLocusAsAReflectanceIsMappedExactly) {
  // Found by fuzzing: XYZ (52.1, 2.1, 0.15) is outside the locus and far too bright; mapped to
  // the locus, then dimmed into the reflectance solid, its target sat 1e-6 from the solid's
  // boundary, where the bounded projection stalled at 2e-5. With the solid's margin of 1e-4 the
  // result is exact to double precision (1e-9 with margin) and bounded.
  SpectralizerSettings s;
  s.grid = WavelengthGrid(380, 780, 10);
  s.mode = Mode::reflectance;
  const Spectralizer sp(s);
  const SpectrumResult r = sp.spectralize(Xyz{52.1, 2.1, 0.15});
  EXPECT_TRUE(out_of_gamut(r.status));
  EXPECT_TRUE(sp.in_gamut(r.target));
  EXPECT_LE(r.relative_error, 1e-9);
  for (double v : r.values) {
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 1.0);
  }
}

// --- Other observers and grids ---

TEST(Spectralizer, Cie1964ObserverIsExact) {
  for (Mode mode : {Mode::emission, Mode::reflectance}) {
    const Spectralizer sp = make(mode, "380:780:5", "cie1964");
    ASSERT_EQ(&sp.observer(), &Observer::get("cie1964"));
    const Reference ref = reference_of(sp);
    Tally t;
    for (const Xyz& rgb :
         {Xyz{0.21, 0.72, 0.15}, Xyz{0.9, 0.2, 0.1}, Xyz{0.1, 0.3, 0.8}, Xyz{1, 1, 1}}) {
      const Xyz xyz = test::mul(test::kRec709ToXyz, rgb);
      const SpectrumResult r = sp.spectralize(xyz);
      EXPECT_EQ(r.status, Outcome::exact) << r.message;
      check_result(sp, ref, xyz, r, t);
    }
  }
}

TEST(Spectralizer, OneNanometreGridIsExact) {
  // 401 samples, ~1.7M admissible triples per colour: only a few colours (~10 ms each).
  for (Mode mode : {Mode::emission, Mode::reflectance}) {
    const Spectralizer sp = make(mode, "380:780:1");
    const Reference ref = reference_of(sp);
    Tally t;
    for (const Xyz& rgb : {Xyz{0.21, 0.72, 0.15}, Xyz{0.8, 0.3, 0.2}}) {
      const Xyz xyz = test::mul(test::kRec709ToXyz, rgb);
      const SpectrumResult r = sp.spectralize(xyz);
      EXPECT_EQ(r.status, Outcome::exact) << r.message;
      check_result(sp, ref, xyz, r, t);
    }
  }
}

TEST(Spectralizer, IsThreadSafe) {
  // spectralize() is documented thread-safe: two threads give the same spectra as one.
  const Spectralizer sp = make(Mode::emission);
  std::vector<Xyz> colours;
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int n = 0; n < 200; ++n)
    colours.push_back(test::rgb(test::kRec709ToXyz, u(rng), u(rng), u(rng)));
  std::vector<std::vector<double>> serial, parallel(colours.size());
  for (const Xyz& c : colours) serial.push_back(sp.spectralize(c).values);
  auto work = [&](std::size_t from) {
    for (std::size_t i = from; i < colours.size(); i += 2)
      parallel[i] = sp.spectralize(colours[i]).values;
  };
  std::thread a(work, 0), b(work, 1);
  a.join();
  b.join();
  for (std::size_t i = 0; i < colours.size(); ++i) {
    EXPECT_EQ(parallel[i], serial[i]) << i;
  }
}

TEST(Spectralizer, ConfigurationMistakesThrow) {
  test::expect_error_mentioning([] { make(Mode::emission, "380:780:5", "cie2006"); }, {"cie2006"},
                                "unknown observer");
  // A typo in the illuminant is an error in either mode.
  test::expect_error_mentioning([] { make(Mode::emission, "380:780:5", "cie1931", "D65x"); },
                                {"D65x"}, "unknown illuminant (emission)");
  test::expect_error_mentioning([] { (void)parse_mode("emissive"); }, {"emission", "reflectance"},
                                "unknown mode");
  EXPECT_EQ(parse_mode("reflectance"), Mode::reflectance);
}

}  // namespace
}  // namespace spectralize
