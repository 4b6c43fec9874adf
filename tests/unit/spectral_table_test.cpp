// SpectralTable against direct solves and its own definition (docs/DESIGN.md §4, §14): the
// blend of a cell's node spectra reproduces each pixel's colour to float precision, equals the
// blend of the nodes solved directly by the Spectralizer, and stays within the bounds; colours
// outside are mapped and counted; stored nodes are checked against their own colour.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/tables/spectral_table.h"
#include "spectralize/core/spectralizer.h"
#include "test_support.h"

namespace spectralize {
namespace {

SpectralizerSettings settings(Mode mode) {
  SpectralizerSettings s;
  s.mode = mode;
  return s;
}

// The integration of test_support.h, written from the definition (not the library's weights).
Xyz integrate(const Spectralizer& sp, const std::vector<float>& v) {
  const std::vector<double> d(v.begin(), v.end());
  return test::reference_xyz(sp.settings().grid, d, Observer::get(sp.settings().observer),
                             sp.illuminant() ? &sp.illuminant()->spd : nullptr);
}

TEST(SpectralTable, EveryPixelReproducesItsColourToFloatPrecision) {
  for (Mode mode : {Mode::emission, Mode::reflectance}) {
    SCOPED_TRACE(std::string(to_string(mode)));
    const Spectralizer sp(settings(mode));
    SpectralTable table(sp);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0.02, 0.95);
    const std::size_t n = sp.settings().grid.size();
    std::vector<Xyz> colours;
    for (int i = 0; i < 500; ++i) {
      // Linear Rec.709 colours (inside both gamuts), to XYZ by the sRGB matrix.
      const double r = u(rng), g = u(rng), b = u(rng);
      colours.push_back({0.4124 * r + 0.3576 * g + 0.1805 * b, 0.2126 * r + 0.7152 * g + 0.0722 * b,
                         0.0193 * r + 0.1192 * g + 0.9505 * b});
    }
    std::vector<float> out(colours.size() * n);
    std::vector<PixelResult> results(colours.size());
    table.spectra(colours.data(), colours.size(), out.data(), results.data());
    double worst = 0;
    for (std::size_t i = 0; i < colours.size(); ++i) {
      std::vector<float> s(out.begin() + i * n, out.begin() + (i + 1) * n);
      for (float v : s) {
        ASSERT_GE(v, 0.0f);
        if (mode == Mode::reflectance) {
          ASSERT_LE(v, 1.0f);
        }
      }
      worst = std::max(worst, relative_error(integrate(sp, s), sp.target_of(colours[i])));
    }
    std::printf("  %s: worst relative XYZ error %.2g over 500 colours\n",
                std::string(to_string(mode)).c_str(), worst);
    EXPECT_LE(worst, 2e-6);
    EXPECT_GT(table.stats().nodes_computed, 0u);
  }
}

// Truth: an emission pixel inside a cell is (X+Y+Z) times the blend of the exact spectra of the
// corners of its triangle (spacing 1/128 in chromaticity; the square cut by its diagonal, the
// weights the gaps between the sorted fractional coordinates), each solved here directly. A
// table with transposed or wrong weights fails this.
TEST(SpectralTable, EmissionIsTheTriangleBlendOfDirectlySolvedNodes) {
  const Spectralizer sp(settings(Mode::emission));
  SpectralTable table(sp);
  const double step = 1.0 / 128;
  // Nodes every 1/128 through the white of the flat spectrum (docs/DESIGN.md §14).
  const std::vector<double> ones(sp.settings().grid.size(), 1.0);
  const Xyz flat = test::reference_xyz(sp.settings().grid, ones, Observer::get("cie1931"), nullptr);
  const double x0 = flat.X / flat.sum(), y0 = flat.Y / flat.sum();
  for (const auto& [x, y] :
       {std::pair{0.3127, 0.3290}, std::pair{0.4012, 0.2871}, std::pair{0.2213, 0.3817}}) {
    const double S = 2.5;
    const Xyz pixel{S * x, S * y, S * (1 - x - y)};
    std::vector<float> got(sp.settings().grid.size());
    PixelResult res;
    table.spectra(&pixel, 1, got.data(), &res);
    ASSERT_FALSE(res.fallback);
    const int ix = static_cast<int>(std::floor((x - x0) / step));
    const int iy = static_cast<int>(std::floor((y - y0) / step));
    const double ux = (x - x0) / step - ix, uy = (y - y0) / step - iy;
    std::vector<double> want(got.size(), 0.0);
    // (0,0) -> (1,0) -> (1,1) when ux >= uy, else (0,0) -> (0,1) -> (1,1).
    const int corners[3][2] = {{0, 0}, {ux >= uy ? 1 : 0, ux >= uy ? 0 : 1}, {1, 1}};
    const double hi = std::max(ux, uy), lo = std::min(ux, uy);
    const double weights[3] = {1 - hi, hi - lo, lo};
    for (int c = 0; c < 3; ++c) {
      const double nx = x0 + (ix + corners[c][0]) * step, ny = y0 + (iy + corners[c][1]) * step;
      const SpectrumResult node = sp.spectralize_target({nx, ny, 1 - nx - ny});
      for (std::size_t i = 0; i < want.size(); ++i) want[i] += S * weights[c] * node.values[i];
    }
    double peak = 0, diff = 0;
    for (std::size_t i = 0; i < want.size(); ++i) {
      peak = std::max(peak, want[i]);
      diff = std::max(diff, std::abs(want[i] - got[i]));
    }
    EXPECT_LE(diff, 1e-5 * peak) << "at (" << x << ", " << y << ")";
  }
}

// Truth (the guide): RGB (1, 1, 1) of a D65 space is the perfect reflector, rho == 1 everywhere,
// through the table too; the black pixel is the zero spectrum.
TEST(SpectralTable, WhiteIsOneAndBlackIsZero) {
  const Spectralizer sp(settings(Mode::reflectance));
  SpectralTable table(sp);
  const Xyz colours[2] = {kWhiteD65, Xyz{}};
  std::vector<float> got(2 * sp.settings().grid.size());
  PixelResult res[2];
  table.spectra(colours, 2, got.data(), res);
  const std::size_t n = sp.settings().grid.size();
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_NEAR(got[i], 1.0, 2e-6) << i;
    EXPECT_EQ(got[n + i], 0.0f) << i;
  }
  EXPECT_EQ(res[1].kind, Outcome::black);
}

// Stored nodes are adopted only when they are the spectra of their own colours.
TEST(SpectralTable, AdoptedNodesAreCheckedAgainstTheirColour) {
  const Spectralizer sp(settings(Mode::emission));
  SpectralTable made(sp);
  const Xyz c{0.3, 0.35, 0.4};
  std::vector<float> out(sp.settings().grid.size());
  PixelResult res;
  made.spectra(&c, 1, out.data(), &res);
  SpectralTable copy(sp), poisoned(sp);
  std::size_t adopted = 0, refused = 0;
  made.for_each_node([&](std::size_t index, std::span<const float> values) {
    EXPECT_TRUE(copy.adopt_node(index, values));
    ++adopted;
    std::vector<float> doubled(values.begin(), values.end());
    for (float& v : doubled) v *= 2;
    refused += !poisoned.adopt_node(index, doubled);
  });
  EXPECT_EQ(adopted, 4u);
  EXPECT_EQ(refused, 4u);
  EXPECT_FALSE(copy.adopt_node(copy.node_count(), out));  // index out of range
  EXPECT_FALSE(copy.adopt_node(0, {}));                   // no spectrum
  // The copy answers from the adopted nodes, without solving, with the same spectrum.
  std::vector<float> again(out.size());
  copy.spectra(&c, 1, again.data(), &res);
  EXPECT_EQ(copy.stats().nodes_computed, 0u);
  EXPECT_EQ(again, out);
}

// Colours outside the gamut are mapped (docs/DESIGN.md §5) and counted by kind, with no solve:
// the spectrum is the table's blend of the mapped colour, which the Spectralizer maps the same.
TEST(SpectralTable, OutsideColoursAreMappedByTheTableWithoutSolves) {
  for (Mode mode : {Mode::emission, Mode::reflectance}) {
    SCOPED_TRACE(std::string(to_string(mode)));
    const Spectralizer sp(settings(mode));
    SpectralTable table(sp);
    // A laser green (outside the locus) and, for reflectances, a green brighter than white.
    const Xyz colours[2] = {test::xyz_from_xy(0.1, 0.85, 0.5), test::xyz_from_xy(0.3, 0.6, 1.5)};
    std::vector<float> out(2 * sp.settings().grid.size());
    PixelResult res[2];
    table.spectra(colours, 2, out.data(), res);
    EXPECT_EQ(res[0].kind, Outcome::outside_locus);
    if (mode == Mode::reflectance) {
      EXPECT_EQ(res[1].kind, Outcome::outside_solid);
    }
    for (int c = 0; c < 2; ++c) {
      const SpectrumResult direct = sp.spectralize(colours[c]);
      EXPECT_LE(relative_error(res[c].target, direct.target), 1e-12);
      const std::vector<float> s(out.begin() + c * sp.settings().grid.size(),
                                 out.begin() + (c + 1) * sp.settings().grid.size());
      EXPECT_LE(relative_error(integrate(sp, s), direct.target), 1e-5);
      EXPECT_FALSE(res[c].fallback);
    }
    EXPECT_EQ(table.stats().fallback_solves, 0u);
  }
}

}  // namespace
}  // namespace spectralize
