// What the commands share (tool/flags.h): --color values parsed strictly with the slip named;
// errors sorted into the command line's (exit 2, naming the flag) and the job's (exit 1); a
// --color's spectrum reproducing its colour, by the tests' own integration (docs/DESIGN.md §3)
// of the Rec.709 matrix written out; what is said on stderr at each verbosity.

#include "tool/flags.h"

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

TEST(Flags, AColourIsThreeNumbersSeparatedByCommasSpacesAllowed) {
  const Rgb c = parse_rgb(" 0.25, +0.5 ,1e-3");
  EXPECT_EQ(c.r, 0.25);
  EXPECT_EQ(c.g, 0.5);
  EXPECT_EQ(c.b, 0.001);
  EXPECT_EQ(c.text, " 0.25, +0.5 ,1e-3");  // named as given in messages
  const Rgb n = parse_rgb("-0.1,2,3");     // out of gamut is the spectralizer's to say
  EXPECT_EQ(n.r, -0.1);
}

TEST(Flags, AMalformedColourIsRefusedNamingTheValueAndTheSlip) {
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
  EXPECT_NE(usage_message("nan,0,0").find("components must be finite, got 'nan'"),
            std::string::npos);
  EXPECT_NE(usage_message("0,inf,0").find("must be finite"), std::string::npos);
  EXPECT_FALSE(usage_message("1e999,0,0").empty());  // beyond double: refused, not infinite
}

TEST(Flags, ValueMistakesAreTheCommandLinesAndFileOrConfigFailuresTheJobs) {
  try {
    usage_checked("--wavelengths", []() -> int { throw Error("step must be positive"); });
    ADD_FAILURE() << "no UsageError";
  } catch (const UsageError& e) {
    EXPECT_EQ(e.message, "--wavelengths: step must be positive");
  }
  try {
    usage_checked("", []() -> int { throw Error("bad value"); });
    ADD_FAILURE() << "no UsageError";
  } catch (const UsageError& e) {
    EXPECT_EQ(e.message, "bad value");
  }
  // A file or the config at fault: exit 1, the message unchanged.
  EXPECT_THROW(usage_checked("-o", []() -> int { throw FileError("'x.exr': disk full"); }),
               FileError);
  EXPECT_THROW(usage_checked("--config", []() -> int { throw ConfigError("no such file"); }),
               ConfigError);
  EXPECT_EQ(usage_checked("--x", [] { return 7; }), 7);
}

TEST(Flags, AColoursSpectrumReproducesItByTheReferenceIntegration) {
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

TEST(Flags, NegativeLuminanceIsMappedAndNaNFailsTheJob) {
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

TEST(Flags, ColoursInADataSpaceAreWarnedAboutAsAnImageIs) {
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

TEST(Flags, TheConsoleSaysWarningsUnlessQuietAndDetailsWhenVerbose) {
  const auto said = [](int verbosity, int level) {
    testing::internal::CaptureStderr();
    console_log(verbosity)(level, "m");
    return testing::internal::GetCapturedStderr();
  };
  EXPECT_EQ(said(0, 0), "");  // -q
  EXPECT_EQ(said(1, 0), "spectralize WARNING: m\n");
  EXPECT_EQ(said(1, 1), "");
  EXPECT_EQ(said(2, 1), "spectralize: m\n");  // -v
  EXPECT_EQ(said(2, 2), "spectralize: m\n");
  EXPECT_EQ(console_progress(0, "x"), nullptr);  // -q: no progress at all
}

}  // namespace
}  // namespace spectralize::tool
