// A studio's texture library, made by the test (nested asset folders; 8/16-bit PNG, JPEG,
// TIFF, half and float EXR, Radiance HDR, a maketx .tx; engine, Substance and abbreviated map
// names; HDRIs and lights by folder; float textures with no word), ingested under the ACES CG
// config and under the shipped one. Truth: every file is decided as a TD would decide it —
// colour space by the file's metadata and format before a config role, data maps never
// spectralized, light or surface by words, folders and the image's values, same-stem siblings
// kept. The oracles are the file system, the manifest as JSON, the outputs read back with OIIO
// and integrated by the test's own CIE tables.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "exr_support.h"

namespace fs = std::filesystem;
using e2e::run;
using Json = nlohmann::json;

namespace {

const std::string kAcesConfig =
    SPECTRALIZE_SOURCE_DIR "/tests/ocio/cg-config-v1.0.0_aces-v1.3_ocio-v2.1.ocio";

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_studio") {}
};

using PixelFn = std::function<float(int x, int y, int c)>;

// Writes an image with OIIO: `nch` channels of `type`, values from `px` (0..1 for integers).
void write_image(const std::string& path, int w, int h, int nch, OIIO::TypeDesc type,
                 const PixelFn& px, const std::function<void(OIIO::ImageSpec&)>& edit = nullptr) {
  fs::create_directories(fs::path(path).parent_path());
  OIIO::ImageSpec spec(w, h, nch, type);
  if (edit) edit(spec);
  std::vector<float> data;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < nch; ++c) data.push_back(px(x, y, c));
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << path;
  ASSERT_TRUE(out->open(path, spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeFloat, data.data())) << out->geterror();
  out->close();
}

// A textured colour within 0..1, different per file (seed).
PixelFn texture(int seed) {
  return [seed](int x, int y, int c) {
    return 0.05f + 0.8f * static_cast<float>((x * 7 + y * 3 + c * 5 + seed) % 11) / 10.0f;
  };
}

// A sky: bright at the top (peak 8, far above white), dim below.
float sky(int x, int y, int c) {
  return (y < 2 ? 8.0f : 0.2f) * (c == 0 ? 0.8f : c == 1 ? 0.3f : 0.1f) + 0.01f * x;
}

// Photoshop's chromaticities: Rec.709 primaries Bradford-adapted to a D50 white.
const float kPhotoshopD50[8] = {0.6484f, 0.3309f, 0.3212f, 0.5978f,
                                0.1559f, 0.0660f, 0.3457f, 0.3585f};

void make_library(const Scratch& s) {
  const OIIO::TypeDesc u8 = OIIO::TypeUInt8, u16 = OIIO::TypeUInt16;
  const OIIO::TypeDesc half = OIIO::TypeHalf, flt = OIIO::TypeFloat;
  const std::string a = s / "lib/assets/";
  // Data maps by engine, Substance and abbreviated names, by folder; ambiguous words.
  write_image(a + "rock/T_Rock_N.png", 12, 8, 3, u8, texture(1));
  write_image(a + "rock/T_Rock_D.png", 12, 8, 3, u8, texture(2));
  write_image(a + "rock/T_Rock_ARM.png", 12, 8, 3, u8, texture(3));
  write_image(a + "brick/T_Brick_ORM.png", 12, 8, 3, u8, texture(4));
  write_image(a + "rock/rock_nrml.jpg", 12, 8, 3, u8, texture(5));
  write_image(a + "rock/rock_displace.tif", 12, 8, 1, u16, texture(6));
  write_image(a + "wood/wood_light.png", 12, 8, 3, u8, texture(7));
  write_image(a + "wood/Wood_BaseColor_4K.jpg", 12, 8, 3, u8, texture(8));
  write_image(a + "metal/metal_plate_basecolor.tif", 12, 8, 3, u8, texture(9));
  write_image(a + "metal/MetalPlate_Roughness.tif", 12, 8, 1, u16, texture(10));
  write_image(a + "metal/metal_plate_Specular.png", 12, 8, 1, u8, texture(11));  // grey
  write_image(a + "metal/metal_plate_spec.png", 12, 8, 3, u8, texture(12));      // RGB
  write_image(a + "crate/normals/crate.png", 12, 8, 3, u8, texture(13));
  write_image(a + "crate/crate_Emissive.exr", 12, 8, 3, half, texture(14));
  // Lights and surfaces in float: by folder, by value; colour spaces by format and metadata.
  write_image(s / "lib/hdri/studio.hdr", 32, 16, 3, flt, sky);
  write_image(s / "lib/env/city.exr", 32, 16, 3, half, sky, [](OIIO::ImageSpec& spec) {
    spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), kPhotoshopD50);
  });
  write_image(s / "lib/textures/graffiti.exr", 12, 8, 3, half, texture(15));
  write_image(s / "lib/textures/macbeth_chart.exr", 12, 8, 3, flt, texture(16));
  write_image(s / "lib/lights/panel.exr", 12, 8, 3, half, texture(17));
  write_image(s / "lib/shots/plate_bright.exr", 12, 8, 3, half,
              [](int x, int y, int c) { return x == 3 && y == 5 ? 4.0f : 0.1f * (c + 1); });
  write_image(s / "lib/tagged/wall.exr", 12, 8, 3, half, texture(18),
              [](OIIO::ImageSpec& spec) { spec.attribute("colorInteropID", "lin_rec2020_scene"); });
  // Same-stem siblings: a.tx made from a.tif by maketx (its header says so), a.png another image.
  write_image(s / "lib/tex/a.tif", 16, 16, 3, u8, texture(19));
  write_image(s / "lib/tex/a.png", 16, 16, 3, u8, texture(20));
  ASSERT_EQ(
      e2e::run_measured("cd " + (s / "lib/tex") + " && maketx a.tif -o a.tx >/dev/null").exit_code,
      0);
}

std::vector<Json> read_manifest(const std::string& path) {
  std::vector<Json> out;
  std::ifstream f(path);
  for (std::string line; std::getline(f, line);) out.push_back(Json::parse(line));
  return out;
}

Json record(const std::vector<Json>& m, const std::string& input_suffix) {
  for (const Json& r : m) {
    if (!r.contains("input")) continue;
    const std::string in = r["input"].get<std::string>();
    if (in.size() >= input_suffix.size() &&
        in.compare(in.size() - input_suffix.size(), input_suffix.size(), input_suffix) == 0)
      return r;
  }
  ADD_FAILURE() << "no record of " << input_suffix;
  return Json::object();
}

std::string text(const Json& r, const char* key) {
  return r.contains(key) && r[key].is_string() ? r[key].get<std::string>() : "";
}

bool has_warning(const Json& r, const std::string& part) {
  if (!r.contains("warnings")) return false;
  for (const Json& w : r["warnings"])
    if (w.get<std::string>().find(part) != std::string::npos) return true;
  return false;
}

// What a TD decides: status, colour space under each config ("" for data), mode, and a word
// the reason must contain.
struct Expected {
  std::string file, status, aces_space, shipped_space, mode, reason_word;
};

const std::vector<Expected>& expected() {
  static const std::vector<Expected> table = {
      {"rock/T_Rock_N.png", "skipped_data", "", "", "", "'n'"},
      {"rock/T_Rock_D.png", "converted", "sRGB - Texture", "sRGB - Texture", "reflectance", "'d'"},
      {"rock/T_Rock_ARM.png", "skipped_data", "", "", "", "'arm'"},
      {"brick/T_Brick_ORM.png", "skipped_data", "", "", "", "'orm'"},
      {"rock/rock_nrml.jpg", "skipped_data", "", "", "", "'nrml'"},
      {"rock/rock_displace.tif", "skipped_data", "", "", "", "'displace'"},
      {"wood/wood_light.png", "converted", "sRGB - Texture", "sRGB - Texture", "reflectance",
       "cannot exceed white"},
      {"wood/Wood_BaseColor_4K.jpg", "converted", "sRGB - Texture", "sRGB - Texture", "reflectance",
       "'basecolor'"},
      {"metal/metal_plate_basecolor.tif", "converted", "sRGB - Texture", "sRGB - Texture",
       "reflectance", "'basecolor'"},
      {"metal/MetalPlate_Roughness.tif", "skipped_data", "", "", "", "'roughness'"},
      {"metal/metal_plate_Specular.png", "skipped_data", "", "", "", "a grey map"},
      {"metal/metal_plate_spec.png", "converted", "sRGB - Texture", "sRGB - Texture", "reflectance",
       "a colour map"},
      {"crate/normals/crate.png", "skipped_data", "", "", "", "folder word 'normals'"},
      {"crate/crate_Emissive.exr", "converted", "ACEScg", "Linear Rec.709 (sRGB)", "emission",
       "'emissive'"},
      {"hdri/studio.hdr", "converted", "Linear Rec.709 (sRGB)", "Linear Rec.709 (sRGB)", "emission",
       "folder word 'hdri'"},
      {"env/city.exr", "converted", "Linear Rec.709 (sRGB)", "Linear Rec.709 (sRGB)", "emission",
       "folder word 'env'"},
      {"textures/graffiti.exr", "converted", "ACEScg", "Linear Rec.709 (sRGB)", "reflectance",
       "within white"},
      {"textures/macbeth_chart.exr", "converted", "ACEScg", "Linear Rec.709 (sRGB)", "reflectance",
       "within white"},
      {"lights/panel.exr", "converted", "ACEScg", "Linear Rec.709 (sRGB)", "emission",
       "folder word 'lights'"},
      {"shots/plate_bright.exr", "converted", "ACEScg", "Linear Rec.709 (sRGB)", "emission",
       "brighter than white"},
      {"tagged/wall.exr", "converted", "Linear Rec.2020", "Linear Rec.2020", "reflectance",
       "within white"},
      {"tex/a.tif", "converted", "sRGB - Texture", "sRGB - Texture", "reflectance",
       "cannot exceed white"},
      {"tex/a.png", "converted", "sRGB - Texture", "sRGB - Texture", "reflectance",
       "cannot exceed white"},
      {"tex/a.tx", "derived", "", "", "", "maketx"},
  };
  return table;
}

// Which config a library is decided under.
enum class Config { shipped, aces_file, builtin_cg, builtin_studio };

// The built-in configs of OCIO 2.2 and later name the sRGB texture space "sRGB Encoded Rec.709
// (sRGB)" ("sRGB - Texture" is its alias), and the ACES 2.0 studio config has a file rule 'EXR'
// (*.exr: ACES2065-1) that decides an OpenEXR without colour metadata; the other names are the
// ACES CG config file's.
std::string expected_space(const Expected& e, Config config) {
  if (config == Config::shipped) return e.shipped_space;
  if (config == Config::aces_file) return e.aces_space;
  if (e.aces_space == "sRGB - Texture") return "sRGB Encoded Rec.709 (sRGB)";
  const bool exr = e.file.size() > 4 && e.file.compare(e.file.size() - 4, 4, ".exr") == 0;
  if (config == Config::builtin_studio && exr && e.aces_space == "ACEScg") return "ACES2065-1";
  return e.aces_space;
}

void check_library(const std::string& config, Config kind) {
  Scratch s;
  make_library(s);
  auto r = run("ingest " + (s / "lib") + " -o " + (s / "out") + " --config " + config +
               " --format float -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<Json> m = read_manifest(s / "out/spectralize-ingest.jsonl");
  for (const Expected& e : expected()) {
    const Json j = record(m, e.file);
    SCOPED_TRACE(e.file + ": " + j.dump());
    EXPECT_EQ(text(j, "status"), e.status);
    const std::string reason = text(j, e.status == "converted" ? "mode_reason" : "reason");
    const std::string all = reason + " " + text(j, "colorspace_reason");
    EXPECT_NE(all.find(e.reason_word), std::string::npos) << all;
    const std::string rel = e.file.substr(0, e.file.rfind('.'));
    if (e.status == "skipped_data") {
      EXPECT_FALSE(fs::exists(s / ("out/assets/" + rel + ".exr")));
      continue;
    }
    if (e.status != "converted") continue;
    EXPECT_EQ(text(j, "colorspace"), expected_space(e, kind));
    if (expected_space(e, kind) == "ACES2065-1") {
      EXPECT_NE(text(j, "colorspace_reason").find("file rule 'EXR'"), std::string::npos);
    }
    EXPECT_EQ(text(j, "mode"), e.mode);
    // The output says the same in its header and holds the mode's channels.
    const e2e::Exr o = e2e::read_exr(text(j, "output"));
    ASSERT_GT(o.width, 0) << text(j, "output");
    EXPECT_EQ(o.attributes.at("spectralize:colorspaceReason"), text(j, "colorspace_reason"));
    EXPECT_EQ(o.attributes.at("spectralize:modeReason"), text(j, "mode_reason"));
    EXPECT_EQ(e2e::spectral_channels(o, e.mode == "emission" ? "S0." : "T.").size(), 81u);
  }
  // Ambiguous names are decided and warned.
  EXPECT_TRUE(has_warning(record(m, "wood/wood_light.png"), "'light'"));
  EXPECT_TRUE(has_warning(record(m, "metal/metal_plate_spec.png"), "'spec'"));
  EXPECT_TRUE(has_warning(record(m, "metal/metal_plate_Specular.png"), "'specular'"));
  // Same-stem siblings: the derived .tx is the .tif's asset; the other image keeps its own.
  EXPECT_EQ(text(record(m, "tex/a.tx"), "source"), s / "lib/tex/a.tif");
  EXPECT_EQ(text(record(m, "tex/a.tif"), "output"), s / "out/tex/a.tif.exr");
  EXPECT_EQ(text(record(m, "tex/a.png"), "output"), s / "out/tex/a.png.exr");
  EXPECT_FALSE(fs::exists(s / "out/tex/a.exr"));
  EXPECT_FALSE(fs::exists(s / "out/tex/a.tx.exr"));
  const Json& sum = m.back()["summary"];
  EXPECT_EQ(sum["failed"], 0);
  EXPECT_EQ(sum["derived"], 1);
  EXPECT_EQ(sum["skipped_data"], 8);
  EXPECT_EQ(sum["converted"], 15);
  // The Radiance file is linear Rec.709 by the format, not the ACES config's ACEScg: its
  // spectra integrate (the test's own CIE tables) to the Rec.709 XYZ of its pixels, and not to
  // AP1's. Same for the EXR with Photoshop's D50-adapted Rec.709 chromaticities.
  for (const auto& [in, out] :
       {std::pair<std::string, std::string>{"lib/hdri/studio.hdr", "out/hdri/studio.exr"},
        {"lib/env/city.exr", "out/env/city.exr"}}) {
    const e2e::Exr src = e2e::read_exr(s / in), o = e2e::read_exr(s / out);
    ASSERT_EQ(o.width, 32) << out;
    const auto bands = e2e::spectral_channels(o, "S0.");
    std::vector<double> nm;
    for (const auto& b : bands) nm.push_back(b.second);
    const auto w = e2e::band_weights(nm, "cie1931_2deg_cmf_1nm.csv");
    double worst = 0;
    for (const auto& [x, y] : {std::pair{0, 0}, std::pair{31, 1}, std::pair{5, 9}}) {
      const double r = src.at(x, y, 0), g = src.at(x, y, 1), b = src.at(x, y, 2);
      // Rec.709 to XYZ from its primaries and the D65 white (0.3127, 0.3290).
      const double want[3] = {
          0.41239079926595948 * r + 0.35758433938387796 * g + 0.18048078840183429 * b,
          0.21263900587151036 * r + 0.71516867876775593 * g + 0.07219231536073372 * b,
          0.01933081871559185 * r + 0.11919477979462599 * g + 0.95053215224966058 * b};
      double got[3] = {0, 0, 0};
      for (std::size_t i = 0; i < bands.size(); ++i)
        for (int c = 0; c < 3; ++c) got[c] += w[i][c] * o.at(x, y, bands[i].first);
      const double scale = std::max({want[0], want[1], want[2]});
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(got[c] - want[c]) / scale);
    }
    // 1e-5: the bar for float output; read as AP1 they would be off by more than 1e-2.
    EXPECT_LE(worst, 1e-5) << out;
  }
}

}  // namespace

TEST(StudioLibrary, EveryFileDecidedAsATdWouldUnderTheAcesConfig) {
  check_library(kAcesConfig, Config::aces_file);
}

TEST(StudioLibrary, EveryFileDecidedAsATdWouldUnderTheShippedConfig) {
  check_library(SPECTRALIZE_SOURCE_DIR "/ocio_configs/spectralize.ocio", Config::shipped);
}

// The same library under OCIO's built-in ACES configs, by URI: the ACES 2.0 studio config
// (whose matte_paint role is the log ACEScct: integer textures take color_picking's sRGB; its
// file rule makes untagged OpenEXR ACES2065-1) and the ACES 1.3 CG config of OCIO 2.4, both
// stating interop IDs and encodings.
TEST(StudioLibrary, EveryFileDecidedAsATdWouldUnderOcioBuiltInConfigs) {
  if (!e2e::ocio_has_builtin_configs())
    GTEST_SKIP() << "OpenColorIO " << e2e::ocio_version()
                 << " has no built-in configs (2.2 and later do): the same decisions are checked "
                    "under the ACES CG config file and the shipped config";
  for (const auto& [uri, kind] :
       {std::pair{"ocio://studio-config-latest", Config::builtin_studio},
        std::pair{"ocio://cg-config-v2.2.0_aces-v1.3_ocio-v2.4", Config::builtin_cg}}) {
    SCOPED_TRACE(uri);
    check_library(uri, kind);
  }
}
