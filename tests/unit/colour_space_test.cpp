// Chromaticities matched up to chromatic adaptation, and interop IDs that say whether a space is
// scene- or display-referred (colour/colour_space.h). Oracles: the sRGB ICC profile's published
// D50-adapted colorants, the standards' primaries, and the ACES CG config's own definitions.

#include "colour/colour_space.h"

#include <OpenColorIO/OpenColorIO.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>

#include "file_test_support.h"
#include "spectralize/core/error.h"

namespace spectralize {
namespace {

const std::string kAcesConfig =
    SPECTRALIZE_SOURCE_DIR "/tests/ocio/cg-config-v1.0.0_aces-v1.3_ocio-v2.1.ocio";

TEST(ColourSpace, ChromaticitiesMatchUpToTheAdaptationOfTheirWhite) {
  // Rec.709 primaries adapted to a D50 white, as an ICC sRGB profile's colorants state them
  // (rXYZ 0.4361 0.2225 0.0139, gXYZ 0.3851 0.7169 0.0971, bXYZ 0.1431 0.0606 0.7141) and as
  // Photoshop writes EXR chromaticities.
  const float d50_709[8] = {0.6484f, 0.3309f, 0.3212f, 0.5978f, 0.1559f, 0.0660f, 0.3457f, 0.3585f};
  const float rec709[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
  const auto adapted = adapt_chromaticities_to_d65(d50_709);
  EXPECT_LT(chromaticity_difference(adapted.data(), rec709), 1e-4);
  EXPECT_EQ(interop_id_of_chromaticities(d50_709), "lin_rec709_scene");
  // Rec.709's own primaries with a D50 white are another space (0.02 away once adapted).
  const float unadapted[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3457f, 0.3585f};
  EXPECT_GT(chromaticity_difference(adapt_chromaticities_to_d65(unadapted).data(), rec709), 0.01);
  EXPECT_EQ(interop_id_of_chromaticities(unadapted), "");
  // D65 input is unchanged; AP1 with the ACES white is ACEScg; Rec.2020 is not AP1.
  EXPECT_LT(chromaticity_difference(adapt_chromaticities_to_d65(rec709).data(), rec709), 1e-6);
  const float ap1[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
  EXPECT_EQ(interop_id_of_chromaticities(ap1), "lin_ap1_scene");
  const float rec2020[8] = {0.708f, 0.292f, 0.170f, 0.797f, 0.131f, 0.046f, 0.3127f, 0.3290f};
  EXPECT_EQ(interop_id_of_chromaticities(rec2020), "lin_rec2020_scene");
  // The config sees ACEScg's primaries as the same adaptation gives them.
  const ColourSpaces aces = ColourSpaces::load(kAcesConfig);
  const auto p = aces.primaries_d65("ACEScg");
  ASSERT_TRUE(p);
  EXPECT_LT(chromaticity_difference(p->data(), adapt_chromaticities_to_d65(ap1).data()),
            kChromaticityTolerance);
}

TEST(ColourSpace, InteropIdsSayDisplayReferred) {
  const ColourSpaces aces = ColourSpaces::load(kAcesConfig);
  EXPECT_TRUE(aces.is_display_referred("sRGB - Display"));
  EXPECT_FALSE(aces.is_display_referred("sRGB - Texture"));
  EXPECT_EQ(aces.interop_id("sRGB - Display"), "srgb_rec709_display");
  EXPECT_EQ(aces.interop_id("Rec.1886 Rec.709 - Display"), "g24_rec709_display");
  EXPECT_EQ(aces.interop_id("sRGB - Texture"), "srgb_rec709_scene");
  EXPECT_EQ(aces.interop_id("ACEScg"), "lin_ap1_scene");
  EXPECT_EQ(aces.interop_id("Raw"), "data");
  const ColourSpaces shipped = ColourSpaces::load();
  EXPECT_EQ(shipped.interop_id("sRGB - Texture"), "srgb_rec709_scene");
  EXPECT_EQ(shipped.interop_id("Display P3 - Texture"), "srgb_p3d65_scene");
  EXPECT_EQ(shipped.interop_id("ACEScct"), "");  // a log curve: no ID a measurement can tell
}

// A process keeps the configs it parsed, keyed by location and bytes: a config edited between two
// loads (same path, same size) is read again, and a broken one is never remembered as valid.
TEST(ColourSpace, AnEditedConfigIsReadAgain) {
  const test::TempDir t("cs_cache");
  const std::string path = t / "c.ocio";
  auto write = [&](const std::string& a, const std::string& b) {
    std::ofstream(path) << "ocio_profile_version: 2\nroles:\n  default: " << a
                        << "\n  scene_linear: " << a << "\n  cie_xyz_d65_interchange: " << a
                        << "\ndisplays:\n  d:\n    - !<View> {name: v, colorspace: " << a
                        << "}\ncolorspaces:\n  - !<ColorSpace>\n    name: " << a
                        << "\n  - !<ColorSpace>\n    name: " << b << "\n";
  };
  write("lin_one", "extra_aa");
  const auto first = ColourSpaces::load(path).names();
  EXPECT_NE(std::find(first.begin(), first.end(), "extra_aa"), first.end());
  write("lin_one", "extra_bb");  // same length: only the bytes tell the configs apart
  const auto second = ColourSpaces::load(path).names();
  EXPECT_EQ(std::find(second.begin(), second.end(), "extra_aa"), second.end());
  EXPECT_NE(std::find(second.begin(), second.end(), "extra_bb"), second.end());
  std::ofstream(path) << "ocio_profile_version: 2\nroles: [\n";  // not YAML
  EXPECT_THROW(ColourSpaces::load(path), Error);
  EXPECT_THROW(ColourSpaces::load(path), Error);
  write("lin_one", "extra_aa");  // back to the first bytes: the first config again
  const auto third = ColourSpaces::load(path).names();
  EXPECT_NE(std::find(third.begin(), third.end(), "extra_aa"), third.end());
}

// The file rules decide as OCIO decides, for every kind of rule and path: OCIO's own answer
// (asked directly here, each time) is the oracle of ColourSpaces::file_rule, whose screen keeps
// most paths from OCIO's per-call expression compiles (colour/file_rule_screen.h).
TEST(ColourSpace, FileRulesDecideAsOcioDoesForEveryPath) {
  namespace OCIO = OCIO_NAMESPACE;
  const test::TempDir t("file_rules");
  const std::vector<std::vector<std::array<const char*, 4>>> rule_sets = {
      // name, colour space, pattern, extension (a pattern "~" means: this is a regex rule)
      {{"srgb", "sRGB - Texture", "*_[sS][rR][gG][bB]*", "*"},
       {"linear", "Linear Rec.709 (sRGB)", "*_[lL][iI][nN][eE][aA][rR]*", "*"},
       {"radiance", "Linear Rec.709 (sRGB)", "*", "[hH][dD][rR]"}},
      {{"tex", "sRGB - Texture", "*/textures/*", "png"},
       {"acescg", "ACEScg", "*_acescg_?*", "EXR"},
       {"digits", "Raw", "map\\d[0-9][!a]x", "tif"},
       {"dotted", "ACEScg", "plates/v1.0/*", "*"}},
      {{"plain", "sRGB - Texture", "*", "jpg"}, {"re", "ACEScg", "~", ".*_cg\\.[eE][xX][rR]$"}},
      {},  // the default rule only
  };
  const std::vector<std::string> paths = {"wall_srgb.png",
                                          "wall_SRGB.tif",
                                          "wall.png",
                                          "brick",
                                          "sky.hdr",
                                          "sky.HDR",
                                          "a/b/sky.hdr",
                                          "lib/textures/brick.png",
                                          "lib/textures/brick.PNG",
                                          "lib/texture/brick.png",
                                          "shot_acescg_v2.exr",
                                          "shot_acescg_.exr",
                                          "SHOT_ACESCG_V2.EXR",
                                          "shot_acescg_v2.EXR",
                                          "map7 1yx.tif",
                                          "mapQ-Zx.tif",
                                          "map71yy.tif",
                                          "map71Ax.tif",
                                          "map71ax.tif",
                                          "plates/v1.0/a.dpx",
                                          "plates/v1x0/a.dpx",
                                          "photo.jpg",
                                          "photo.JPG",
                                          "photo.jpeg",
                                          "render_cg.exr",
                                          "render_cg.EXR",
                                          "render_cgexr",
                                          "x_linear_y.exr",
                                          "dir_srgb/plain.exr",
                                          ".hidden",
                                          "trailing.",
                                          "/abs/wall_srgb.png"};
  int asked_ocio = 0;
  for (std::size_t set = 0; set < rule_sets.size(); ++set) {
    const OCIO::ConfigRcPtr config =
        OCIO::Config::CreateFromFile(SPECTRALIZE_SOURCE_DIR "/ocio_configs/spectralize.ocio")
            ->createEditableCopy();
    const OCIO::FileRulesRcPtr rules = OCIO::FileRules::Create();
    std::size_t at = 0;
    for (const auto& [name, space, pattern, extension] : rule_sets[set]) {
      if (std::string(pattern) == "~")
        rules->insertRule(at++, name, space, extension);
      else
        rules->insertRule(at++, name, space, pattern, extension);
    }
    rules->setColorSpace(rules->getNumEntries() - 1, "default");
    config->setFileRules(rules);
    const std::string file = t / ("rules" + std::to_string(set) + ".ocio");
    std::ofstream(file) << *config;
    const OCIO::ConstConfigRcPtr oracle = OCIO::Config::CreateFromFile(file.c_str());
    const ColourSpaces spaces = ColourSpaces::load(file);
    for (const std::string& path : paths) {
      SCOPED_TRACE("rule set " + std::to_string(set) + ", '" + path + "'");
      std::size_t index = 0;
      const std::string space = oracle->getColorSpaceFromFilepath(path.c_str(), index);
      const bool by_default = index + 1 == oracle->getFileRules()->getNumEntries();
      const auto [got_space, got_rule] = spaces.file_rule(path);
      if (by_default) {
        EXPECT_EQ(got_space, "");
        EXPECT_EQ(got_rule, "");
      } else {
        ++asked_ocio;
        EXPECT_EQ(got_space, oracle->getColorSpace(space.c_str())->getName());
        EXPECT_EQ(got_rule, oracle->getFileRules()->getName(index));
      }
    }
  }
  EXPECT_GE(asked_ocio, 15);  // the paths exercise the rules, not only the default
}

}  // namespace
}  // namespace spectralize
