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
#include "test_support.h"

namespace spectralize {
namespace {

const std::string kAcesConfig =
    SPECTRALIZE_SOURCE_DIR "/tests/ocio/cg-config-v1.0.0_aces-v1.3_ocio-v2.1.ocio";

TEST(ColourSpace, TheConfigSeesAcescgAsTheBradfordAdaptationGivesIt) {
  const float ap1[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
  const ColourSpaces aces = ColourSpaces::load(kAcesConfig);
  const auto p = aces.primaries_d65("ACEScg");
  ASSERT_TRUE(p);
  EXPECT_LT(chromaticity_difference(p->data(), adapt_chromaticities_to_d65(ap1).data()),
            kChromaticityTolerance);
}

TEST(ColourSpace, ANameIsResolvedOnceIntoWhatIsKnownOfTheSpace) {
  const ColourSpaces aces = ColourSpaces::load(kAcesConfig);
  // An alias, in another case: the name as given stays for messages, the facts are the space's.
  const NamedSpace named = aces.named("aces - acescg");
  ASSERT_TRUE(named);
  EXPECT_EQ(named.given, "aces - acescg");
  EXPECT_EQ(named.name(), "ACEScg");
  EXPECT_EQ(named.facts, &aces.facts("ACEScg"));  // one record per space and config
  EXPECT_FALSE(aces.named(""));
  try {
    aces.named("no such space");
    ADD_FAILURE() << "an unknown name was resolved";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("ACEScg"), std::string::npos) << "lists the valid names";
  }
}

TEST(ColourSpace, FactsMeasureTheMatrixTheWhiteAndOneMeaningOfLinear) {
  const ColourSpaces aces = ColourSpaces::load(kAcesConfig);
  // ACEScg: the AP1 matrix Bradford-adapted to D65 (the tests' own, from the primaries), its
  // white D65.
  const ColourSpaceFacts& cg = aces.facts("ACEScg");
  ASSERT_TRUE(cg.rgb_to_xyz.has_value());
  const test::Mat3 want = test::acescg_to_xyz_d65();
  for (int i = 0; i < 9; ++i) EXPECT_NEAR((*cg.rgb_to_xyz)[i], want[i / 3][i % 3], 1e-5) << i;
  EXPECT_NEAR(cg.white.X, 0.95047, 1e-4);
  EXPECT_NEAR(cg.white.Y, 1.0, 1e-5);
  EXPECT_TRUE(cg.linear);
  ASSERT_TRUE(cg.transfer.has_value());
  EXPECT_EQ(cg.transfer->kind, IccTransfer::linear);
  // A curve: not linear, and its transfer says which; the ID and the transfer agree.
  const ColourSpaceFacts& tx = aces.facts("Utility - sRGB - Texture");
  EXPECT_FALSE(tx.linear);
  ASSERT_TRUE(tx.transfer.has_value());
  EXPECT_EQ(tx.transfer->kind, IccTransfer::srgb);
  EXPECT_EQ(tx.interop_id, "srgb_rec709_scene");
  // Every space of the config: linear exactly when its transfer is the linear one.
  for (const std::string& name : aces.names()) {
    SCOPED_TRACE(name);
    const ColourSpaceFacts& f = aces.facts(name);
    if (f.data) continue;
    EXPECT_EQ(f.linear, f.transfer && f.transfer->kind == IccTransfer::linear);
  }
}

// A config's spaces whose conversion to CIE XYZ carries no colour: a zero matrix (all black),
// a NaN in the matrix, a rank-1 matrix (every colour grey); and two that stay usable: a tiny
// scale, a curve that saturates above 0.3.
std::string broken_spaces_config() {
  auto space = [](const std::string& name, const std::string& matrix) {
    return "  - !<ColorSpace>\n    name: " + name +
           "\n    isdata: false\n    to_scene_reference: !<MatrixTransform> {matrix: [" + matrix +
           ", 0, 0, 0, 1]}\n";
  };
  return "ocio_profile_version: 2\nroles:\n  scene_linear: XYZ\n  default: XYZ\n"
         "  cie_xyz_d65_interchange: XYZ\n  data: Raw\n"
         "displays:\n  sRGB:\n    - !<View> {name: Raw, colorspace: Raw}\ncolorspaces:\n"
         "  - !<ColorSpace>\n    name: XYZ\n    isdata: false\n"
         "  - !<ColorSpace>\n    name: Raw\n    isdata: true\n" +
         space("Zero", "0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0") +
         space("NaNs", ".nan, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0") +
         space("Grey", "0.3, 0.3, 0.3, 0, 0.3, 0.3, 0.3, 0, 0.3, 0.3, 0.3, 0") +
         space("Dim", "1e-5, 0, 0, 0, 0, 1e-5, 0, 0, 0, 0, 1e-5, 0") +
         // Saturating above 0.3, as ADX16's curve does above 0.5: usable below.
         "  - !<ColorSpace>\n    name: Clamped\n    isdata: false\n    to_scene_reference: "
         "!<RangeTransform> {min_in_value: 0, max_in_value: 0.3, min_out_value: 0, "
         "max_out_value: 0.3}\n";
}

// Every way to a conversion refuses a space no colour converts through, naming it and why:
// named() (what the planner resolves), to_xyz() and from_xyz() (every converter); data and a
// dim but invertible space stay usable.
TEST(ColourSpace, ASpaceNoColourConvertsThroughIsRefusedBeforeAnyConversion) {
  test::TempDir t("colour_space");
  std::ofstream(t / "broken.ocio") << broken_spaces_config();
  const ColourSpaces spaces = ColourSpaces::load(t / "broken.ocio");
  const std::pair<std::string, std::string> broken[] = {
      {"Zero", "makes every colour black"}, {"NaNs", "NaN or infinity"}, {"Grey", "singular"}};
  for (const auto& [name, why] : broken) {
    SCOPED_TRACE(name);
    EXPECT_NE(spaces.facts(name).unusable.find(why), std::string::npos)
        << spaces.facts(name).unusable;
    for (const std::string& msg : {test::error_message([&] { spaces.named(name); }),
                                   test::error_message([&] { spaces.to_xyz(name); }),
                                   test::error_message([&] { spaces.from_xyz(name); })}) {
      EXPECT_NE(msg.find("colour space '" + name + "'"), std::string::npos) << msg;
      EXPECT_NE(msg.find("cannot be used: "), std::string::npos) << msg;
      EXPECT_NE(msg.find(why), std::string::npos) << msg;
    }
  }
  for (const char* fine : {"XYZ", "Raw", "Dim", "Clamped"}) {
    SCOPED_TRACE(fine);
    EXPECT_EQ(spaces.facts(fine).unusable, "");
    EXPECT_NO_THROW(spaces.named(fine));
    EXPECT_NO_THROW(spaces.to_xyz(fine));
  }
}

// The configs users point spectralize at have no such space: the shipped one, the ACES CG
// config, and OCIO's built-in configs where this OCIO has them.
TEST(ColourSpace, EverySpaceOfRealConfigsIsUsable) {
  std::vector<std::string> configs = {"", kAcesConfig};
  if (OCIO_VERSION_HEX >= 0x02020000)
    configs.insert(configs.end(), {"ocio://cg-config-latest", "ocio://studio-config-latest"});
  for (const std::string& config : configs) {
    const ColourSpaces spaces = ColourSpaces::load(config);
    for (const std::string& name : spaces.names()) {
      SCOPED_TRACE(config + ": " + name);
      try {
        EXPECT_EQ(spaces.facts(name).unusable, "");
      } catch (const Error& e) {  // a space OCIO cannot convert at all says so itself
        ADD_FAILURE() << e.what();
      }
    }
  }
}

// A Color Interop Forum ID names a space wherever a name does (as OpenUSD and OIIO 3 name
// spaces): the config's space with that ID, stated or measured; an ID no space has is unknown.
// Oracle: the spaces' published primaries and curves (the shipped and ACES configs' names).
TEST(ColourSpace, AnInteropIdNamesTheSpaceThatHasIt) {
  const ColourSpaces shipped = ColourSpaces::load();
  const ColourSpaces aces = ColourSpaces::load(kAcesConfig);
  const std::pair<std::string, std::string> cases[] = {
      {"lin_ap1_scene", "ACEScg"},
      {"lin_ap0_scene", "ACES2065-1"},
      {"lin_rec2020_scene", "Linear Rec.2020"},
      {"srgb_rec709_scene", "sRGB - Texture"},
      {"lin_rec709_scene", "Linear Rec.709 (sRGB)"}};
  for (const auto& [id, name] : cases) {
    EXPECT_EQ(shipped.resolve(id), name) << id;
    EXPECT_EQ(aces.resolve(id), name) << id;
    EXPECT_EQ(shipped.named(id).name(), name) << id;
  }
  EXPECT_EQ(aces.resolve("srgb_rec709_display"), "sRGB - Display");
  const std::string msg = test::error_message([&] { shipped.resolve("pq_rec2020_display"); });
  EXPECT_NE(msg.find("no space of it has that interop ID"), std::string::npos) << msg;
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
