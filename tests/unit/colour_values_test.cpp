// The --color values (tool/colour_values.h): parsed strictly with the slip named; a colour's
// spectrum reproducing it, by the tests' own integration (docs/DESIGN.md §3) of the Rec.709
// matrix written out; negative and NaN colours; colours in a data space warned about.

#include "tool/colour_values.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "test_support.h"

namespace spectralize::tool {
namespace {

std::string usage_message(const std::string& text) {
  try {
    parse_rgb(text);
  } catch (const UsageError& e) {
    return e.message;
  }
  return "";
}

TEST(ColourValues, AColourIsThreeNumbersSeparatedByCommasSpacesAllowed) {
  const Rgb c = parse_rgb(" 0.25, +0.5 ,1e-3");
  EXPECT_EQ(c.r, 0.25);
  EXPECT_EQ(c.g, 0.5);
  EXPECT_EQ(c.b, 0.001);
  EXPECT_EQ(c.text, " 0.25, +0.5 ,1e-3");  // named as given in messages
  const Rgb n = parse_rgb("-0.1,2,3");     // out of gamut is the spectralizer's to say
  EXPECT_EQ(n.r, -0.1);
}

TEST(ColourValues, AMalformedColourIsRefusedNamingTheValueAndTheSlip) {
  // The usual slip: the components given as separate words.
  const std::string words = usage_message("1");
  EXPECT_NE(words.find("expected 3 components R,G,B separated by commas, got 1"), std::string::npos)
      << words;
  EXPECT_NE(words.find("write --color 1,0.5,0.2, not --color 1 0.5 0.2"), std::string::npos);
  EXPECT_NE(usage_message("1,2").find("got 2"), std::string::npos);
  EXPECT_EQ(usage_message("1,2").find("not --color"), std::string::npos);  // only for one
  EXPECT_NE(usage_message("1,2,3,4").find("got 4"), std::string::npos);
  EXPECT_NE(usage_message("1,x,3").find("--color '1,x,3': 'x' is not a number"), std::string::npos);
  EXPECT_NE(usage_message("1,,3").find("'' is not a number"), std::string::npos);
  EXPECT_NE(usage_message("1,2,3abc").find("'3abc' is not a number"), std::string::npos);
  EXPECT_NE(usage_message("nan,0,0").find("'nan' is not a finite number"), std::string::npos);
  EXPECT_NE(usage_message("0,inf,0").find("'inf' is not a finite number"), std::string::npos);
  // A finite number in another notation is named for what it is (core/decimal_number.h).
  EXPECT_NE(usage_message("0x1p-2,0,0")
                .find("'0x1p-2' is a hexadecimal number; write it in "
                      "decimal (0.25)"),
            std::string::npos)
      << usage_message("0x1p-2,0,0");
  EXPECT_FALSE(usage_message("1e999,0,0").empty());  // beyond double: refused, not infinite
}

TEST(ColourValues, AColoursSpectrumReproducesItByTheReferenceIntegration) {
  // Emission (auto for --color) in the config's scene-linear space, Linear Rec.709: the
  // spectrum's XYZ is the colour's by the IEC 61966-2-1 matrix, within 1e-5.
  const Options options;
  const ColourInputs in = colour_inputs(options);
  EXPECT_EQ(in.settings.mode, Mode::emission);
  const Spectralizer spectralizer(in.settings);
  int status = kExitOk;
  const SpectrumResult r =
      spectralize_colour(spectralizer, nullptr, in.to_xyz, parse_rgb("0.2,0.3,0.4"), status);
  EXPECT_EQ(status, kExitOk);
  EXPECT_EQ(r.status, Outcome::exact);
  const Xyz want = test::rgb(test::kRec709ToXyz, 0.2, 0.3, 0.4);
  const Xyz got =
      test::reference_xyz(in.settings.grid, r.values, Observer::get(in.settings.observer), nullptr);
  EXPECT_LE(test::rel_err(got, want), 1e-5);
  for (double v : r.values) EXPECT_GE(v, 0.0);
}

TEST(ColourValues, NegativeLuminanceIsMappedAndNaNFailsTheJob) {
  const ColourInputs in = colour_inputs(Options{});
  const Spectralizer spectralizer(in.settings);
  int status = kExitOk;
  testing::internal::CaptureStderr();
  const SpectrumResult black =
      spectralize_colour(spectralizer, nullptr, in.to_xyz, parse_rgb("-0.2,-0.1,-0.3"), status);
  const std::string warned = testing::internal::GetCapturedStderr();
  EXPECT_EQ(status, kExitOk);  // out of gamut and mapped: exit 0, as a pixel
  EXPECT_EQ(black.status, Outcome::negative);
  for (double v : black.values) EXPECT_EQ(v, 0.0);
  EXPECT_NE(warned.find("spectralize WARNING: colour -0.2,-0.1,-0.3"), std::string::npos);
  EXPECT_NE(warned.find("negative luminance"), std::string::npos) << warned;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  testing::internal::CaptureStderr();
  const SpectrumResult bad =
      spectralize_colour(spectralizer, nullptr, in.to_xyz, Rgb{nan, 0, 0, "nan,0,0"}, status);
  const std::string failed = testing::internal::GetCapturedStderr();
  EXPECT_EQ(status, kExitFailure);
  EXPECT_EQ(bad.status, Outcome::invalid);
  EXPECT_NE(failed.find("spectralize ERROR: colour nan,0,0"), std::string::npos) << failed;
}

TEST(ColourValues, ColoursInADataSpaceAreWarnedAboutAsAnImageIs) {
  Options options;
  options.settings.colorspace = "Raw";
  testing::internal::CaptureStderr();
  const ColourInputs in = colour_inputs(options);
  const std::string err = testing::internal::GetCapturedStderr();
  EXPECT_NE(err.find("spectralize WARNING: colour space 'Raw' is marked as data"),
            std::string::npos)
      << err;
  // Its values are CIE XYZ: the transform is the identity.
  const Xyz x = in.to_xyz(0.2, 0.3, 0.4);
  EXPECT_NEAR(x.X, 0.2, 1e-6);
  EXPECT_NEAR(x.Y, 0.3, 1e-6);
  EXPECT_NEAR(x.Z, 0.4, 1e-6);
  testing::internal::CaptureStderr();
  colour_inputs(Options{});
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
}

}  // namespace
}  // namespace spectralize::tool
