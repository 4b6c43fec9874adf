// The input interpretation (classify/input_interpretation.h): channels, colour space and its
// reason, data or colour, ICC descriptions, each against the standards' and the config's own
// definitions.

#include "classify/input_interpretation.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <sstream>

#include "colour/colour_space.h"
#include "file_test_support.h"
#include "spectralize/core/error.h"

namespace spectralize {
namespace {

using test::spec_of;

TEST(InputInterpretation, ColourAndAlphaChannelsByName) {
  ChannelRoles r = colour_channels(spec_of({"B", "G", "R", "A"}), "x.exr");
  EXPECT_EQ(r.colour, (std::vector<int>{2, 1, 0}));
  EXPECT_EQ(r.alpha, 3);
  r = colour_channels(spec_of({"Y"}), "grey.png");
  EXPECT_TRUE(r.grey());
  r = colour_channels(spec_of({"Y", "A"}), "grey.png");
  EXPECT_EQ(r.colour, std::vector<int>{0});
  EXPECT_EQ(r.alpha, 1);
  r = colour_channels(spec_of({"R", "G", "B", "Z"}), "depth.exr");
  EXPECT_EQ(r.ignored, std::vector<std::string>{"Z"});
  for (const auto& names :
       std::vector<std::vector<std::string>>{{"R", "G"},
                                             {"diffuse.R", "diffuse.G", "diffuse.B"},
                                             {"S0.500,0nm", "S0.600,0nm"},
                                             {"U", "V"}})
    EXPECT_THROW(colour_channels(spec_of(names), "f.exr"), Error) << names[0];
}

TEST(InputInterpretation, ColourSpaceByCommandLineMetadataRulesConventionsThenRoles) {
  const ColourSpaces spaces = ColourSpaces::load();
  const ColourSpaces aces = ColourSpaces::load(
      SPECTRALIZE_SOURCE_DIR "/tests/ocio/cg-config-v1.0.0_aces-v1.3_ocio-v2.1.ocio");
  Settings s;
  // Roles of the shipped config by data type.
  InputInterpretation in = interpret_colour("a.exr", spec_of({"R", "G", "B"}), s, spaces);
  EXPECT_EQ(in.colorspace, "Linear Rec.709 (sRGB)");
  EXPECT_NE(in.colorspace_reason.find("scene_linear"), std::string::npos);
  in = interpret_colour("a.tif", spec_of({"R", "G", "B"}, OIIO::TypeUInt8), s, spaces);
  EXPECT_EQ(in.colorspace, "sRGB - Texture");
  EXPECT_NE(in.colorspace_reason.find("matte_paint"), std::string::npos);
  // The formats' conventions outrank the roles: Radiance HDR is linear Rec.709 (not the ACES
  // config's scene_linear, ACEScg), an untagged PNG is sRGB.
  in = interpret_colour("sky.hdr", spec_of({"R", "G", "B"}), s, aces);
  EXPECT_EQ(in.colorspace, "Linear Rec.709 (sRGB)");
  EXPECT_NE(in.colorspace_reason.find("Radiance"), std::string::npos);
  in = interpret_colour("a.png", spec_of({"R", "G", "B"}, OIIO::TypeUInt8), s, aces);
  EXPECT_EQ(in.colorspace, "sRGB - Texture");
  EXPECT_NE(in.colorspace_reason.find("PNG"), std::string::npos);
  EXPECT_EQ(interpret_colour("a.exr", spec_of({"R", "G", "B"}), s, aces).colorspace, "ACEScg");
  // EXR chromaticities of ACES AP1 with the ACES white: ACEScg.
  OIIO::ImageSpec ap1 = spec_of({"R", "G", "B"});
  const float xy[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
  ap1.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), xy);
  EXPECT_EQ(interpret_colour("a.exr", ap1, s, spaces).colorspace, "ACEScg");
  // Rec.709 adapted to D50 (Photoshop): Rec.709, also under the ACES config, the reason saying
  // how it was matched.
  OIIO::ImageSpec d50 = spec_of({"R", "G", "B"});
  const float ps[8] = {0.6484f, 0.3309f, 0.3212f, 0.5978f, 0.1559f, 0.0660f, 0.3457f, 0.3585f};
  d50.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), ps);
  in = interpret_colour("city.exr", d50, s, aces);
  EXPECT_EQ(in.colorspace, "Linear Rec.709 (sRGB)");
  EXPECT_NE(in.colorspace_reason.find("Bradford"), std::string::npos) << in.colorspace_reason;
  EXPECT_TRUE(in.warnings.empty());
  // File rules against the file's chromaticities (the shipped config's *_linear*, *_srgb*,
  // *_acescg*): an agreeing rule refines the encoding, a disagreeing one is warned and the
  // file's own statement followed.
  in = interpret_colour("wall_srgb.exr", d50, s, spaces);
  EXPECT_EQ(in.colorspace, "sRGB - Texture");
  EXPECT_NE(in.colorspace_reason.find("file rule 'sRGB'"), std::string::npos);
  in = interpret_colour("lamp_acescg.exr", ap1, s, spaces);
  EXPECT_EQ(in.colorspace, "ACEScg");
  EXPECT_TRUE(in.warnings.empty());
  in = interpret_colour("lamp_linear.exr", ap1, s, spaces);
  EXPECT_EQ(in.colorspace, "ACEScg");
  ASSERT_EQ(in.warnings.size(), 1u);
  EXPECT_NE(in.warnings[0].find("file rule 'Linear'"), std::string::npos) << in.warnings[0];
  // Without metadata the rule applies.
  EXPECT_EQ(interpret_colour("lamp_linear.exr", spec_of({"R", "G", "B"}), s, aces).colorspace,
            "ACEScg");
  EXPECT_EQ(interpret_colour("lamp_linear.exr", spec_of({"R", "G", "B"}), s, spaces).colorspace,
            "Linear Rec.709 (sRGB)");
  // colorInteropID, and the exact space a file names among those of one ID.
  OIIO::ImageSpec tagged = spec_of({"R", "G", "B"});
  tagged.attribute("colorInteropID", "lin_rec2020_scene");
  EXPECT_EQ(interpret_colour("a.exr", tagged, s, spaces).colorspace, "Linear Rec.2020");
  OIIO::ImageSpec tex = spec_of({"R", "G", "B"}, OIIO::TypeUInt8);
  tex.attribute("colorInteropID", "srgb_rec709_scene");
  tex.attribute("oiio:ColorSpace", "sRGB - Texture");
  EXPECT_EQ(interpret_colour("t.png", tex, s, aces).colorspace, "sRGB - Texture");
  tex.attribute("colorInteropID", "srgb_rec709_display");
  tex.attribute("oiio:ColorSpace", "sRGB - Display");
  EXPECT_EQ(interpret_colour("t.png", tex, s, aces).colorspace, "sRGB - Display");
  // The command line wins over everything (its name as the planner resolved it).
  s.colorspace = "ACEScg";
  in = interpret_colour("a.exr", tagged, s, spaces);
  EXPECT_EQ(in.colorspace, "ACEScg");
  EXPECT_EQ(in.colorspace_reason, "--colorspace");
}

// Truth: among spaces of one interop ID the file's own name for its space wins, then the
// config's roles, never the first match of the list (a studio config has several sRGB spaces).
TEST(InputInterpretation, TheExactSpaceAmongThoseOfOneInteropId) {
  std::ifstream f(SPECTRALIZE_SOURCE_DIR "/ocio_configs/spectralize.ocio");
  std::stringstream ss;
  ss << f.rdbuf();
  std::string text = ss.str();
  const std::size_t at = text.find("  - !<ColorSpace>\n    name: sRGB - Texture");
  const std::size_t end = text.find("  - !<ColorSpace>", at + 10);
  ASSERT_NE(at, std::string::npos);
  std::string copy = text.substr(at, end - at);
  copy.replace(copy.find("name: sRGB - Texture"), 20, "name: Painted sRGB");
  copy.erase(copy.find("    aliases:"),
             copy.find('\n', copy.find("    aliases:")) + 1 - copy.find("    aliases:"));
  const std::size_t first = text.find("  - !<ColorSpace>", text.find("\ncolorspaces:"));
  text.insert(first, copy);  // listed before every other space
  const test::TempDir t("two_srgb");
  const std::string config = t / "two_srgb.ocio";
  std::ofstream(config) << text;
  const ColourSpaces spaces = ColourSpaces::load(config);
  ASSERT_EQ(spaces.interop_id("Painted sRGB"), "srgb_rec709_scene");
  Settings s;
  OIIO::ImageSpec tex = spec_of({"R", "G", "B"}, OIIO::TypeUInt8);
  tex.attribute("colorInteropID", "srgb_rec709_scene");
  tex.attribute("oiio:ColorSpace", "Painted sRGB");
  EXPECT_EQ(interpret_colour("t.png", tex, s, spaces).colorspace, "Painted sRGB");
  tex.attribute("oiio:ColorSpace", "sRGB - Texture");
  EXPECT_EQ(interpret_colour("t.png", tex, s, spaces).colorspace, "sRGB - Texture");
  tex.erase_attribute("oiio:ColorSpace");
  EXPECT_EQ(interpret_colour("t.png", tex, s, spaces).colorspace, "sRGB - Texture");  // matte_paint
  std::remove(config.c_str());
}

TEST(InputInterpretation, DataByNameOrByColourSpace) {
  const ColourSpaces spaces = ColourSpaces::load();
  Settings s;
  InputInterpretation in =
      interpret_colour("T_Rock_N.png", spec_of({"R", "G", "B"}, OIIO::TypeUInt8), s, spaces);
  EXPECT_NE(in.data_reason.find("'n'"), std::string::npos) << in.data_reason;
  // Albedo or alpha: by the channels.
  EXPECT_FALSE(interpret_colour("T_Rock_A.png", spec_of({"Y"}, OIIO::TypeUInt8), s, spaces)
                   .data_reason.empty());
  EXPECT_TRUE(interpret_colour("T_Rock_A.png", spec_of({"R", "G", "B"}, OIIO::TypeUInt8), s, spaces)
                  .data_reason.empty());
  s.colorspace = "Raw";
  in = interpret_colour("photo.png", spec_of({"R", "G", "B"}, OIIO::TypeUInt8), s, spaces);
  EXPECT_NE(in.data_reason.find("Raw"), std::string::npos);
}

TEST(InputInterpretation, IccDescriptionsOfBothVersions) {
  // Version 2 'desc': ASCII with a count.
  std::vector<unsigned char> v2(128, 0);
  auto be32 = [](std::vector<unsigned char>& v, std::uint32_t x) {
    for (int i = 3; i >= 0; --i) v.push_back(static_cast<unsigned char>(x >> (8 * i)));
  };
  be32(v2, 1);
  v2.insert(v2.end(), {'d', 'e', 's', 'c'});
  be32(v2, 144);
  be32(v2, 29);
  v2.insert(v2.end(), {'d', 'e', 's', 'c', 0, 0, 0, 0});
  be32(v2, 17);
  for (char c : std::string("sRGB IEC61966-2.1")) v2.push_back(static_cast<unsigned char>(c));
  EXPECT_EQ(icc_description(v2.data(), v2.size()), "sRGB IEC61966-2.1");
  // Version 4 'mluc': one UTF-16BE record.
  std::vector<unsigned char> v4(128, 0);
  be32(v4, 1);
  v4.insert(v4.end(), {'d', 'e', 's', 'c'});
  be32(v4, 144);
  be32(v4, 28 + 8);
  v4.insert(v4.end(), {'m', 'l', 'u', 'c', 0, 0, 0, 0});
  be32(v4, 1);
  be32(v4, 12);
  v4.insert(v4.end(), {'e', 'n', 'U', 'S'});
  be32(v4, 8);
  be32(v4, 28);
  for (char c : std::string("P3-X")) v4.insert(v4.end(), {0, static_cast<unsigned char>(c)});
  EXPECT_EQ(icc_description(v4.data(), v4.size()), "P3-X");
  // Truncated or empty profiles never crash.
  EXPECT_EQ(icc_description(v2.data(), 140), "");
  EXPECT_EQ(icc_description(nullptr, 0), "");
}

}  // namespace
}  // namespace spectralize
