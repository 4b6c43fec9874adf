// Units of the io layer, each against an independent truth: recipes (what they accept and
// refuse), the input interpretation (channels, colour space and its reason), the spectral layout
// analysis of other tools' channel names, ICC descriptions, colour tags, and the node cache's
// file (round trip, and refusal of files that are not what they claim).

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "classify/input_interpretation.h"
#include "colour/colour_space.h"
#include "colour/colour_tags.h"
#include "core/spectral_table.h"
#include "pipeline/rgb_from_spectral.h"
#include "pipeline/table_cache.h"
#include "settings/recipe.h"
#include "spectralize/core/error.h"
#include "text/strings.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

OIIO::ImageSpec spec_of(std::vector<std::string> names, OIIO::TypeDesc type = OIIO::TypeFloat) {
  OIIO::ImageSpec spec(8, 8, static_cast<int>(names.size()), type);
  spec.channelnames = std::move(names);
  spec.alpha_channel = -1;
  return spec;
}

// --- Recipes ---

TEST(Recipe, ParsesEveryKeyByTheSchemaAndResolvesTheSource) {
  const Recipe r = parse_recipe(
      R"({"source": "img/a.png", "mode": "reflectance", "wavelengths": "400:700:10",
          "tile": 64, "filter": 0.5, "format": "float", "model": "smooth"})",
      "/recipes/x.spectral");
  EXPECT_EQ(r.source, "/recipes/img/a.png");
  EXPECT_FALSE(r.to_rgb);
  EXPECT_EQ(r.settings.mode, ModeChoice::reflectance);
  EXPECT_EQ(r.settings.spectral.grid.size(), 31u);
  EXPECT_EQ(r.settings.tile_width, 64);
  EXPECT_EQ(r.settings.tile_height, 64);
  EXPECT_EQ(r.settings.spectral.filter.to_string(), "0.5");
  EXPECT_FALSE(r.settings.half);
  EXPECT_EQ(r.settings.spectral.model, "smooth");
  // Overrides (the plugin's spectral:<key> attributes) win over the file.
  const Recipe o = parse_recipe(R"({"source": "a.png", "mode": "emission"})", "x.spectral",
                                {{"mode", "reflectance"}});
  EXPECT_EQ(o.settings.mode, ModeChoice::reflectance);
}

TEST(Recipe, RefusesWhatTheCliRefusesNamingTheRecipe) {
  for (const char* text :
       {R"([1, 2])", R"({"source": 3})", R"({"mode": "emission"})", R"({"source": "a", "x": 1})",
        R"({"source": "a", "compression": "bogus"})", R"({"source": "a", "tile": 7})",
        R"({"source": "a", "threads": ""})",
        R"({"source": "a", "to": "rgb", "wavelengths": "400:700:10"})",
        R"({"source": "a", "print_format": "json"})", R"({"source": "a", "to": "cmyk"})",
        R"({"source": "a", "mode": true})", "{not json"}) {
    try {
      parse_recipe(text, "bad.spectral");
      ADD_FAILURE() << "accepted " << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("bad.spectral"), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(parse_recipe("{\"source\": \"" + std::string(70000, 'a') + "\"}", "big.spectral"),
               Error);
  EXPECT_TRUE(looks_like_recipe(R"({"source": "a.png"})"));
  EXPECT_FALSE(looks_like_recipe(R"({"source": 1})"));
}

TEST(Recipe, CacheWritesOnlyWhenAsked) {
  EXPECT_FALSE(parse_recipe(R"({"source": "a.png", "cache": "c"})", "x.spectral").cache_write);
  EXPECT_TRUE(
      parse_recipe(R"({"source": "a.png", "cache_write": "yes"})", "x.spectral").cache_write);
  // The plugin's attribute spectral:cache_write arrives as an override.
  EXPECT_TRUE(
      parse_recipe(R"({"source": "a.png"})", "x.spectral", {{"cache_write", "yes"}}).cache_write);
  EXPECT_THROW(parse_recipe(R"({"source": "a.png", "cache_write": "1"})", "x.spectral"), Error);
}

// Recipe chains: a thread's nested opens. Oracle: the documented limit and the file system's
// identity of files (a hard link is the same recipe).
TEST(RecipeChain, RefusesLoopsAndChainsBeyondTheLimitNamingTheFirstRecipe) {
  const fs::path dir = fs::temp_directory_path() / ("recipe_chain_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::vector<std::string> paths;
  for (int i = 0; i <= kMaxRecipeDepth; ++i) {
    paths.push_back((dir / ("r" + std::to_string(i) + ".spectral")).string());
    std::ofstream(paths.back()) << "{}";
  }
  {
    std::vector<std::unique_ptr<RecipeChainLink>> links;
    for (int i = 0; i < kMaxRecipeDepth; ++i) {
      links.push_back(std::make_unique<RecipeChainLink>(paths[i]));
      EXPECT_EQ(links.back()->depth(), i + 1);
    }
    try {
      RecipeChainLink one_more(paths[kMaxRecipeDepth]);
      ADD_FAILURE() << "a chain of " << kMaxRecipeDepth + 1 << " recipes was accepted";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("'" + paths[0] + "': a chain of more than 16 recipes", 0), 0u) << m;
      EXPECT_EQ(RecipeChainLink::chain_failure(), m);
    }
  }
  {
    // A loop through another name of the same file; a fresh chain forgets the old failure.
    const std::string alias = (dir / "alias.spectral").string();
    fs::create_hard_link(paths[0], alias);
    RecipeChainLink a(paths[0]);
    EXPECT_TRUE(RecipeChainLink::chain_failure().empty());
    RecipeChainLink b(paths[1]);
    try {
      RecipeChainLink again(alias);
      ADD_FAILURE() << "a loop was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("loop"), std::string::npos) << e.what();
    }
  }
  // Every link has gone: the chain starts again at depth 1.
  EXPECT_EQ(RecipeChainLink(paths[3]).depth(), 1);
  fs::remove_all(dir);
}

// --- Input interpretation ---

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
  // The command line wins over everything.
  s.colorspace = "acescg";
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
  const std::string config =
      ::testing::TempDir() + "two_srgb_" + std::to_string(::getpid()) + ".ocio";
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

// --- Colour tags ---

TEST(ColourTags, KnownSpacesGetTheirStandardsPrimariesAndIds) {
  const ColourSpaces spaces = ColourSpaces::load();
  EXPECT_EQ(spaces.interop_id("ACEScg"), "lin_ap1_scene");
  EXPECT_EQ(spaces.interop_id("Linear Rec.709 (sRGB)"), "lin_rec709_scene");
  EXPECT_EQ(spaces.interop_id("sRGB - Texture"), "srgb_rec709_scene");
  EXPECT_EQ(spaces.interop_id("Adobe RGB (1998) - Texture"), "g22_adobergb_scene");
  EXPECT_EQ(spaces.interop_id("Raw"), "data");
  EXPECT_EQ(spaces.interop_id("ACEScct"), "");
  EXPECT_TRUE(spaces.is_linear("ACEScg"));
  EXPECT_FALSE(spaces.is_linear("sRGB - Texture"));
  OIIO::ImageSpec spec = spec_of({"R", "G", "B"});
  spec.attribute("colorInteropID", "lin_ap0_scene");
  spec.attribute("ICCProfile:device_class", "mntr");
  tag_colour_space(spec, spaces, "Linear Rec.2020");
  EXPECT_EQ(spec.get_string_attribute("colorInteropID"), "lin_rec2020_scene");
  EXPECT_EQ(spec.find_attribute("ICCProfile:device_class"), nullptr);
  const OIIO::ParamValue* c =
      spec.find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
  ASSERT_TRUE(c);
  EXPECT_NEAR(static_cast<const float*>(c->data())[0], 0.708f, 1e-5);
  // An encoded space has its primaries' chromaticities too (they say nothing of the transfer).
  tag_colour_space(spec, spaces, "sRGB - Texture");
  c = spec.find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
  ASSERT_TRUE(c);
  EXPECT_NEAR(static_cast<const float*>(c->data())[0], 0.64f, 1e-5);
  // Transfer functions an ICC curve states, measured through OCIO.
  EXPECT_EQ(spaces.transfer("sRGB - Texture")->kind, IccTransfer::srgb);
  EXPECT_EQ(spaces.transfer("ACEScg")->kind, IccTransfer::linear);
  EXPECT_EQ(spaces.transfer("Gamma 2.2 Rec.709 - Texture")->exponent, 2.2);
  EXPECT_EQ(spaces.transfer("Adobe RGB (1998) - Texture")->exponent, 563.0 / 256);
  EXPECT_FALSE(spaces.transfer("ACEScct"));
  EXPECT_FALSE(spaces.transfer("Raw"));
}

// --- Spectral layouts of other tools ---

TEST(SpectralLayout, ChannelsSortedByWavelengthAndStrangeOnesNamed) {
  const auto info = analyse_spectral_layout(
      spec_of({"A", "S0.1000,0nm", "S0.950,0nm", "S0.0,55um", "S0.5x0nm", "R"}), "f.exr");
  EXPECT_EQ(info.wavelengths, (std::vector<double>{550, 950, 1000}));
  EXPECT_EQ(info.band_channels, (std::vector<int>{3, 2, 1}));
  EXPECT_EQ(info.alpha, 0);
  EXPECT_EQ(info.unparsed, std::vector<std::string>{"S0.5x0nm"});
  EXPECT_THROW(
      analyse_spectral_layout(spec_of({"T.500,0nm", "T.500,0nm.510,0nm", "T.510,0nm"}), "bi.exr"),
      Error);
  EXPECT_THROW(analyse_spectral_layout(spec_of({"S0.900,0nm", "S0.950,0nm"}), "ir.exr"), Error);
  EXPECT_THROW(analyse_spectral_layout(spec_of({"S0.500,0nm", "T.600,0nm"}), "mixed.exr"), Error);
}

// --- The node cache's file ---

TEST(TableCache, RoundTripAndRefusals) {
  const fs::path dir = fs::path(::testing::TempDir()) / ("cache_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  SpectralizerSettings ss;
  const Spectralizer sp(ss);
  SpectralTable made(sp);
  const Xyz c{0.3, 0.35, 0.4};
  std::vector<float> out(sp.settings().grid.size());
  PixelResult res;
  made.spectra(&c, 1, out.data(), &res);
  const std::string key = "test key";
  const std::string file = table_cache_file(dir.string(), key);
  // Stable name: FNV-1a of the key (documented), whatever the standard library.
  EXPECT_EQ(fs::path(file).filename(), "spectralize-table-ee323c675103fedc.bin");
  EXPECT_EQ(save_table_cache(made, file, key), "");
  SpectralTable loaded(sp);
  EXPECT_EQ(load_table_cache(loaded, file, key), "");
  EXPECT_EQ(loaded.stats().nodes_loaded, 4u);
  SpectralTable other(sp);
  EXPECT_NE(load_table_cache(other, file, "another key").find("other settings"), std::string::npos);
  // Truncated by one byte: the checksum catches it.
  fs::resize_file(file, fs::file_size(file) - 1);
  EXPECT_NE(load_table_cache(other, file, key), "");
  // A directory or a FIFO where the file should be: refused without blocking.
  fs::remove(file);
  fs::create_directory(file);
  EXPECT_EQ(load_table_cache(other, file, key), "is a directory");
  EXPECT_NE(save_table_cache(made, file, key), "");
  fs::remove(file);
  EXPECT_EQ(load_table_cache(other, file, key), "");  // absent: nothing to load, no complaint
  fs::remove_all(dir);
}

// --- Messages ---

TEST(Messages, LongValuesAreClipped) {
  const std::string big(100000, 'x');
  EXPECT_LT(clip(big).size(), 120u);
  EXPECT_NE(clip(big).find("100000 bytes"), std::string::npos);
  EXPECT_EQ(clip("short"), "short");
  EXPECT_LT(quote(big).size(), 120u);
  try {
    ColourSpaces::load().resolve(big);
    ADD_FAILURE();
  } catch (const Error& e) {
    EXPECT_LT(std::string(e.what()).size(), 5000u);
  }
}

}  // namespace
}  // namespace spectralize
