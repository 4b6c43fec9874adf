// The job plan (pipeline/job_plan.h): settings checked against the output and the config before
// any work, messages spelt as the caller spells options, the mode resolved once per subject, and
// an input decided with the channel count the layout writes. Oracles: the guide's "Conventions"
// (docs/guide/conventions.md) (light or surface) and docs/DESIGN.md §7 (the channels of a spectral
// OpenEXR).

#include "pipeline/job_plan.h"

#include <gtest/gtest.h>

#include <string>

#include "file_test_support.h"
#include "spectralize/core/error.h"

namespace spectralize {
namespace {

using test::spec_of;

const OptionNames kFlags{"--", "-o"};
const OptionNames kKeywords{"", "output"};

std::string message_of(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(JobPlan, ColourJobsWithoutAnImageTakeTheirSubjectsDefaultMode) {
  // --mode wins; else float colours and spectra are light, a render-time table is for textures.
  for (ColourSubject subject :
       {ColourSubject::colours, ColourSubject::spectra, ColourSubject::table}) {
    EXPECT_EQ(mode_of_subject(ModeChoice::reflectance, subject), Mode::reflectance);
    EXPECT_EQ(mode_of_subject(ModeChoice::emission, subject), Mode::emission);
  }
  EXPECT_EQ(mode_of_subject(ModeChoice::automatic, ColourSubject::colours), Mode::emission);
  EXPECT_EQ(mode_of_subject(ModeChoice::automatic, ColourSubject::spectra), Mode::emission);
  EXPECT_EQ(mode_of_subject(ModeChoice::automatic, ColourSubject::table), Mode::reflectance);
  // And the plan carries it, with the config's scene-linear space by default.
  const JobPlan plan = plan_colours(Settings{}, ColourSubject::table, kFlags);
  EXPECT_EQ(plan.settings.spectral.mode, Mode::reflectance);
  EXPECT_EQ(plan.settings.colorspace, "Linear Rec.709 (sRGB)");
  ASSERT_TRUE(plan.spaces);
}

TEST(JobPlan, ColoursInADataSpaceAreWarnedAboutInTheWordsAnImageIs) {
  // A space the config marks as data ("isdata: true": Raw) holds no colour: colours in it are
  // taken as CIE XYZ with a warning, as an image in it is (the guide's "--color"
  // (docs/guide/colours.md)); not refused.
  Settings raw;
  raw.colorspace = "Raw";
  const JobPlan colours = plan_colours(raw, ColourSubject::colours, kKeywords);
  ASSERT_EQ(colours.warnings.size(), 1u);
  EXPECT_NE(colours.warnings[0].find("'Raw' is marked as data"), std::string::npos);
  EXPECT_NE(colours.warnings[0].find("taken as CIE XYZ"), std::string::npos);
  const JobPlan image = planned_input(plan_to_spectral(raw, "out.exr", kFlags), "albedo.png",
                                      spec_of({"R", "G", "B"}, OIIO::TypeUInt8));
  ASSERT_FALSE(image.interpretation.warnings.empty());
  EXPECT_EQ(image.interpretation.warnings[0], "'albedo.png': " + colours.warnings[0]);
  // A colour space is not data: nothing to say.
  EXPECT_TRUE(plan_colours(Settings{}, ColourSubject::colours, kKeywords).warnings.empty());
}

TEST(JobPlan, SettingsAreRefusedNamingTheOptionAsTheCallerSpellsIt) {
  Settings s;
  s.colorspace = "no such space";
  const std::string cli = message_of([&] { plan_to_spectral(s, "out.exr", kFlags); });
  const std::string python = message_of([&] { plan_to_spectral(s, "out.exr", kKeywords); });
  EXPECT_EQ(cli.rfind("--colorspace: ", 0), 0u) << cli;
  EXPECT_EQ(python.rfind("colorspace: ", 0), 0u) << python;
  // A spectral image is an OpenEXR of half or float samples.
  EXPECT_NE(message_of([] {
              plan_to_spectral(Settings{}, "out.png", kKeywords);
            }).find("output 'out.png'"),
            std::string::npos);
  Settings uint8;
  uint8.integer_bits = 8;
  EXPECT_NE(message_of([&] { plan_to_spectral(uint8, "out.exr", kFlags); }).find("--format uint8"),
            std::string::npos);
  // Spectra to RGB: a colour space or a display, not both.
  Settings both;
  both.colorspace = "ACEScg";
  both.display = "sRGB";
  EXPECT_NE(message_of([&] {
              plan_to_rgb(both, "out.exr", false, false, kKeywords);
            }).find("give colorspace or display, not both"),
            std::string::npos);
}

TEST(JobPlan, RgbOutputsTakeTheirFormatsDefaults) {
  // Integer formats are display-referred: 8 bits and the config's texture space; OpenEXR keeps
  // half and the scene-linear space.
  const JobPlan png = plan_to_rgb(Settings{}, "out.png", false, false, kFlags);
  EXPECT_EQ(png.settings.integer_bits, 8);
  EXPECT_EQ(png.settings.colorspace, "sRGB - Texture");
  const JobPlan exr = plan_to_rgb(Settings{}, "out.exr", false, false, kFlags);
  EXPECT_EQ(exr.settings.integer_bits, 0);
  EXPECT_EQ(exr.settings.colorspace, "Linear Rec.709 (sRGB)");
  EXPECT_TRUE(png.to_rgb && exr.to_rgb);
  EXPECT_FALSE(png.decided());
}

TEST(JobPlan, AnInputIsDecidedWithTheChannelsItsOutputHas) {
  // An 8-bit texture named albedo is a surface by its name (no pixels read); its spectral
  // OpenEXR holds the bands, R, G, B previews and, with alpha, A (docs/DESIGN.md §7).
  const JobPlan plan = plan_to_spectral(Settings{}, "out.exr", kFlags);
  const std::size_t bands = plan.settings.spectral.grid.size();
  const JobPlan rgb = planned_input(plan, "albedo.png", spec_of({"R", "G", "B"}, OIIO::TypeUInt8));
  EXPECT_TRUE(rgb.decided());
  EXPECT_EQ(rgb.settings.spectral.mode, Mode::reflectance);
  EXPECT_EQ(rgb.settings.colorspace, "sRGB - Texture");
  EXPECT_FALSE(rgb.interpretation.mode_reason.empty());
  EXPECT_EQ(rgb.output_channels, static_cast<int>(bands) + 3);
  OIIO::ImageSpec rgba = spec_of({"R", "G", "B", "A"}, OIIO::TypeUInt8);
  rgba.alpha_channel = 3;
  EXPECT_EQ(planned_input(plan, "albedo.png", rgba).output_channels, static_cast<int>(bands) + 4);
  // --mode decides before the name.
  Settings light;
  light.mode = ModeChoice::emission;
  EXPECT_EQ(planned_input(plan_to_spectral(light, "out.exr", kFlags), "albedo.png",
                          spec_of({"R", "G", "B"}, OIIO::TypeUInt8))
                .settings.spectral.mode,
            Mode::emission);
}

TEST(JobPlan, ASpectralInputIsDecidedByItsChannels) {
  // Reflectance (T.*) channels make a reflective input, S0.* an emissive one; RGB out has alpha
  // when the input does.
  const JobPlan plan = plan_to_rgb(Settings{}, "out.exr", false, false, kFlags);
  const JobPlan t = planned_input(plan, "t.exr", spec_of({"T.500nm", "T.600nm", "T.700nm"}));
  EXPECT_EQ(t.settings.spectral.mode, Mode::reflectance);
  EXPECT_EQ(t.output_channels, 3);
  const JobPlan e =
      planned_input(plan, "e.exr", spec_of({"A", "S0.500nm", "S0.600nm", "S0.700nm"}));
  EXPECT_EQ(e.settings.spectral.mode, Mode::emission);
  EXPECT_EQ(e.output_channels, 4);
  // Not spectral at all: refused, naming the file.
  auto plan_rgb = [&] { planned_input(plan, "rgb.exr", spec_of({"R", "G", "B"})); };
  const std::string refused = message_of(plan_rgb);
  EXPECT_NE(refused.find("rgb.exr"), std::string::npos) << refused;
}

}  // namespace
}  // namespace spectralize
