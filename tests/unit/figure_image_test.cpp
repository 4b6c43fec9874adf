// The figures' images (figures/figure_image.h): a linear space's matrices are the published
// ones (written out in test_support.h) and a curved space is refused; XYZ images are written as
// display sRGB, exposed, clipped, with NaN and negative light black (the sRGB encoding written out
// here); a sphere image blends the background by coverage; difference maps colour covered pixels
// by the ramp's stops and the rest grey, with a colour bar beneath. Images are read back from the
// PNG files (no labels drawn: the tests give none, or look where none is drawn).

#include "figures/figure_image.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "file_test_support.h"
#include "test_support.h"

namespace spectralize::figures {
namespace {

struct Png {
  int width = 0, height = 0, channels = 0;
  std::vector<unsigned char> pixels;
  int at(int x, int y, int c) const {
    return pixels[(static_cast<std::size_t>(y) * width + x) * channels + c];
  }
};

Png read_png(const std::string& path) {
  Png png;
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << path;
  if (!in) return png;
  const OIIO::ImageSpec& spec = in->spec();
  png.width = spec.width;
  png.height = spec.height;
  png.channels = spec.nchannels;
  EXPECT_EQ(spec.format, OIIO::TypeDesc::UINT8) << path;
  png.pixels.resize(static_cast<std::size_t>(png.width) * png.height * png.channels);
  EXPECT_TRUE(in->read_image(0, 0, 0, png.channels, OIIO::TypeDesc::UINT8, png.pixels.data()));
  return png;
}

// The sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1], as 8 bits.
int srgb8(double linear) {
  const double v = linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
  return static_cast<int>(std::lround(255 * v));
}

int unit8(double v) {
  return static_cast<int>(std::lround(255 * v));
}

void expect_pixel(const Png& png, int x, int y, std::array<int, 3> want, const std::string& what) {
  for (int c = 0; c < 3; ++c)
    EXPECT_NEAR(png.at(x, y, c), want[c], 1) << what << " (" << x << ", " << y << ") channel " << c;
}

TEST(FigureImage, LinearSpaceMatricesAreThePublishedOnes) {
  const ColourSpaces spaces = ColourSpaces::load();
  const Mat3 m709 = rgb_to_xyz_matrix(spaces, "Linear Rec.709 (sRGB)");
  const Mat3 m2020 = rgb_to_xyz_matrix(spaces, "Linear Rec.2020");
  const Mat3 inv709 = xyz_to_rgb_matrix(spaces, "Linear Rec.709 (sRGB)");
  const test::Mat3 want_inv = test::inverse(test::kRec709ToXyz);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) {
      // OCIO works in float.
      EXPECT_NEAR(m709[r][c], test::kRec709ToXyz[r][c], 2e-6) << r << c;
      EXPECT_NEAR(m2020[r][c], test::kRec2020ToXyz[r][c], 2e-6) << r << c;
      EXPECT_NEAR(inv709[r][c], want_inv[r][c], 1e-5) << r << c;
    }
}

TEST(FigureImage, ACurvedSpaceIsRefusedNamingIt) {
  const ColourSpaces spaces = ColourSpaces::load();
  test::expect_error_mentioning([&] { rgb_to_xyz_matrix(spaces, "sRGB - Texture"); },
                                {"sRGB - Texture", "not linear"}, "rgb_to_xyz_matrix");
  test::expect_error_mentioning([&] { xyz_to_rgb_matrix(spaces, "sRGB - Texture"); },
                                {"sRGB - Texture", "not linear"}, "xyz_to_rgb_matrix");
}

TEST(XyzPng, IsExposedDisplaySrgbClippedWithNanAndNegativeLightBlack) {
  const ColourSpaces spaces = ColourSpaces::load();
  const test::TempDir dir("figure_image");
  const Xyz white = test::d65_white();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Exposure 0.5: each pixel is shown at half its value.
  const std::vector<Xyz> xyz = {2.0 * white,
                                0.36 * white,
                                Xyz{},
                                4.0 * white,
                                Xyz{nan, nan, nan},
                                -1.0 * white,
                                test::rgb(test::kRec709ToXyz, 2, 0, 0),
                                test::rgb(test::kRec709ToXyz, 0, 0.36, 0)};
  const std::string path = dir / "xyz.png";
  write_xyz_png(path, 4, 2, xyz, 0.5, spaces);
  const Png png = read_png(path);
  ASSERT_EQ(png.width, 4);
  ASSERT_EQ(png.height, 2);
  ASSERT_EQ(png.channels, 3);
  const int grey = srgb8(0.18);
  expect_pixel(png, 0, 0, {255, 255, 255}, "white");
  expect_pixel(png, 1, 0, {grey, grey, grey}, "18% grey");
  expect_pixel(png, 2, 0, {0, 0, 0}, "black");
  expect_pixel(png, 3, 0, {255, 255, 255}, "over white, clipped");
  expect_pixel(png, 0, 1, {0, 0, 0}, "NaN");
  expect_pixel(png, 1, 1, {0, 0, 0}, "negative");
  expect_pixel(png, 2, 1, {255, 0, 0}, "the red primary");
  expect_pixel(png, 3, 1, {0, grey, 0}, "18% green");
  // Nothing is left beside the image (the write goes through a temporary file).
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir.dir)) ++files;
  EXPECT_EQ(files, 1u);
}

TEST(XyzPng, AWrongPixelCountOrAnUnwritablePathIsRefusedNamingTheFile) {
  const ColourSpaces spaces = ColourSpaces::load();
  const test::TempDir dir("figure_image");
  const std::string path = dir / "short.png";
  test::expect_error_mentioning([&] { write_xyz_png(path, 4, 2, std::vector<Xyz>(7), 1, spaces); },
                                {path, "7 pixels", "4 x 2"}, "7 pixels for 8");
  EXPECT_FALSE(std::filesystem::exists(path));
  const std::string missing = dir / "no/such/folder/x.png";
  test::expect_error_mentioning([&] { write_xyz_png(missing, 1, 1, {Xyz{}}, 1, spaces); },
                                {missing}, "a missing folder");
}

TEST(SpherePng, BlendsTheBackgroundByCoverageUnderOneExposure) {
  const ColourSpaces spaces = ColourSpaces::load();
  const test::TempDir dir("figure_image");
  const int size = 32;
  const SphereGeometry g = SphereGeometry::orthographic(size, 4);
  const Xyz white = test::d65_white();
  // The sphere shows 36% white at exposure 0.5: 18% on display.
  std::vector<Xyz> xyz(g.coverage.size());
  for (std::size_t i = 0; i < xyz.size(); ++i) xyz[i] = (0.36 * g.coverage[i]) * white;
  SphereView view;
  view.exposure = 0.5;
  view.background = 0.05 * white;
  view.left_label = view.right_label = "";
  const std::string path = dir / "sphere.png";
  write_sphere_png(path, g, xyz, view, spaces);
  const Png png = read_png(path);
  ASSERT_EQ(png.width, size);
  ASSERT_EQ(png.height, size);
  int partial = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double c = g.coverage[static_cast<std::size_t>(y) * size + x];
      // Exposure on the sphere's light, not on the background it is blended over.
      const int want = srgb8(0.5 * 0.36 * c + (1 - c) * 0.05);
      expect_pixel(png, x, y, {want, want, want}, "coverage " + std::to_string(c));
      partial += c > 0 && c < 1;
    }
  EXPECT_GT(partial, 0);  // the edge's pixels were blended
}

// The ramp's stops (figure_image.cpp): 0 -> (0, 0, 0.02), scale / 2 -> (0.70, 0.16, 0.35),
// scale and beyond -> (0.99, 0.99, 0.70); an eighth of the scale half way between the first two.
TEST(DeltaEMapPng, ColoursCoveredPixelsByTheRampAndTheRestGreyAboveAColourBar) {
  const test::TempDir dir("figure_image");
  const int size = 64;
  const double scale = 4;
  std::vector<double> de(static_cast<std::size_t>(size) * size, 0.0);
  std::vector<bool> covered(de.size(), true);
  auto at = [&](int x, int y) { return static_cast<std::size_t>(y) * size + x; };
  de[at(1, 0)] = scale / 2;
  de[at(2, 0)] = scale;
  de[at(3, 0)] = 100 * scale;
  de[at(4, 0)] = scale / 8;
  covered[at(5, 0)] = false;
  de[at(5, 0)] = scale;  // not covered: grey whatever its value
  const std::string path = dir / "de.png";
  write_delta_e_map_png(path, size, de, covered, scale, "");
  const Png png = read_png(path);
  ASSERT_EQ(png.width, size);
  ASSERT_EQ(png.height, delta_e_map_height(size));
  const std::array<int, 3> low{0, 0, unit8(0.02)}, mid{unit8(0.70), unit8(0.16), unit8(0.35)},
      high{unit8(0.99), unit8(0.99), unit8(0.70)}, grey{unit8(0.5), unit8(0.5), unit8(0.5)};
  expect_pixel(png, 0, 0, low, "0");
  expect_pixel(png, 1, 0, mid, "scale / 2");
  expect_pixel(png, 2, 0, high, "scale");
  expect_pixel(png, 3, 0, high, "beyond the scale");
  expect_pixel(png, 4, 0, {unit8(0.14), unit8(0.025), unit8(0.235)}, "scale / 8");
  expect_pixel(png, 5, 0, grey, "not covered");
  expect_pixel(png, size - 1, size - 1, low, "the last pixel");
  // Grey between the map and the bar; the bar runs from the ramp's start to its end.
  expect_pixel(png, size / 2, size + 2, grey, "the gap");
  const int margin = size / 16, bar = size + 8 + 8;
  expect_pixel(png, margin, bar, low, "the bar's start");
  expect_pixel(png, size - margin - 1, bar, high, "the bar's end");
  expect_pixel(png, margin - 1, bar, grey, "left of the bar");
}

TEST(DeltaEMapPng, AMapOfTheWrongSizeIsRefusedNamingTheFile) {
  const test::TempDir dir("figure_image");
  const std::string path = dir / "de.png";
  test::expect_error_mentioning(
      [&] {
        write_delta_e_map_png(path, 8, std::vector<double>(63), std::vector<bool>(64), 1, "");
      },
      {path, "8 x 8"}, "63 values for 8 x 8");
  test::expect_error_mentioning(
      [&] {
        write_delta_e_map_png(path, 8, std::vector<double>(64), std::vector<bool>(60), 1, "");
      },
      {path, "8 x 8"}, "60 coverage flags for 8 x 8");
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(DeltaEPng, ShowsTheMirrorDifferenceOnTheSphereOnly) {
  const test::TempDir dir("figure_image");
  const int size = 32;
  const SphereGeometry g = SphereGeometry::orthographic(size, 2);
  MirrorDifference d;
  d.delta_e.assign(g.coverage.size(), 10.0);  // off the sphere too: must not be shown
  const std::string path = dir / "mirror.png";
  write_delta_e_png(path, g, d, 10.0, "");
  const Png png = read_png(path);
  ASSERT_EQ(png.height, delta_e_map_height(size));
  const std::array<int, 3> high{unit8(0.99), unit8(0.99), unit8(0.70)},
      grey{unit8(0.5), unit8(0.5), unit8(0.5)};
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      expect_pixel(png, x, y, g.coverage[static_cast<std::size_t>(y) * size + x] > 0 ? high : grey,
                   "pixel");
}

}  // namespace
}  // namespace spectralize::figures
