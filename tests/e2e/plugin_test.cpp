// End-to-end tests of the OpenImageIO plugin (stock oiiotool, maketx, iinfo loading
// spectral.imageio.so) and of `spectralize --to-rgb`, including spectral EXRs written by other
// tools, checked against an independent integration.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "exr_support.h"

namespace fs = std::filesystem;
using e2e::run;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";
const std::string kPluginEnv = "OIIO_LIBRARY_PATH=" SPECTRALIZE_PLUGIN_DIR " " SPECTRALIZE_TOOL_ENV;

// XYZ -> Linear Rec.709, written out independently (inverse of the primaries' matrix).
constexpr double kXyzTo709[3][3] = {{3.2409699419045226, -1.5373831775700939, -0.4986107602930034},
                                    {-0.9692436362808796, 1.8759675015077202, 0.0415550574071756},
                                    {0.0556300796969937, -0.2039769588889765, 1.0569715142428786}};
constexpr double kD65[3] = {0.3127 / 0.3290, 1.0, 0.3583 / 0.3290};

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_plugin") {}
};

// Runs a shell command with the plugin on OIIO's search path.
e2e::Run sh(const std::string& command) {
  static int counter = 0;
  std::string base = std::string(::testing::TempDir()) + "plugin_sh_" + std::to_string(::getpid()) +
                     "_" + std::to_string(counter++);
  std::string cmd = kPluginEnv + " " + command + " >" + base + ".out 2>" + base + ".err";
  int status = std::system(cmd.c_str());
  e2e::Run r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = e2e::slurp(base + ".out");
  r.err = e2e::slurp(base + ".err");
  fs::remove(base + ".out");
  fs::remove(base + ".err");
  return r;
}

// The RGB of every pixel of a spectral file by our own integration: S0 as light, T under D65
// relative to its white (ρ ≡ 1 -> RGB 1).
std::vector<std::array<double, 3>> reference_rgb(const e2e::Exr& e) {
  auto s0 = e2e::spectral_channels(e, "S0.");
  auto t = e2e::spectral_channels(e, "T.");
  const bool emissive = !s0.empty();
  auto& bands = emissive ? s0 : t;
  std::vector<double> nm;
  for (auto& b : bands) nm.push_back(b.second);
  auto w = e2e::band_weights(nm, "cie1931_2deg_cmf_1nm.csv",
                             emissive ? "" : "cie_illuminant_d65_1nm.csv");
  std::array<double, 3> white{0, 0, 0};
  for (auto& b : w)
    for (int c = 0; c < 3; ++c) white[c] += b[c];
  std::vector<std::array<double, 3>> out;
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x) {
      std::array<double, 3> xyz{0, 0, 0};
      for (std::size_t i = 0; i < bands.size(); ++i)
        for (int c = 0; c < 3; ++c) xyz[c] += w[i][c] * e.at(x, y, bands[i].first);
      if (!emissive)
        for (int c = 0; c < 3; ++c) xyz[c] *= kD65[c] / white[c];
      std::array<double, 3> rgb;
      for (int r = 0; r < 3; ++r)
        rgb[r] = kXyzTo709[r][0] * xyz[0] + kXyzTo709[r][1] * xyz[1] + kXyzTo709[r][2] * xyz[2];
      out.push_back(rgb);
    }
  return out;
}

double worst_relative(const e2e::Exr& got, const std::vector<std::array<double, 3>>& want) {
  double worst = 0;
  for (int y = 0; y < got.height; ++y)
    for (int x = 0; x < got.width; ++x) {
      const auto& w = want[static_cast<std::size_t>(y) * got.width + x];
      const double scale = std::max({std::abs(w[0]), std::abs(w[1]), std::abs(w[2])});
      if (scale == 0) continue;
      for (int c = 0; c < 3; ++c) worst = std::max(worst, std::abs(got.at(x, y, c) - w[c]) / scale);
    }
  return worst;
}

TEST(Plugin, OiiotoolGivesTheSamePixelsAsTheCli) {
  Scratch s;
  fs::copy_file(kImages + "colorchecker_srgb8_rgba.png", s / "cc.png");
  const std::string recipe = s.write(
      "cc.spectral",
      R"({"source": "cc.png", "colorspace": "sRGB - Texture", "mode": "reflectance", "wavelengths": "380:780:10", "model": "smooth"})");
  auto r = sh("oiiotool " + recipe + " -o " + (s / "oiio.exr"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run((s / "cc.png") + " -o " + (s / "cli.exr") +
          " --colorspace 'sRGB - Texture' --mode reflectance --wavelengths 380:780:10 --model "
          "smooth");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  e2e::Exr a = e2e::read_exr(s / "oiio.exr"), b = e2e::read_exr(s / "cli.exr");
  EXPECT_EQ(a.channels, b.channels);  // same names, previews, alpha
  EXPECT_EQ(a.format, "half");
  EXPECT_EQ(a.pixels, b.pixels);  // identical pixels
  EXPECT_EQ(a.attributes["spectralLayoutVersion"], "1.0");
  EXPECT_EQ(a.attributes["spectralize:wavelengths"], "380:780:10");
  EXPECT_EQ(a.attributes["spectralize:model"], "smooth");
  // Emission, float, with options given as "spectral:" attributes of the open config.
  s.write("sun.spectral",
          R"({"source": ")" + kImages + R"(hdri_sunset_256x128.exr", "format": "float"})");
  r = sh("oiiotool -iconfig spectral:wavelengths 400:700:10 -iconfig spectral:emission_basis D65 " +
         (s / "sun.spectral") + " -o " + (s / "sun_oiio.exr"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_EQ(run(kImages + "hdri_sunset_256x128.exr -o " + (s / "sun_cli.exr") +
                " --format float --wavelengths 400:700:10 --emission-basis D65")
                .exit_code,
            0);
  e2e::Exr c = e2e::read_exr(s / "sun_oiio.exr"), d = e2e::read_exr(s / "sun_cli.exr");
  EXPECT_EQ(c.channels.size(), 3u + 31u);
  EXPECT_EQ(c.channels, d.channels);
  EXPECT_EQ(c.pixels, d.pixels);
}

TEST(Plugin, MaketxMakesATiledMipMappedSpectralTexture) {
  Scratch s;
  const std::string recipe =
      s.write("t.spectral", R"({"source": ")" + kImages +
                                R"(colorchecker_srgb8.png", "wavelengths": "400:700:20"})");
  // .tx defaults to TIFF, which cannot name channels: ask for OpenEXR to keep the layout.
  auto r = sh("maketx " + recipe + " --format openexr -o " + (s / "t.tx"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = sh("iinfo -v " + (s / "t.tx"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("MIP-map levels: 110x74 55x37"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("tile size"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("T.400,000000nm"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("T.700,000000nm"), std::string::npos) << r.out;
}

TEST(Plugin, IinfoDescribesARecipe) {
  Scratch s;
  const std::string recipe =
      s.write("h.spectral", R"({"source": ")" + kImages + R"(hdri_forest_256x128.exr"})");
  auto r = sh("iinfo -v " + recipe);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("256 x  128, 84 channel, half spectral"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("S0.380,000000nm"), std::string::npos);
  EXPECT_NE(r.out.find("spectralLayoutVersion: \"1.0\""), std::string::npos);
  EXPECT_NE(r.out.find("emissiveUnits"), std::string::npos);
}

// A reader writes nothing unless asked: a recipe's node cache is read where its folder exists,
// and only "cache_write": "yes" (or the open attribute spectral:cache_write, oiiotool -iconfig)
// lets the plugin create the folder and save the nodes. Oracle: the file system.
TEST(Plugin, ReadersWriteTheCacheOnlyWhenAsked) {
  Scratch s;
  const std::string cache = s / "cache";
  const std::string recipe =
      s.write("r.spectral", R"({"source": ")" + kImages + R"(colorchecker_srgb8.png", "cache": ")" +
                                cache + R"("})");
  auto files_in_cache = [&] {
    std::vector<std::string> out;
    if (fs::is_directory(cache))
      for (const auto& e : fs::directory_iterator(cache)) out.push_back(e.path().string());
    return out;
  };
  // Reproduction: iinfo created the folder, oiiotool saved a cache in it.
  EXPECT_EQ(sh("iinfo -v " + recipe).exit_code, 0);
  EXPECT_FALSE(fs::exists(cache));
  EXPECT_EQ(sh("oiiotool " + recipe + " -o " + (s / "o.exr")).exit_code, 0);
  EXPECT_FALSE(fs::exists(cache));
  // An existing folder is read, not written.
  fs::create_directories(cache);
  EXPECT_EQ(sh("oiiotool " + recipe + " -o " + (s / "o.exr")).exit_code, 0);
  EXPECT_TRUE(files_in_cache().empty());
  // Asked by the open configuration: saved.
  EXPECT_EQ(
      sh("oiiotool -iconfig spectral:cache_write yes " + recipe + " -o " + (s / "o.exr")).exit_code,
      0);
  EXPECT_EQ(files_in_cache().size(), 1u);
  // Asked by the recipe: the folder is made and the nodes saved.
  fs::remove_all(cache);
  s.write("w.spectral", R"({"source": ")" + kImages + R"(colorchecker_srgb8.png", "cache": ")" +
                            cache + R"(", "cache_write": "yes"})");
  EXPECT_EQ(sh("oiiotool " + (s / "w.spectral") + " -o " + (s / "o.exr")).exit_code, 0);
  EXPECT_EQ(files_in_cache().size(), 1u);
}

TEST(Plugin, SpectralToRgbRecipeMatchesTheCli) {
  Scratch s;
  ASSERT_EQ(
      run(kImages + "colorchecker_srgb8.png -o " + (s / "cc.exr") + " --format float").exit_code,
      0);
  s.write(
      "rgb.spectral",
      R"({"source": "cc.exr", "to": "rgb", "colorspace": "ACEScg", "illuminant": "A", "format": "float"})");
  auto r = sh("oiiotool " + (s / "rgb.spectral") + " -o " + (s / "plugin.exr"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run("--to-rgb " + (s / "cc.exr") + " -o " + (s / "cli.exr") +
          " --colorspace ACEScg --illuminant A --format float");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  e2e::Exr a = e2e::read_exr(s / "plugin.exr"), b = e2e::read_exr(s / "cli.exr");
  EXPECT_EQ(a.channels, (std::vector<std::string>{"R", "G", "B"}));
  EXPECT_EQ(a.pixels, b.pixels);
}

// RGB -> spectral -> RGB: the round trip returns the input (float), emission and reflectance.
TEST(ToRgb, RoundTripReturnsTheInput) {
  Scratch s;
  for (const char* name : {"hdri_sunset_256x128.exr", "colorchecker_srgb16.png"}) {
    SCOPED_TRACE(name);
    const bool png = std::string(name).find(".png") != std::string::npos;
    ASSERT_EQ(run(kImages + name + " -o " + (s / "spec.exr") + " --format float").exit_code, 0);
    // Back to the input's own space (sRGB-encoded for the texture).
    auto r = run("--to-rgb " + (s / "spec.exr") + " -o " + (s / "back.exr") + " --format float" +
                 (png ? " --colorspace 'sRGB - Texture'" : ""));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    e2e::Exr in = e2e::read_exr(kImages + name), back = e2e::read_exr(s / "back.exr");
    double worst = 0;
    for (int y = 0; y < in.height; ++y)
      for (int x = 0; x < in.width; ++x) {
        const float* p =
            &in.pixels[(static_cast<std::size_t>(y) * in.width + x) * in.channels.size()];
        if (p[0] < 0 || p[1] < 0 || p[2] < 0) continue;  // out of gamut: mapped, not returned
        const double scale = std::max({p[0], p[1], p[2]});
        if (scale <= 0) continue;
        for (int c = 0; c < 3; ++c)
          worst = std::max(worst, std::abs(back.at(x, y, c) - p[c]) / scale);
      }
    // 1e-5 relative (float output; OCIO's float maths and, for the PNG, its sRGB curve).
    EXPECT_LE(worst, 1e-5);
  }
}

// Files written by other tools (colour-science, Fichet's reference, the ART renderer): read,
// converted, and checked against our own integration of the same samples.
TEST(ToRgb, ReadsOtherToolsFilesExactly) {
  Scratch s;
  for (const char* name :
       {"colour_D65.exr", "colour_Ohta1997.exr", "colour_Polarised.exr", "fichet_D65.exr"}) {
    SCOPED_TRACE(name);
    const std::string in = kImages + "spectral_samples/" + name;
    auto r = run("--to-rgb " + in + " -o " + (s / "out.exr") + " --format float");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    e2e::Exr src = e2e::read_exr(in), out = e2e::read_exr(s / "out.exr");
    ASSERT_EQ(out.width, src.width);
    EXPECT_LE(worst_relative(out, reference_rgb(src)), 1e-5);
    if (std::string(name) == "colour_Polarised.exr") {
      EXPECT_NE(r.err.find("S0 used"), std::string::npos) << r.err;
      EXPECT_GE(out.channel("A"), 0);  // alpha passed through
    }
  }
  // D65 light is white: Linear Rec.709 R = G = B (to the tables' rounding, 1e-3).
  e2e::Exr d65 = e2e::read_exr(s / "out.exr");  // fichet_D65, the last one
  EXPECT_NEAR(d65.at(0, 0, 0) / d65.at(0, 0, 1), 1.0, 1e-3);
  EXPECT_NEAR(d65.at(0, 0, 2) / d65.at(0, 0, 1), 1.0, 1e-3);
}

// Channel names of every form the regex allows, in any order, unevenly spaced.
TEST(ToRgb, AcceptsAnyChannelOrderUnitsAndSpacing) {
  Scratch s;
  const std::string path = s / "odd.exr";
  {
    // Bands at 400, 450, 520, 600, 700 nm, named in nm, um and metres, shuffled.
    OIIO::ImageSpec spec(2, 1, 5, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"S0.0,7um", "S0.400,0nm", "S0.5,2e-7m", "S0.450nm", "S0.600,5nm"};
    spec.attribute("spectralLayoutVersion", "1.0");
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec));
    const float px[10] = {0.1f, 1.0f, 2.0f, 3.0f, 0.5f, 0.2f, 0.3f, 0.9f, 0.1f, 0.7f};
    ASSERT_TRUE(out->write_image(OIIO::TypeFloat, px));
    out->close();
  }
  auto r = run("--to-rgb " + path + " -o " + (s / "o.exr") + " --format float");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("5 emissive bands 400..700 nm"), std::string::npos) << r.err;
  e2e::Exr src = e2e::read_exr(path), out = e2e::read_exr(s / "o.exr");
  EXPECT_LE(worst_relative(out, reference_rgb(src)), 1e-5);
}

struct BadSpectral {
  const char* name;
  std::vector<std::string> channels;
  const char* expected;
};

class ToRgbBad : public ::testing::TestWithParam<BadSpectral> {};

TEST_P(ToRgbBad, IsRefusedWithAMessage) {
  Scratch s;
  const std::string path = s / "bad.exr";
  OIIO::ImageSpec spec(2, 2, static_cast<int>(GetParam().channels.size()), OIIO::TypeDesc::HALF);
  spec.channelnames = GetParam().channels;
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->open(path, spec));
  std::vector<float> px(4 * GetParam().channels.size(), 0.5f);
  ASSERT_TRUE(out->write_image(OIIO::TypeFloat, px.data()));
  out->close();
  auto r = run("--to-rgb " + path + " -o " + (s / "o.exr"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("bad.exr"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(GetParam().expected), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s / "o.exr"));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, ToRgbBad,
    ::testing::Values(
        BadSpectral{"Rgb", {"R", "G", "B"}, "no spectral channels"},
        BadSpectral{
            "Mixed", {"S0.500,0nm", "S0.600,0nm", "T.500,0nm", "T.600,0nm"}, "both emissive"},
        BadSpectral{"StokesOnly", {"S1.500,0nm", "S1.600,0nm"}, "no S0"},
        BadSpectral{"Duplicate", {"S0.500,0nm", "S0.500,000000nm", "S0.600nm"}, "same wavelength"},
        BadSpectral{"OneBand", {"S0.550nm", "R"}, "single spectral band"}),
    [](const auto& info) { return info.param.name; });

struct BadRecipe {
  const char* name;
  std::string text;  // "{dir}" is the scratch folder
  const char* expected;
};

class PluginBadRecipe : public ::testing::TestWithParam<BadRecipe> {};

TEST_P(PluginBadRecipe, FailsInOpenNamingTheRecipeAndTheProblem) {
  Scratch s;
  fs::copy_file(kImages + "grey_ramp8.png", s / "grey.png");
  s.write("loop_a.spectral", R"({"source": "loop_b.spectral"})");
  s.write("loop_b.spectral", R"({"source": "loop_a.spectral"})");
  const std::string recipe = s.write("r.spectral", GetParam().text);
  auto r = sh("oiiotool " + recipe + " -o " + (s / "o.exr"));
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("r.spectral"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(GetParam().expected), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s / "o.exr"));
}

INSTANTIATE_TEST_SUITE_P(
    Cases, PluginBadRecipe,
    ::testing::Values(
        BadRecipe{"InvalidJson", R"({"source": "grey.png",)", "invalid JSON"},
        BadRecipe{"NotAnObject", R"(["grey.png"])", "JSON object"},
        // Found by fuzzing: a number too large for a double escaped as an uncaught exception.
        BadRecipe{"NumberOverflow", R"({"source": "grey.png", "threads": 1E110000000000})",
                  "invalid JSON"},
        BadRecipe{"UnknownKey", R"({"source": "grey.png", "colour": "x"})", "unknown key 'colour'"},
        BadRecipe{"BadGrid", R"({"source": "grey.png", "wavelengths": "780:380:5"})",
                  "key 'wavelengths'"},
        BadRecipe{"BadMode", R"({"source": "grey.png", "mode": "glow"})", "key 'mode'"},
        BadRecipe{"BadModel", R"({"source": "grey.png", "model": "wavy"})", "key 'model'"},
        BadRecipe{"BadBasis", R"({"source": "grey.png", "emission_basis": "D6x"})",
                  "key 'emission_basis'"},
        BadRecipe{"BadIlluminant", R"({"source": "grey.png", "illuminant": "F99"})",
                  "key 'illuminant'"},
        BadRecipe{"BadTo", R"({"source": "grey.png", "to": "xyz"})", "key 'to'"},
        BadRecipe{"SourceNotText", R"({"source": 3})", "expected a string"},
        BadRecipe{"NoSource", R"({"mode": "emission"})", "no \"source\""},
        BadRecipe{"MissingSource", R"({"source": "nowhere.png"})", "does not exist"},
        BadRecipe{"Self", R"({"source": "r.spectral"})", "the recipe itself"},
        BadRecipe{"Loop", R"({"source": "loop_a.spectral"})", "loop"},
        BadRecipe{"SpectralKeyForRgb", R"({"source": "grey.png", "to": "rgb", "filter": 0.7})",
                  "does not apply"}),
    [](const auto& info) { return info.param.name; });

}  // namespace
