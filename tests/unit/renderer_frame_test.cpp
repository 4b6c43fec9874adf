// A renderer's RGB -> XYZ (src/core/colorimetry/renderer_frame.h): the matrix of published
// primaries and a white is the textbook one (oracle: the sRGB matrix as published to 7 digits with
// white (0.95047, 1, 1.08883)); an illuminant's white under an observer is its published
// chromaticity (CIE 015: D65 2 degrees 0.31272, 0.32903; A 0.44757, 0.40745); the two forms
// parse, print canonically and resolve; everything else is refused saying why.

#include "core/colorimetry/renderer_frame.h"

#include <gtest/gtest.h>

#include <string>

#include "spectralize/core/error.h"
#include "test_support.h"

namespace spectralize {
namespace {

constexpr std::array<double, 6> kSrgbPrimaries = {0.64, 0.33, 0.30, 0.60, 0.15, 0.06};

TEST(RendererFrame, PrimariesAndAWhiteGiveTheTextbookMatrix) {
  const Mat3 m = rgb_to_xyz_of_primaries(kSrgbPrimaries, Xyz{0.95047, 1.0, 1.08883});
  const Mat3 published = {0.4124564, 0.3575761, 0.1804375, 0.2126729, 0.7151522,
                          0.0721750, 0.0193339, 0.1191920, 0.9503041};
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(m[k], published[k], 1e-7) << k;
  // Its white is the white given, its columns the primaries' chromaticities.
  const Xyz w = mul(m, Xyz{1, 1, 1});
  EXPECT_NEAR(w.X, 0.95047, 1e-12);
  EXPECT_NEAR(w.Z, 1.08883, 1e-12);
  for (int c = 0; c < 3; ++c) {
    const double sum = m[c] + m[3 + c] + m[6 + c];
    EXPECT_NEAR(m[c] / sum, kSrgbPrimaries[2 * c], 1e-12);
    EXPECT_NEAR(m[3 + c] / sum, kSrgbPrimaries[2 * c + 1], 1e-12);
  }
}

TEST(RendererFrame, AnIlluminantsWhiteIsItsPublishedChromaticity) {
  const Observer& obs = Observer::get("cie1931");
  const Xyz d65 = illuminant_white(Illuminant::get("D65"), obs);
  const Xyz a = illuminant_white(Illuminant::get("A"), obs);
  EXPECT_EQ(d65.Y, 1.0);
  const auto xy65 = test::chromaticity(d65), xya = test::chromaticity(a);
  EXPECT_NEAR(xy65[0], 0.31272, 1e-5);
  EXPECT_NEAR(xy65[1], 0.32903, 1e-5);
  // A's published to five decimals from its 5 nm table; the 1 nm table's within 2e-5.
  EXPECT_NEAR(xya[0], 0.44757, 2e-5);
  EXPECT_NEAR(xya[1], 0.40745, 2e-5);
}

TEST(RendererFrame, NineNumbersAreTheMatrixAsGiven) {
  const RendererMatrix r = RendererMatrix::parse("0.5,0.3,0.2, 0.25,0.7,0.05,0,0.1,1.1");
  const Mat3 m = r.resolve(Observer::get("cie1931"));
  const Mat3 want = {0.5, 0.3, 0.2, 0.25, 0.7, 0.05, 0, 0.1, 1.1};
  EXPECT_EQ(m, want);
  EXPECT_EQ(r.to_string(), "0.5,0.3,0.2,0.25,0.7,0.05,0,0.1,1.1");
  EXPECT_EQ(RendererMatrix::parse(r.to_string()).resolve(Observer::get("cie1931")), want);
}

TEST(RendererFrame, PrimariesAndAnIlluminantResolveUnderTheObserver) {
  const RendererMatrix r = RendererMatrix::parse("0.64,0.33,0.3,0.6,0.15,0.06,d65");
  EXPECT_EQ(r.to_string(), "0.64,0.33,0.3,0.6,0.15,0.06,D65");
  const Observer& obs = Observer::get("cie1931");
  const Mat3 m = r.resolve(obs);
  // Oracle: the test's own normalised primary matrix with the test's own D65 integration.
  const Xyz w = test::illuminant_xyz(obs, Illuminant::get("D65"));
  const auto xy = test::chromaticity(w);
  const test::Mat3 want = test::rgb_to_xyz(0.64, 0.33, 0.3, 0.6, 0.15, 0.06, xy[0], xy[1]);
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(m[k], want[k / 3][k % 3], 1e-12) << k;
  // The 10 degree observer sees D65's white elsewhere (CIE 015: 0.31382, 0.33100).
  const Mat3 m10 = r.resolve(Observer::get("cie1964"));
  const auto xy10 = test::chromaticity(mul(m10, Xyz{1, 1, 1}));
  EXPECT_NEAR(xy10[0], 0.31382, 1e-5);
  EXPECT_NEAR(xy10[1], 0.33100, 1e-5);
}

TEST(RendererFrame, WhatIsNoMatrixIsRefusedSayingWhy) {
  test::expect_error_mentioning([] { RendererMatrix::parse("1,2,3"); }, {"nine numbers"},
                                "three numbers");
  test::expect_error_mentioning([] { RendererMatrix::parse("1,0,0,0,1,0,0,0,x"); },
                                {"'x' is not a number"}, "a word");
  test::expect_error_mentioning([] { RendererMatrix::parse("1,0,0,0,1,0,0,0,0x1p-2"); },
                                {"'0x1p-2' is a hexadecimal number"}, "a hexadecimal number");
  test::expect_error_mentioning([] { RendererMatrix::parse("1,0,0,0,1,0,0,0,nan"); },
                                {"'nan'", "not a finite number"}, "NaN");
  test::expect_error_mentioning([] { RendererMatrix::parse("1,0,0,2,0,0,0,0,1"); }, {"singular"},
                                "a singular matrix");
  test::expect_error_mentioning([] { RendererMatrix::parse("1,0,0,0,-1,0,0,0,1"); }, {"luminance"},
                                "a white of negative luminance");
  test::expect_error_mentioning([] { RendererMatrix::parse("0.64,0.33,0.3,0.6,0.15,0.06,Q7"); },
                                {"Q7"}, "an unknown illuminant");
  test::expect_error_mentioning([] { RendererMatrix::parse("0.64,0.33,0.64,0.33,0.15,0.06,D65"); },
                                {"no triangle"}, "two equal primaries");
  test::expect_error_mentioning([] { RendererMatrix::parse("0.64,0,0.3,0.6,0.15,0.06,D65"); },
                                {"y = 0"}, "a primary at y = 0");
  test::expect_error_mentioning([] { RendererMatrix::parse("64,33,30,60,15,6,D65"); },
                                {"chromaticity"}, "percentages");
}

}  // namespace
}  // namespace spectralize
