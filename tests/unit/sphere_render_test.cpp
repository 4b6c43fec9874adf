// The figures' sphere renderer: the geometry is the unit sphere under an orthographic camera
// with the light at the eye (each pixel reflects in proportion to n.v = sqrt(1 - r^2)), the two
// renderers do what their names say, and the halves are compared pixel for mirror pixel. The
// expected values come from the geometry and from sums written out here, not from the code.

#include "figures/sphere_render.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/colorimetry/colour_difference.h"
#include "figures/figure_image.h"

namespace spectralize::figures {
namespace {

constexpr Mat3 kIdentity{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};

std::size_t at(int size, int x, int y) {
  return static_cast<std::size_t>(y) * size + x;
}

TEST(SphereGeometry, ShadingIsCosineOfTheViewAngle) {
  const int size = 101;  // odd: one pixel sits on the axis
  const SphereGeometry g = SphereGeometry::orthographic(size, 8);
  // The centre faces the camera and the light: n.v = 1 up to the pixel's own extent.
  EXPECT_NEAR(g.shading[at(size, 50, 50)], 1.0, 1e-3);
  EXPECT_EQ(g.coverage[at(size, 50, 50)], 1.0);
  // Half way out (r = 0.5 at pixel centre x = 75, u = 2 * 75.5 / 101 - 1): sqrt(1 - u^2).
  const double u = 2 * 75.5 / size - 1;
  EXPECT_NEAR(g.shading[at(size, 75, 50)], std::sqrt(1 - u * u), 1e-3);
  // Corners are off the sphere.
  EXPECT_EQ(g.coverage[at(size, 0, 0)], 0.0);
  EXPECT_EQ(g.shading[at(size, 0, 0)], 0.0);
  // The disc covers pi/4 of the frame; the mean of n.v over it is 2/3 (a hemisphere seen
  // head on), so the shading sums to pi/6 of the frame.
  double covered = 0, shade = 0;
  for (std::size_t i = 0; i < g.coverage.size(); ++i) {
    covered += g.coverage[i];
    shade += g.shading[i];
  }
  EXPECT_NEAR(covered / (size * size), std::numbers::pi / 4, 1e-3);
  EXPECT_NEAR(shade / (size * size), std::numbers::pi / 6, 1e-3);
}

TEST(SphereGeometry, IsMirrorSymmetricSoHalvesCanBeCompared) {
  const int size = 64;
  const SphereGeometry g = SphereGeometry::orthographic(size, 4);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size / 2; ++x) {
      EXPECT_EQ(g.shading[at(size, x, y)], g.shading[at(size, size - 1 - x, y)]);
      EXPECT_EQ(g.coverage[at(size, x, y)], g.coverage[at(size, size - 1 - x, y)]);
    }
}

TEST(SphereRender, RgbPixelIsAlbedoTimesLightTimesShading) {
  const int size = 33;
  const SphereGeometry g = SphereGeometry::orthographic(size, 4);
  const std::vector<Xyz> img = render_rgb(g, {0.5, 0.25, 1.0}, {2, 4, 3}, kIdentity);
  const std::size_t c = at(size, 16, 16);
  EXPECT_NEAR(img[c].X, 1.0 * g.shading[c], 1e-15);
  EXPECT_NEAR(img[c].Y, 1.0 * g.shading[c], 1e-15);
  EXPECT_NEAR(img[c].Z, 3.0 * g.shading[c], 1e-15);
  // Through a matrix: XYZ = M (albedo x light) shading.
  const Mat3 m{{{0.4, 0.3, 0.2}, {0.2, 0.7, 0.1}, {0.0, 0.1, 0.9}}};
  const std::vector<Xyz> mixed = render_rgb(g, {1, 1, 1}, {1, 0, 0}, m);
  EXPECT_NEAR(mixed[c].X, 0.4 * g.shading[c], 1e-15);
  EXPECT_NEAR(mixed[c].Z, 0.0, 1e-15);
}

TEST(SphereRender, SpectralPixelIsTheBandSumTimesShading) {
  const int size = 33;
  const SphereGeometry g = SphereGeometry::orthographic(size, 4);
  const std::vector<double> rho{0.2, 0.5, 1.0};
  const std::vector<Xyz> w{{1, 2, 3}, {0.5, 0.5, 0.5}, {0, 1, 0}};
  // sum rho_i W_i = (0.2 + 0.25, 0.4 + 0.25 + 1, 0.6 + 0.25) = (0.45, 1.65, 0.85).
  const std::vector<Xyz> img = render_spectral(g, rho, w, {2, 1, 0.5});
  const std::size_t c = at(size, 16, 16);
  EXPECT_NEAR(img[c].X, 0.90 * g.shading[c], 1e-15);
  EXPECT_NEAR(img[c].Y, 1.65 * g.shading[c], 1e-15);
  EXPECT_NEAR(img[c].Z, 0.425 * g.shading[c], 1e-15);
  // Twice the light, twice the radiance (brightness is proportional to light x albedo).
  std::vector<Xyz> w2;
  for (const Xyz& v : w) w2.push_back(2 * v);
  EXPECT_NEAR(render_spectral(g, rho, w2, {2, 1, 0.5})[c].Y, 2 * img[c].Y, 1e-15);
  EXPECT_THROW(render_spectral(g, rho, std::vector<Xyz>(2), {1, 1, 1}), std::exception);
}

TEST(SphereRender, NeutralSurfaceLooksTheSameInBothRenderers) {
  // A grey surface under any light: the RGB renderer's light is the light's colour (the XYZ
  // of rho == 1, here with M = identity), so both halves agree exactly.
  const int size = 48;
  const SphereGeometry g = SphereGeometry::orthographic(size, 2);
  const std::vector<Xyz> w{{0.3, 0.2, 0.0}, {0.4, 0.5, 0.1}, {0.1, 0.3, 0.9}};
  const std::vector<double> grey(3, 0.4);
  const Xyz white = w[0] + w[1] + w[2];
  const std::vector<Xyz> rgb =
      render_rgb(g, {0.4, 0.4, 0.4}, {white.X, white.Y, white.Z}, kIdentity);
  const std::vector<Xyz> spectral = render_spectral(g, grey, w, {1, 1, 1});
  const MirrorDifference d = mirror_delta_e(g, split_halves(size, rgb, spectral), white);
  EXPECT_LT(d.max, 1e-10);
  EXPECT_GT(d.pairs, 0u);
}

TEST(MirrorDeltaE, ComparesMirrorPixelsOfTheTwoHalves) {
  const int size = 40;
  const SphereGeometry g = SphereGeometry::orthographic(size, 2);
  const Xyz white{0.95047, 1.0, 1.08883};
  const std::vector<Xyz> left = render_rgb(g, {0.5, 0.5, 0.5}, {1, 1, 1}, kIdentity);
  const std::vector<Xyz> right = render_rgb(g, {0.5, 0.4, 0.5}, {1, 1, 1}, kIdentity);
  const std::vector<Xyz> split = split_halves(size, left, right);
  // The left half comes from `left`, the right half from `right`.
  EXPECT_EQ(split[at(size, 10, 20)].Y, left[at(size, 10, 20)].Y);
  EXPECT_EQ(split[at(size, 30, 20)].Y, right[at(size, 30, 20)].Y);
  const MirrorDifference d = mirror_delta_e(g, split, white);
  // Pixel (10, 20) is compared with (29, 20): same shading, different albedo.
  const std::size_t i = at(size, 10, 20), j = at(size, 29, 20);
  const double want = delta_e_2000(to_lab(left[i], white), to_lab(right[j], white));
  EXPECT_NEAR(d.delta_e[i], want, 1e-12);
  EXPECT_EQ(d.delta_e[j], d.delta_e[i]);
  EXPECT_GT(d.max, 1.0);
  // Every covered pixel of the left half is one pair.
  std::size_t covered = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size / 2; ++x) covered += g.coverage[at(size, x, y)] > 0 ? 1 : 0;
  EXPECT_EQ(d.pairs, covered);
  // The same image on both sides: no difference at all.
  EXPECT_EQ(mirror_delta_e(g, split_halves(size, left, left), white).max, 0.0);
}

TEST(Mat3, MatricesReadOffOcioUndoEachOther) {
  // RGB -> XYZ and XYZ -> RGB of Linear Rec.709, both read off OCIO: the round trip returns
  // the colour (1e-6: OCIO's float maths); a non-linear space is refused.
  const ColourSpaces spaces = ColourSpaces::load();
  const Mat3 m = rgb_to_xyz_matrix(spaces, "Linear Rec.709 (sRGB)");
  const Rgb back =
      to_rgb(xyz_to_rgb_matrix(spaces, "Linear Rec.709 (sRGB)"), mul(m, Rgb{0.21, 0.72, 0.15}));
  EXPECT_NEAR(back.r, 0.21, 1e-6);
  EXPECT_NEAR(back.g, 0.72, 1e-6);
  EXPECT_NEAR(back.b, 0.15, 1e-6);
  // The Rec.709 primaries (IEC 61966-2-1): Y of the green primary is 0.7152.
  EXPECT_NEAR(m[1][1], 0.7152, 1e-4);
  EXPECT_THROW(rgb_to_xyz_matrix(spaces, "sRGB - Texture"), std::exception);
}

}  // namespace
}  // namespace spectralize::figures
