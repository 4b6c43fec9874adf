// spectralize in a studio's OCIO/OIIO pipeline, through the real binary: defaults from a studio
// config's roles and file rules, a classic v1 config without a CIE XYZ space, honest colour
// tags on every RGB written, --to-rgb into any format and display, the OIIO tools' command-line
// conventions, progress in farm logs, reflectances far above 1, and plot scales.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>

#include "exr_support.h"
#include "imagefile/oiio_compat.h"

namespace fs = std::filesystem;
using e2e::run;
using Json = nlohmann::json;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_pipeline") {}
};

// The ACES CG config a studio points $OCIO at (the project's copy, tests/ocio/SOURCES.md).
std::string aces_config() {
  return SPECTRALIZE_SOURCE_DIR "/tests/ocio/cg-config-v1.0.0_aces-v1.3_ocio-v2.1.ocio";
}

void write_float_rgb(const std::string& path, float r, float g, float b,
                     const std::function<void(OIIO::ImageSpec&)>& edit = nullptr) {
  OIIO::ImageSpec spec(4, 4, 3, OIIO::TypeFloat);
  if (edit) edit(spec);
  std::vector<float> px;
  for (int i = 0; i < 16; ++i) px.insert(px.end(), {r, g, b});
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->open(path, spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeFloat, px.data()));
  out->close();
}

Json color_json(const std::string& args, const std::string& env = "") {
  auto r = run("--format json " + args, env);
  EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
  return r.exit_code == 0 ? Json::parse(r.out) : Json();
}

std::vector<float> chromaticities(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  if (!in) return {};
  const auto* p =
      in->spec().find_attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8));
  if (!p) return {};
  const float* c = static_cast<const float*>(p->data());
  return std::vector<float>(c, c + 8);
}

const std::vector<float> kAp1 = {0.713f, 0.293f, 0.165f,   0.830f,
                                 0.128f, 0.044f, 0.32168f, 0.33767f};

// --- Studio configs ---

// Truth: with the ACES CG config, defaults are the config's roles (scene_linear: ACEScg for
// float data and single colours, matte_paint: sRGB - Texture for integer textures), and the
// previews are written in the config's scene_linear space, tagged as such.
TEST(Pipeline, StudioConfigDefaultsComeFromItsRoles) {
  Scratch s;
  const std::string env = "OCIO=" + aces_config();
  const Json j = color_json("--color 0.2,0.5,0.1", env);
  EXPECT_EQ(j["colorspace"], "ACEScg");
  write_float_rgb(s / "plain.exr", 0.3f, 0.2f, 0.1f);
  auto r = run((s / "plain.exr") + " -o " + (s / "o.exr") + " --report " + (s / "r.json"), env);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream f(s / "r.json");
  const Json rep = Json::parse(f);
  EXPECT_EQ(rep["colorspace"], "ACEScg");
  EXPECT_NE(rep["colorspace_reason"].get<std::string>().find("scene_linear"), std::string::npos);
  EXPECT_EQ(rep["preview_colorspace"], "ACEScg");
  const auto c = chromaticities(s / "o.exr");
  ASSERT_EQ(c.size(), 8u);
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR(c[i], kAp1[i], 1e-5);
  }
  // The previews are the input itself (an ACEScg pixel previewed in ACEScg), to HALF precision.
  const e2e::Exr o = e2e::read_exr(s / "o.exr");
  EXPECT_NEAR(o.at(1, 1, 0), 0.3, 1e-3);
  EXPECT_NEAR(o.at(1, 1, 2), 0.1, 1e-3);
  r = run(kImages + "grey_ramp8.png -o " + (s / "t.exr") + " --report " + (s / "t.json"), env);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream g(s / "t.json");
  EXPECT_EQ(Json::parse(g)["colorspace"], "sRGB - Texture");
}

// Truth: a config's file rules decide an untagged file's colour space (before its metadata).
TEST(Pipeline, FileRulesOfTheConfigAreConsulted) {
  Scratch s;
  std::string config = e2e::slurp(SPECTRALIZE_SOURCE_DIR "/ocio_configs/spectralize.ocio");
  // The shipped config has these rules; check them through a copy that changes nothing else.
  std::ofstream(s / "c.ocio") << config;
  write_float_rgb(s / "wall_acescg.exr", 0.2f, 0.3f, 0.4f);
  auto r = run((s / "wall_acescg.exr") + " -o " + (s / "o.exr") + " -v --config " + (s / "c.ocio"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("colour space 'ACEScg' (the config's file rule"), std::string::npos)
      << r.err;
}

// A classic OCIO v1 ACES config: no CIE XYZ space, no interchange role; XYZ is derived from its
// ACES2065-1 space by OCIO's built-in transform. Truth: white of any space is the D65 white
// (Bradford maps white to white), and ACEScg through this config is ACEScg through the shipped.
TEST(Pipeline, ClassicV1ConfigWithoutXyzWorks) {
  Scratch s;
  std::ofstream(s / "v1.ocio") << R"(ocio_profile_version: 1
search_path: ""
strictparsing: true
luma: [0.2126, 0.7152, 0.0722]
roles:
  reference: ACES - ACES2065-1
  scene_linear: ACES - ACEScg
  color_picking: ACES - ACEScg
  data: Utility - Raw
  default: ACES - ACES2065-1
displays:
  sRGB:
    - !<View> {name: Raw, colorspace: Utility - Raw}
active_displays: [sRGB]
active_views: [Raw]
colorspaces:
  - !<ColorSpace>
    name: ACES - ACES2065-1
    family: ACES
    bitdepth: 32f
    isdata: false
  - !<ColorSpace>
    name: ACES - ACEScg
    family: ACES
    bitdepth: 32f
    isdata: false
    to_reference: !<MatrixTransform> {matrix: [0.6954522414, 0.1406786965, 0.1638690622, 0, 0.0447945634, 0.8596711185, 0.0955343182, 0, -0.0055258826, 0.0040252103, 1.0015006723, 0, 0, 0, 0, 1]}
  - !<ColorSpace>
    name: Utility - Raw
    family: Utility
    bitdepth: 32f
    isdata: true
)";
  const Json white = color_json("--color 1,1,1 --config " + (s / "v1.ocio"));
  EXPECT_EQ(white["colorspace"], "ACES - ACEScg");
  const double d65[3] = {0.3127 / 0.3290, 1.0, 0.3583 / 0.3290};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(white["input_xyz"][i].get<double>(), d65[i], 2e-4);
  }
  const Json a = color_json("--color 0.7,0.2,0.1 --config " + (s / "v1.ocio"));
  const Json b = color_json("--color 0.7,0.2,0.1 --colorspace ACEScg");
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(a["input_xyz"][i].get<double>(), b["input_xyz"][i].get<double>(), 2e-5);
  }
  // A config with no way to XYZ fails with a message that says what is missing.
  std::string bare = e2e::slurp(s / "v1.ocio");
  bare = std::regex_replace(bare, std::regex("ACES - ACES2065-1"), "Studio Reference");
  std::ofstream(s / "bare.ocio") << bare;
  auto r = run("--color 1,1,1 --config " + (s / "bare.ocio"));
  EXPECT_NE(r.exit_code, 0);
  // The config is at fault, not a flag that was never given: the message names the config file
  // and what it lacks.
  EXPECT_EQ(r.err.find("--colorspace"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("OCIO config '" + (s / "bare.ocio") + "' has no route to CIE XYZ"),
            std::string::npos)
      << r.err;
  for (const char* lack : {"cie_xyz_d65_interchange", "aces_interchange", "'ACES2065-1'"}) {
    EXPECT_NE(r.err.find(lack), std::string::npos) << lack << ": " << r.err;
  }
  // A nuke-default-like config (reference 'linear', a scene_linear role): the same, also
  // through --to-rgb's and the image command's option handling.
  std::string nuke =
      std::regex_replace(e2e::slurp(s / "v1.ocio"), std::regex("ACES - ACES2065-1"), "linear");
  std::ofstream(s / "nuke.ocio") << nuke;
  for (const std::string& args :
       {"--color 0.2,0.5,0.1 --config " + (s / "nuke.ocio"),
        kImages + "grey_ramp8.png -o " + (s / "n.exr") + " --config " + (s / "nuke.ocio")}) {
    r = run(args);
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.err;
    EXPECT_EQ(r.err.find("--colorspace"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("'" + (s / "nuke.ocio") + "' has no route to CIE XYZ"), std::string::npos)
        << r.err;
  }
  // Plots take their spaces from the config's roles: the swatches in color_picking (here the
  // linear ACEScg, said by the PNG's ICC profile), the EXR plot in scene_linear.
  r = run("--color 0.2,0.5,0.1 -o " + (s / "p.png") + " --config " + (s / "v1.ocio"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  {
    auto in = OIIO::ImageInput::open(s / "p.png");
    ASSERT_TRUE(in);
    EXPECT_EQ(in->spec().get_string_attribute("ICCProfile:profile_description"),
              "ACES - ACEScg (lin_ap1_scene)");
  }
  r = run("--color 0.2,0.5,0.1 -o " + (s / "p.exr") + " --config " + (s / "v1.ocio"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto plot_xy = chromaticities(s / "p.exr");
  ASSERT_EQ(plot_xy.size(), 8u);
  EXPECT_NEAR(plot_xy[0], 0.713f, 1e-5);
  // Without color_picking or matte_paint (and no shipped name): an error naming the roles.
  std::string no_picking =
      std::regex_replace(e2e::slurp(s / "v1.ocio"), std::regex("  color_picking.*\n"), "");
  std::ofstream(s / "nopick.ocio") << no_picking;
  r = run("--color 0.2,0.5,0.1 -o " + (s / "q.png") + " --config " + (s / "nopick.ocio"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("'" + (s / "nopick.ocio") + "' has no color_picking or matte_paint role"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(s / "q.png"));
}

// OCIO's built-in configs by URI, as --config and as $OCIO: used where OCIO has them (2.2 and
// later), recorded in the report as given; refused naming the version where it does not.
TEST(Pipeline, BuiltInConfigsAreUsedWhereOcioHasThemAndRefusedNamingTheVersionElsewhere) {
  Scratch s;
  const bool builtin = e2e::ocio_has_builtin_configs();
  for (const bool env : {false, true}) {
    SCOPED_TRACE(env ? "$OCIO" : "--config");
    const std::string config = env ? "" : " --config ocio://default";
    auto r = run("--color 0.18,0.18,0.18 --colorspace ACEScg --format json" + config,
                 env ? "OCIO=ocio://default" : "");
    if (!builtin) {
      // A config that cannot be loaded, however it is named (docs/guide/files.md): exit 1.
      EXPECT_EQ(r.exit_code, 1) << r.err;
      EXPECT_NE(r.err.find("OpenColorIO 2.2"), std::string::npos) << r.err;
      EXPECT_NE(r.err.find("ocio://"), std::string::npos) << r.err;
      continue;
    }
    ASSERT_EQ(r.exit_code, 0) << r.err;
    // A grey of ACEScg is the D60-ish white of AP1 at 18%: Y = 0.18 (the matrix's middle row
    // sums to 1), whatever the built-in config's version.
    const Json j = Json::parse(r.out);
    EXPECT_NEAR(j.at("xyz").at(1).get<double>(), 0.18, 1e-5) << r.out;
  }
}

// --- Outputs that say what they are ---

TEST(Pipeline, PreviewColourSpaceIsChosenAndTagged) {
  Scratch s;
  auto r = run(kImages + "hdri_forest_256x128.exr -o " + (s / "o.exr") +
               " -q --format float --preview-colorspace ACEScg");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto c = chromaticities(s / "o.exr");
  ASSERT_EQ(c.size(), 8u);
  EXPECT_NEAR(c[0], kAp1[0], 1e-5);
  // The previews equal --to-rgb of the same file into ACEScg (float, to rounding).
  ASSERT_EQ(run("--to-rgb " + (s / "o.exr") + " -o " + (s / "cg.exr") +
                " --colorspace ACEScg --format float -q")
                .exit_code,
            0);
  const e2e::Exr o = e2e::read_exr(s / "o.exr"), cg = e2e::read_exr(s / "cg.exr");
  double worst = 0;
  for (int y = 0; y < o.height; y += 7)
    for (int x = 0; x < o.width; x += 7)
      for (int ch = 0; ch < 3; ++ch)
        worst = std::max(worst, std::abs(static_cast<double>(o.at(x, y, ch) - cg.at(x, y, ch))) /
                                    std::max(1e-3, static_cast<double>(std::abs(cg.at(x, y, ch)))));
  EXPECT_LE(worst, 1e-4);
}

// Truth: --to-rgb writes any format; integer files get the display encoding (sRGB texture,
// 8 bits) and say so; as-lit under A turns a white surface warm, balanced keeps it white.
TEST(Pipeline, ToRgbWritesAnyFormatDisplayAndAsLit) {
  Scratch s;
  ASSERT_EQ(run(kImages + "grey_ramp8.png -o " + (s / "grey.exr") + " -q").exit_code, 0);
  auto r = run("--to-rgb " + (s / "grey.exr") + " -o " + (s / "back.png") + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto in = OIIO::ImageInput::open(s / "back.png");
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().format, OIIO::TypeUInt8);
  // The round trip of an 8-bit sRGB texture through spectra returns its own code values.
  std::vector<unsigned char> back(64 * 8 * 3), orig(64 * 8 * 3);
  ASSERT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeUInt8, back.data()));
  auto src = OIIO::ImageInput::open(kImages + "grey_ramp8.png");
  ASSERT_TRUE(src->read_image(0, 0, 0, 1, OIIO::TypeUInt8, orig.data()));
  for (int x = 0; x < 64; ++x) {
    EXPECT_NEAR(back[(3 * 64 + x) * 3], orig[3 * 64 + x], 1) << x;
  }
  // As lit under A: a white surface reflects A's light: red well above blue.
  ASSERT_EQ(run("--to-rgb " + (s / "grey.exr") + " -o " + (s / "a.exr") +
                " --illuminant A --reflected as-lit --format float -q")
                .exit_code,
            0);
  const e2e::Exr a = e2e::read_exr(s / "a.exr");
  EXPECT_GT(a.at(63, 3, 0), 1.5 * a.at(63, 3, 2));
  ASSERT_EQ(run("--to-rgb " + (s / "grey.exr") + " -o " + (s / "b.exr") +
                " --illuminant A --format float -q")
                .exit_code,
            0);
  const e2e::Exr b = e2e::read_exr(s / "b.exr");
  EXPECT_NEAR(b.at(63, 3, 0), b.at(63, 3, 2), 1e-3);
  // Float TIFF: the same samples as the float EXR (scene-linear by default, as for EXR).
  ASSERT_EQ(run("--to-rgb " + (s / "grey.exr") + " -o " + (s / "f.tif") +
                " --illuminant A --format float -q")
                .exit_code,
            0);
  const e2e::Exr f = e2e::read_exr(s / "f.tif");
  ASSERT_EQ(f.pixels.size(), b.pixels.size());
  EXPECT_EQ(f.pixels, b.pixels);
  EXPECT_EQ(
      run("--to-rgb " + (s / "grey.exr") + " -o " + (s / "f.png") + " --format float -q").exit_code,
      2);
  // A display and view of the config.
  r = run("--to-rgb " + (s / "grey.exr") + " -o " + (s / "d.tif") +
          " --display sRGB --view Standard -q");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  r = run("--to-rgb " + (s / "grey.exr") + " -o " + (s / "d.tif") + " --display Nope");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("sRGB"), std::string::npos) << "lists the valid displays: " << r.err;
  r = run("--to-rgb " + (s / "grey.exr") + " -o " + (s / "x.png") + " --format half");
  EXPECT_EQ(r.exit_code, 2) << r.err;
}

// Truth: every tag describes the data as written. A display's view is display-referred: under
// the ACES config "sRGB - Display" / "ACES 1.0 - SDR Video" is tagged srgb_rec709_display (read
// back with OIIO), and a "sRGB - Texture" PNG reads back as that very space, not as another of
// the same interop ID.
TEST(Pipeline, TagsSayDisplayReferredAndReadBackAsTheExactSpace) {
  Scratch s;
  const std::string env = "OCIO=" + aces_config();
  ASSERT_EQ(run(kImages + "colorchecker_srgb8.png -o " + (s / "cc.exr") + " -q", env).exit_code, 0);
  auto r = run("--to-rgb " + (s / "cc.exr") + " -o " + (s / "d.png") +
                   " --display \"sRGB - Display\" --view \"ACES 1.0 - SDR Video\" -q",
               env);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto in = OIIO::ImageInput::open(s / "d.png");
  ASSERT_TRUE(in);
  EXPECT_EQ(in->spec().get_string_attribute("colorInteropID"), "srgb_rec709_display");
  // OIIO 2 keeps the config's name; OIIO 3 reads the PNG's own chunks (cICP: sRGB).
  if (!spectralize::oiio_compat::kInteropColourSpaceNames) {
    EXPECT_EQ(in->spec().get_string_attribute("oiio:ColorSpace"), "sRGB - Display");
  }
  in.reset();
  r = run(
      "--to-rgb " + (s / "cc.exr") + " -o " + (s / "t.png") + " --colorspace \"sRGB - Texture\" -q",
      env);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const auto& [file, space] : {std::pair<std::string, std::string>{"t.png", "sRGB - Texture"},
                                    {"d.png", "sRGB - Display"}}) {
    ASSERT_EQ(run((s / file) + " -o " + (s / (file + ".exr")) + " --report " +
                      (s / (file + ".json")) + " -q",
                  env)
                  .exit_code,
              0);
    std::ifstream f(s / (file + ".json"));
    EXPECT_EQ(Json::parse(f)["colorspace"], space) << file;
  }
}

// Truth: an integer --to-rgb counts a pixel as clipped only when a value lies more than half a
// code value outside 0..1 (a code is lost). The oracle: the same integration written as float
// in the same encoding, counted by the test. A faithful round trip (the 16-bit chart's values a
// hair below 0) loses nothing; a sunset's sky loses codes in exactly the pixels the float file
// says.
TEST(Pipeline, ToRgbCountsOnlyClippingThatLosesCodes) {
  Scratch s;
  auto count = [](const std::string& path, double margin) {
    const e2e::Exr e = e2e::read_exr(path);
    std::uint64_t n = 0;
    for (int y = 0; y < e.height; ++y)
      for (int x = 0; x < e.width; ++x) {
        bool out = false;
        for (int c = 0; c < 3; ++c)
          out = out || e.at(x, y, c) < -margin || e.at(x, y, c) > 1 + margin;
        n += out;
      }
    return n;
  };
  for (const auto& [image, source] :
       {std::pair<std::string, std::string>{"cc", "colorchecker_srgb16.png"},
        {"sun", "hdri_sunset_256x128.exr"}}) {
    ASSERT_EQ(run(kImages + source + " -o " + (s / (image + ".exr")) + " -q").exit_code, 0);
    auto r = run("--to-rgb " + (s / (image + ".exr")) + " -o " + (s / (image + ".png")) +
                 " --report " + (s / (image + ".json")));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    ASSERT_EQ(run("--to-rgb " + (s / (image + ".exr")) + " -o " + (s / (image + "_f.exr")) +
                  " --colorspace \"sRGB - Texture\" --format float -q")
                  .exit_code,
              0);
    std::ifstream f(s / (image + ".json"));
    const std::uint64_t clipped = Json::parse(f)["clipped_pixels"].get<std::uint64_t>();
    const std::uint64_t lost = count(s / (image + "_f.exr"), 0.5 / 255);
    EXPECT_EQ(clipped, lost) << image;
    EXPECT_EQ(r.err.find("clipped") == std::string::npos, lost == 0) << r.err;
    if (image == "cc") {
      EXPECT_GT(count(s / (image + "_f.exr"), 0), 0u);  // outside 0..1, by less than a code
      EXPECT_EQ(lost, 0u);
    } else {
      EXPECT_GT(lost, 1000u);
    }
  }
}

// --- The OIIO tools' conventions ---

TEST(Pipeline, CommandLineSpeaksLikeTheOiioTools) {
  Scratch s;
  auto r = run("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out.rfind("spectralize ", 0), 0u);
  r = run("-h");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("Flags by command"), std::string::npos);
  const std::string in = kImages + "grey_ramp8.png";
  r = run(in + " -o " + (s / "a.exr") +
          " -d float --threads 0 --tile 64 32 "
          "--compression dwaa:45 --colorconfig " SPECTRALIZE_SOURCE_DIR
          "/ocio_configs/spectralize.ocio -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto file = OIIO::ImageInput::open(s / "a.exr");
  ASSERT_TRUE(file);
  EXPECT_EQ(file->spec().format, OIIO::TypeFloat);
  EXPECT_EQ(file->spec().tile_width, 64);
  EXPECT_EQ(file->spec().tile_height, 32);
  EXPECT_EQ(file->spec().get_string_attribute("compression"), "dwaa");
  // F11 is FL11.
  const Json f11 = color_json("--color 0.3,0.5,0.2 --mode reflectance --illuminant F11");
  const Json fl11 = color_json("--color 0.3,0.5,0.2 --mode reflectance --illuminant FL11");
  EXPECT_EQ(f11["values"], fl11["values"]);
  EXPECT_EQ(f11["illuminant"], "FL11");
  // Common slips name themselves.
  r = run("--color 1 1 1");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--color 1,1,1"), std::string::npos) << r.err;
}

// Truth: off a terminal (a farm log), -v prints progress lines as the job advances.
TEST(Pipeline, ProgressLinesOffATerminal) {
  Scratch s;
  auto r = run(kImages + "hdri_interior_1024x512.exr -o " + (s / "o.exr") + " -v");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::regex line(R"(spectralize: .*hdri_interior_1024x512\.exr: \d+% \()");
  int lines = 0;
  for (std::sregex_iterator it(r.err.begin(), r.err.end(), line), end; it != end; ++it) ++lines;
  EXPECT_GE(lines, 3) << r.err;
}

// Truth: a reflectance far above 1 (8-bit values given as 0..1) is mapped into the solid (not
// black), counted, and the message says what probably happened.
TEST(Pipeline, ReflectancesFarAboveOneAreMappedAndExplained) {
  Scratch s;
  auto r = run("--color 255,128,0 --colorspace srgb --mode reflectance --format json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("did you mean 0-1 values"), std::string::npos) << r.err;
  const Json j = Json::parse(r.out);
  EXPECT_EQ(j["status"], "out_of_gamut");
  double peak = 0;
  for (const auto& v : j["values"]) peak = std::max(peak, v.get<double>());
  EXPECT_GT(peak, 0.3);  // a bright orange surface, not black
  write_float_rgb(s / "hot.exr", 30000.0f, 20000.0f, 10000.0f);
  r = run((s / "hot.exr") + " -o " + (s / "o.exr") + " --mode reflectance --report " +
          (s / "r.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream f(s / "r.json");
  EXPECT_EQ(Json::parse(f)["out_of_gamut"]["brighter_than_white"], 16);
  EXPECT_NE(r.err.find("brighter than a white surface"), std::string::npos) << r.err;
}

// --- Plots ---

TEST(Pipeline, PlotScalesAndPixelCsv) {
  Scratch s;
  ASSERT_EQ(run(kImages + "hdri_interior_1024x512.exr -o " + (s / "m.exr") + " -q").exit_code, 0);
  // CSV of two pixels, normalised: each column's largest value is 1.
  auto r = run("--plot-pixel 100,20 --plot-pixel 500,300 " + (s / "m.exr") + " -o " +
               (s / "p.csv") + " --plot-scale normalized");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::istringstream csv(e2e::slurp(s / "p.csv"));
  std::string row;
  std::getline(csv, row);
  EXPECT_EQ(row, "wavelength_nm,\"pixel (100, 20)\",\"pixel (500, 300)\"");
  double peak[2] = {0, 0};
  int rows = 0;
  while (std::getline(csv, row)) {
    double nm, a, b;
    char c1, c2;
    std::istringstream(row) >> nm >> c1 >> a >> c2 >> b;
    peak[0] = std::max(peak[0], a);
    peak[1] = std::max(peak[1], b);
    ++rows;
  }
  EXPECT_EQ(rows, 81);
  EXPECT_DOUBLE_EQ(peak[0], 1.0);
  EXPECT_DOUBLE_EQ(peak[1], 1.0);
  // Log scale: decade labels on the value axis.
  r = run("--color 6000,5000,1000 --color 0.01,0.02,0.03 -o " + (s / "l.svg") +
          " --plot-scale log");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string svg = e2e::slurp(s / "l.svg");
  EXPECT_NE(svg.find(">1000<"), std::string::npos);
  EXPECT_NE(svg.find(">0.01<"), std::string::npos);
}

}  // namespace
