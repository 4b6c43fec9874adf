// The name table (settings/map_kind.h) against a hand-written table of what a TD would say each
// file holds: the conventions of Unreal, Unity, Substance, Megascans, USD, MaterialX and Arnold,
// and names that only look like them (normandy_beach, armchair, eye_r, wood_light). The guide's
// table is checked against the code's, word for word.

#include "settings/map_kind.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "spectralize/core/error.h"

namespace spectralize {
namespace {

struct Case {
  const char* path;
  MapKind kind;
  bool needs_channels = false;  // the map's channels decide (grey: data)
};

constexpr MapKind D = MapKind::data, R = MapKind::reflectance, E = MapKind::emission,
                  N = MapKind::none;

// What each file holds, decided by hand.
const Case kNames[] = {
    // Unreal: T_<Name>_<Suffix>.
    {"T_Rock_N.png", D},
    {"T_Rock_R.png", D},
    {"T_Rock_M.png", D},
    {"T_Rock_H.png", D},
    {"T_Rock_O.png", D},
    {"T_Rock_E.png", E},
    {"T_Rock_D.png", R},
    {"T_Rock_C.png", R},
    {"T_Rock_BC.png", R},
    {"T_Brick_ORM.png", D},
    {"T_Rock_ARM.png", D},
    {"T_Rock_ARME.png", D},
    {"T_Rock_RMA.tga", D},
    {"TX_Metal_N_01.png", D},
    {"T_Rock_A.png", N, true},
    {"T_Rock_S.png", N, true},
    {"T_Rock01_N.png", D},
    {"T_Wall_BaseColor.png", R},
    {"T_Wall_Normal_DX.png", D},
    // Unity HDRP / URP.
    {"Rock_MaskMap.png", D},
    {"Rock_BaseMap.png", R},
    {"Rock_DetailMap.png", D},
    {"Rock_EmissiveColorMap.png", E},
    {"Rock_MetallicGlossMap.png", D},
    {"Rock_OcclusionMap.png", D},
    {"Rock_NormalMap.png", D},
    {"Rock_ParallaxMap.png", D},
    // Substance 3D Painter.
    {"crate_Crate_BaseColor.png", R},
    {"crate_Crate_Normal_OpenGL.png", D},
    {"crate_Crate_Normal_DirectX.png", D},
    {"crate_Crate_Roughness.png", D},
    {"crate_Crate_Metallic.png", D},
    {"crate_Crate_Height.png", D},
    {"crate_Crate_Mixed_AO.png", D},
    {"crate_Crate_Emissive.png", E},
    {"crate_Crate_Opacity.png", D},
    {"crate_Crate_OcclusionRoughnessMetallic.png", D},
    {"crate_Crate_Specular.png", N, true},
    {"crate_Crate_Glossiness.png", D},
    // Quixel Megascans.
    {"rock_cliff_vdyxeb2_4K_Albedo.jpg", R},
    {"rock_cliff_vdyxeb2_4K_Normal_LOD0.jpg", D},
    {"rock_cliff_vdyxeb2_4K_Roughness.jpg", D},
    {"rock_cliff_vdyxeb2_4K_Displacement.exr", D},
    {"rock_cliff_vdyxeb2_4K_AO.jpg", D},
    {"rock_cliff_vdyxeb2_4K_Cavity.jpg", D},
    {"rock_cliff_vdyxeb2_4K_Bump.jpg", D},
    {"leaf_2K_Translucency.jpg", N, true},
    {"rock_cliff_2K_Gloss.jpg", D},
    // USD Preview Surface, MaterialX (Karma), Arnold.
    {"chair_diffuseColor.png", R},
    {"chair_emissiveColor.exr", E},
    {"chair_specularColor.png", R},
    {"chair_clearcoatRoughness.png", D},
    {"chair_opacityThreshold.png", D},
    {"chair_ior.exr", D},
    {"chair_base_color.png", R},
    {"chair_emission_color.exr", E},
    {"chair_specular_roughness.png", D},
    {"chair_coat_color.png", R},
    {"chair_subsurface_color.png", R},
    {"chair_transmission_color.png", R},
    {"chair_thin_film_thickness.exr", D},
    {"chair_metalness.png", D},
    {"chair_normalCamera.png", D},
    {"chair_baseColor.1001.png", R},
    // Abbreviations.
    {"rock_nrm.png", D},
    {"rock_nrml.png", D},
    {"rock_disp.exr", D},
    {"rock_displace.exr", D},
    {"rock_rgh.png", D},
    {"rock_mtl.png", D},
    {"rock_col.jpg", R},
    {"rock_alb.png", R},
    {"rock_diff_v002.png", R},
    {"rock_spec.png", N, true},
    {"rock_hgt.exr", D},
    {"rock_occ.png", D},
    // Environments and lights.
    {"sunset_hdri.exr", E},
    {"studio_small_08_4k.hdr", N},  // only the folder or the image can tell
    {"forest_env.exr", E},
    {"city_latlong.exr", E},
    {"beach_panorama.jpg", E},
    {"blue_sky.exr", E},
    {"lamp_emission.exr", E},
    {"screen_glow.png", E},
    {"level_lightmap.exr", E},
    // The map's kind is the last word: a subject word first does not decide.
    {"metal_plate_basecolor.png", R},
    {"rough_stone_albedo.png", R},
    {"mask_painted_diffuse.png", R},
    {"albedo_roughness.png", D},
    {"sky_hdri_mask.png", D},
    {"normal_variation_albedo.png", R},
    // Names that only look like the conventions.
    {"normandy_beach.hdr", N},
    {"armchair_basecolor.png", R},
    {"norm_photo.jpg", N},
    {"metal_plate.png", N},
    {"rough_concrete.png", N},
    {"robot_arm.png", N},
    {"eye_r.png", N},
    {"eye_L.png", N},
    {"plan_a.png", N},
    {"photo_2023_b.jpg", N},
    {"Rock_N.png", N},  // not engine-style: no T_ prefix
    {"T_N.png", N},     // a prefix and a letter, no subject
    {"wood_light.png", N},
    {"light_oak_floor.png", N},
    {"sky_blue_paint.png", N},
    {"lava_flow.png", N},
    {"graffiti.exr", N},
    {"macbeth_chart.exr", N},
    {"environmental_poster.png", N},
    {"hdr_camera_rig.png", N},
    {"sunset_hdr.exr", E},
    {"carnival_mask.png", D},  // a texture library's *_mask is a mask
    // Folders decide when the name does not: the parent, then the grandparent.
    {"lib/hdri/studio_small_08_4k.hdr", E},
    {"lib/env/forest.exr", E},
    {"lib/lights/key.exr", E},
    {"lib/studio_lights/key.exr", E},
    {"lib/light_tests/key.exr", N},
    {"lib/normals/rock.png", D},
    {"lib/normal_maps/rock.png", D},
    {"lib/masks/rock.png", D},
    {"lib/hdri/sunset/sunset_8k.exr", E},
    {"lib/textures/wood.png", N},
    {"lib/hdri/wood_basecolor.png", R},     // the name comes first
    {"lib/a/b/hdri/c/d/sky_photo.jpg", N},  // too far up
};

TEST(MapKind, EveryNameAsATdWouldDecideIt) {
  const auto words = name_words_in_force("", "");
  int failures = 0;
  for (const Case& c : kNames) {
    const NameVerdict v = map_kind_by_name(c.path, words);
    const bool ok = v.kind == c.kind && v.needs_channels == c.needs_channels;
    EXPECT_TRUE(ok) << c.path << ": " << to_string(v.kind)
                    << (v.needs_channels ? " (by channels)" : "") << " (" << v.reason
                    << "), expected " << to_string(c.kind);
    failures += !ok;
    // A decision always says why.
    if (v.kind != MapKind::none || v.needs_channels) {
      EXPECT_FALSE(v.reason.empty()) << c.path;
    }
  }
  EXPECT_EQ(failures, 0);
  EXPECT_GE(std::size(kNames), 120u);
}

TEST(MapKind, ReasonsNameTheWordAndWhereItStands) {
  const auto words = name_words_in_force("", "");
  NameVerdict v = map_kind_by_name("T_Rock_M.png", words);
  EXPECT_EQ(v.word, "m");
  EXPECT_NE(v.reason.find("engine-style suffix"), std::string::npos) << v.reason;
  EXPECT_NE(v.reason.find("metallic or mask"), std::string::npos) << v.reason;
  EXPECT_TRUE(v.warnings.empty());  // both readings are data: nothing to warn about
  v = map_kind_by_name("lib/lights/key.exr", words);
  EXPECT_NE(v.reason.find("folder word 'lights'"), std::string::npos) << v.reason;
}

TEST(MapKind, AmbiguousNamesAreDecidedAndWarned) {
  const auto words = name_words_in_force("", "");
  // "light" alone never makes a texture a light, and says so.
  NameVerdict v = map_kind_by_name("wood_light.png", words);
  EXPECT_EQ(v.kind, MapKind::none);
  ASSERT_EQ(v.warnings.size(), 1u);
  EXPECT_NE(v.warnings[0].find("'light'"), std::string::npos) << v.warnings[0];
  // Lower-case arm at the end: the word, warned; ARM in capitals: the packed map.
  v = map_kind_by_name("robot_arm.png", words);
  EXPECT_EQ(v.kind, MapKind::none);
  EXPECT_EQ(v.warnings.size(), 1u);
  EXPECT_EQ(map_kind_by_name("rock_ARM.png", words).kind, MapKind::data);
  // A letter outside an engine-style name is just a letter: no warning.
  EXPECT_TRUE(map_kind_by_name("plan_a.png", words).warnings.empty());
  // Albedo or alpha, specular colour or level: the channels decide, with a warning.
  for (const char* name : {"T_Rock_A.png", "rock_Specular.png", "leaf_Translucency.png"}) {
    for (const bool grey : {true, false}) {
      v = map_kind_by_name(name, words);
      ASSERT_TRUE(v.needs_channels) << name;
      resolve_by_channels(v, grey);
      EXPECT_FALSE(v.needs_channels);
      EXPECT_EQ(v.kind, grey ? MapKind::data : MapKind::reflectance) << name;
      EXPECT_EQ(v.warnings.size(), 1u) << name;
    }
  }
}

TEST(MapKind, TokensSplitAtSeparatorsCaseChangesAndDigits) {
  auto texts = [](const char* name) {
    std::string out;
    for (const NameToken& t : name_tokens(name)) out += (out.empty() ? "" : "|") + t.text;
    return out;
  };
  EXPECT_EQ(texts("T_BaseColor"), "t|base|color");
  EXPECT_EQ(texts("rock-cliff.nrm"), "rock|cliff|nrm");
  EXPECT_EQ(texts("Rock_ORMMap"), "rock|orm|map");
  EXPECT_EQ(texts("Rock01_4K_Normal_LOD0"), "rock|01|4k|normal|lod|0");
  EXPECT_EQ(texts("diffuseColor"), "diffuse|color");
  EXPECT_EQ(texts("RGBMask"), "rgb|mask");
  EXPECT_EQ(texts("wall 16bit (copy)"), "wall|16bit|copy");
  const auto t = name_tokens("rock_ARM_arm");
  ASSERT_EQ(t.size(), 3u);
  EXPECT_TRUE(t[1].capitals);
  EXPECT_FALSE(t[2].capitals);
}

TEST(MapKind, EditsExtendReplaceOrRemoveWords) {
  // Extend: a studio's own words count anywhere; a word has one meaning, the user's.
  auto words = name_words_in_force("+msk,+velvet", "+glow2:emission,+paint");
  EXPECT_EQ(map_kind_by_name("rock_msk.png", words).kind, MapKind::data);
  EXPECT_EQ(map_kind_by_name("velvet_chair.png", words).kind, MapKind::data);
  EXPECT_EQ(map_kind_by_name("screen_glow2.exr", words).kind, MapKind::emission);
  EXPECT_EQ(map_kind_by_name("wall_paint.png", words).kind, MapKind::reflectance);
  EXPECT_EQ(map_kind_by_name("rock_normal.png", words).kind, MapKind::data);  // table kept
  // Remove.
  words = name_words_in_force("-mask", "-sky");
  EXPECT_EQ(map_kind_by_name("carnival_mask.png", words).kind, MapKind::none);
  EXPECT_EQ(map_kind_by_name("blue_sky.exr", words).kind, MapKind::none);
  // Replace: only the listed words of that kind remain.
  words = name_words_in_force("nrm", "");
  EXPECT_EQ(map_kind_by_name("rock_nrm.png", words).kind, MapKind::data);
  EXPECT_EQ(map_kind_by_name("rock_roughness.png", words).kind, MapKind::none);
  EXPECT_EQ(map_kind_by_name("rock_basecolor.png", words).kind, MapKind::reflectance);
  // A letter the user names counts as any name's last word, not only in T_ names.
  EXPECT_EQ(map_kind_by_name("rock_n.png", name_words_in_force("", "")).kind, MapKind::none);
  words = name_words_in_force("+n", "");
  EXPECT_EQ(map_kind_by_name("rock_n.png", words).kind, MapKind::data);
  EXPECT_EQ(map_kind_by_name("n_rock.png", words).kind, MapKind::none);
  // Move a word between kinds: light as an emission word anywhere.
  words = name_words_in_force("", "+light:emission");
  EXPECT_EQ(map_kind_by_name("lamp_light.exr", words).kind, MapKind::emission);
  // Canonical text and refusals.
  EXPECT_EQ(check_name_edit("+MSK,-Metal", false), "+msk,-metal");
  EXPECT_EQ(check_name_edit("glow:emission,paint:reflectance", true), "glow:emission,paint");
  for (const char* bad : {"+msk,nrm", "nor mal", "+", "-nosuchword", "a,,b"}) {
    EXPECT_THROW(check_name_edit(bad, false), Error) << bad;
  }
  for (const char* bad : {"+sky:light", "-light:emission", "glow,+x", "-normal"}) {
    EXPECT_THROW(check_name_edit(bad, true), Error) << bad;
  }
}

// The guide lists the table (docs/guide/pipeline.md): every word with its kind and place, as
// the code has it.
TEST(MapKind, TheReadmeTableIsTheCodesTable) {
  std::ifstream f(SPECTRALIZE_SOURCE_DIR "/docs/guide/pipeline.md");
  std::stringstream ss;
  ss << f.rdbuf();
  const std::string readme = ss.str();
  const std::size_t at = readme.find("<!-- name table -->");
  const std::size_t end = readme.find("<!-- end of name table -->");
  ASSERT_NE(at, std::string::npos);
  ASSERT_NE(end, std::string::npos);
  const std::string table = readme.substr(at, end - at);
  // Rows: | kind | place | words |, words as `word` (meaning).
  std::map<std::string, std::string> listed;
  const std::regex row(R"(\|\s*([a-z ]+?)\s*\|\s*([a-z ]+?)\s*\|([^\n]*)\|)");
  for (auto it = std::sregex_iterator(table.begin(), table.end(), row);
       it != std::sregex_iterator(); ++it) {
    const std::string kind = (*it)[1], place = (*it)[2], cell = (*it)[3];
    const std::regex word("`([a-z0-9]+)`");
    for (auto w = std::sregex_iterator(cell.begin(), cell.end(), word); w != std::sregex_iterator();
         ++w)
      listed[(*w)[1]] = kind + "/" + place;
  }
  auto kind_name = [](WordKind k) {
    return k == WordKind::data          ? "data"
           : k == WordKind::reflectance ? "surface colour"
           : k == WordKind::emission    ? "light"
                                        : "data if grey";
  };
  auto place_name = [](WordPlace p) {
    return p == WordPlace::anywhere  ? "anywhere"
           : p == WordPlace::last    ? "last word"
           : p == WordPlace::engine  ? "engine suffix"
           : p == WordPlace::acronym ? "engine suffix or capitals"
                                     : "folder";
  };
  std::size_t n = 0;
  for (const NameWord& w : builtin_name_words()) {
    ++n;
    ASSERT_TRUE(listed.count(w.word)) << "the guide lacks '" << w.word << "'";
    EXPECT_EQ(listed[w.word], std::string(kind_name(w.kind)) + "/" + place_name(w.place)) << w.word;
  }
  EXPECT_EQ(listed.size(), n) << "the guide lists words the code does not have";
}

}  // namespace
}  // namespace spectralize
