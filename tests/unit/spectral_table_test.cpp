// SpectralTable against direct solves and its own definition (docs/DESIGN.md §4): the blend of a
// cell's node spectra reproduces each pixel's colour to float precision, equals the bilinear
// (trilinear) blend of the nodes solved directly by the Spectralizer, and stays within the
// bounds; stored nodes are checked against their own colour.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/spectral_table.h"
#include "core/spectralizer.h"
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
        if (mode == Mode::reflectance) ASSERT_LE(v, 1.0f);
      }
      worst = std::max(worst, relative_error(integrate(sp, s), sp.target_of(colours[i])));
    }
    std::printf("  %s: worst relative XYZ error %.2g over 500 colours\n",
                std::string(to_string(mode)).c_str(), worst);
    EXPECT_LE(worst, 2e-6);
    EXPECT_GT(table.stats().nodes_computed, 0u);
  }
}

// Truth: an emission pixel inside a cell is (X+Y+Z) times the bilinear blend, with weights from
// its chromaticity, of the exact spectra of the cell's corners (spacing 1/128), each solved here
// directly. A table with transposed or wrong weights fails this.
TEST(SpectralTable, EmissionIsTheBilinearBlendOfDirectlySolvedNodes) {
  const Spectralizer sp(settings(Mode::emission));
  SpectralTable table(sp);
  const double step = 1.0 / 128;
  for (const auto& [x, y] :
       {std::pair{0.3127, 0.3290}, std::pair{0.4012, 0.2871}, std::pair{0.2213, 0.3817}}) {
    const double S = 2.5;
    const Xyz pixel{S * x, S * y, S * (1 - x - y)};
    std::vector<float> got(sp.settings().grid.size());
    PixelResult res;
    table.spectra(&pixel, 1, got.data(), &res);
    ASSERT_FALSE(res.fallback);
    const int ix = static_cast<int>(x / step), iy = static_cast<int>(y / step);
    const double ux = x / step - ix, uy = y / step - iy;
    std::vector<double> want(got.size(), 0.0);
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const double nx = (ix + dx) * step, ny = (iy + dy) * step;
        const SpectrumResult node = sp.spectralize_target({nx, ny, 1 - nx - ny});
        const double w = (dx ? ux : 1 - ux) * (dy ? uy : 1 - uy);
        for (std::size_t i = 0; i < want.size(); ++i) want[i] += S * w * node.values[i];
      }
    double peak = 0, diff = 0;
    for (std::size_t i = 0; i < want.size(); ++i) {
      peak = std::max(peak, want[i]);
      diff = std::max(diff, std::abs(want[i] - got[i]));
    }
    EXPECT_LE(diff, 1e-5 * peak) << "at (" << x << ", " << y << ")";
  }
}

// Truth (README): RGB (1, 1, 1) of a D65 space is the perfect reflector, rho == 1 everywhere,
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
  EXPECT_EQ(res[1].kind, PixelKind::black);
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
    if (values.empty()) return;
    std::vector<float> doubled(values.begin(), values.end());
    for (float& v : doubled) v *= 2;
    refused += !poisoned.adopt_node(index, doubled);
  });
  EXPECT_EQ(adopted, 4u);
  EXPECT_EQ(refused, 4u);
  EXPECT_FALSE(copy.adopt_node(copy.node_count(), {}));  // index out of range
  // The copy answers from the adopted nodes, without solving, with the same spectrum.
  std::vector<float> again(out.size());
  copy.spectra(&c, 1, again.data(), &res);
  EXPECT_EQ(copy.stats().nodes_computed, 0u);
  EXPECT_EQ(again, out);
}

}  // namespace
}  // namespace spectralize
