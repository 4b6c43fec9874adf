// The scene's inputs: the ColorChecker chart's layout, its measured reflectances matching the
// committed chart image (the test integrates the CSV itself under D65), images converted by OCIO
// to linear RGB, and unit-luminance illuminants.

#include "path_tracer/scene_inputs.h"

#include <gtest/gtest.h>

#include "../test_support.h"

namespace spectralize::path_tracer {
namespace {

TEST(SceneInputs, ColorCheckerLayout) {
  EXPECT_EQ(colorchecker_patch(0, 0), -1);
  EXPECT_EQ(colorchecker_patch(2, 2), 0);
  EXPECT_EQ(colorchecker_patch(17, 17), 0);
  EXPECT_EQ(colorchecker_patch(18, 2), -1);
  EXPECT_EQ(colorchecker_patch(20, 2), 1);
  EXPECT_EQ(colorchecker_patch(2, 20), 6);
  EXPECT_EQ(colorchecker_patch(107, 71), 23);
  EXPECT_EQ(colorchecker_patch(108, 71), -1);
  EXPECT_EQ(colorchecker_patch(107, 72), -1);
}

TEST(SceneInputs, MeasuredChartIsTheChartImage) {
  const ColourSpaces spaces = ColourSpaces::load();
  const RgbImage img = read_linear_rgb(SPECTRALIZE_SOURCE_DIR "/testimages/colorchecker_srgb16.png",
                                       "sRGB - Texture", "Linear Rec.709 (sRGB)", spaces);
  ASSERT_EQ(img.width, 110);
  ASSERT_EQ(img.height, 74);
  const SampledSpectra truth = measured_colorchecker(img.width, img.height);
  const Observer& obs = Observer::get("cie1931");
  const std::vector<double> d65 = Illuminant::get("D65").spd;
  const WavelengthGrid grid;  // 380:780:5, the CSV's
  // As the chart was made (testimages/README.md): XYZ under D65 relative to a perfect reflector
  // over the whole 360..830 nm table.
  const std::vector<double> ones(471, 1.0);
  const double norm = test::raw_integral(360, 1, ones, obs, &d65).Y;
  const test::Mat3 to_rgb = test::inverse(test::kRec709ToXyz);
  const SpectralFilm film(obs);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const std::uint32_t t = static_cast<std::uint32_t>(y * img.width + x);
      // The texel's spectrum on the grid, read back through eval.
      std::vector<double> rho;
      for (std::size_t i = 0; i < grid.size(); i += 4) {
        WavelengthPacket p;
        for (int k = 0; k < 4; ++k)
          p.nm[k] = static_cast<float>(grid[std::min(i + k, grid.size() - 1)]);
        float v[4];
        truth.eval(t, std::span<const WavelengthPacket>(&p, 1), v);
        for (int k = 0; k < 4 && i + k < grid.size(); ++k) rho.push_back(v[k]);
      }
      const Xyz c = (1 / norm) * test::raw_integral(grid.start(), grid.step(), rho, obs, &d65);
      const Xyz want = test::mul(to_rgb, c);
      const float* got = &img.rgb[3 * t];
      const int patch = colorchecker_patch(x, y);
      // 16-bit sRGB codes: a step of 1/65535 in the encoding.
      const double tol = 3e-5;
      if (patch == 17)  // cyan: outside sRGB, its red clipped to 0 in the image
        EXPECT_NEAR(got[0], 0.0, tol);
      else
        EXPECT_NEAR(got[0], std::max(0.0, want.X), tol) << x << "," << y;
      EXPECT_NEAR(got[1], want.Y, tol) << x << "," << y;
      EXPECT_NEAR(got[2], want.Z, tol) << x << "," << y;
    }
}

TEST(SceneInputs, IlluminantsAtUnitLuminance) {
  const Observer& obs = Observer::get("cie1931");
  Xyz xyz;
  const std::vector<float> a = unit_illuminant("A", &xyz);
  ASSERT_EQ(a.size(), 471u);
  std::vector<double> v(a.begin(), a.end());
  const Xyz got = (1 / test::y_integral(obs)) * test::raw_integral(360, 1, v, obs, nullptr);
  EXPECT_NEAR(got.Y, 1.0, 1e-6);
  EXPECT_LT(test::rel_err(got, xyz), 1e-6);
  // Illuminant A's chromaticity (CIE 015: x = 0.44757, y = 0.40745).
  EXPECT_NEAR(test::chromaticity(xyz)[0], 0.44757, 2e-4);
  EXPECT_NEAR(test::chromaticity(xyz)[1], 0.40745, 2e-4);
}

TEST(SceneInputs, RefusesAnotherChart) {
  test::expect_error_mentioning([] { measured_colorchecker(64, 8); }, {"110 x 74", "64 x 8"},
                                "size");
}

}  // namespace
}  // namespace spectralize::path_tracer
