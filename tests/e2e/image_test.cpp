// End-to-end tests of `spectralize INPUT -o OUTPUT.exr` on testimages/ through the real binary:
// layout, exactness against an independent integration, bounds, gamut counts, alpha, methods,
// threads, cache, streaming memory and bad input.

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <regex>

#include "exr_support.h"

namespace fs = std::filesystem;
using e2e::run;
using Json = nlohmann::json;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";

// Linear Rec.709 / Rec.2020 / ACEScg (Bradford to D65) -> XYZ, written out independently.
constexpr double kRec709[3][3] = {{0.41239079926595948, 0.35758433938387796, 0.18048078840183429},
                                  {0.21263900587151036, 0.71516867876775593, 0.07219231536073372},
                                  {0.01933081871559185, 0.11919477979462599, 0.95053215224966058}};
constexpr double kD65[3] = {0.3127 / 0.3290, 1.0, 0.3583 / 0.3290};

std::array<double, 3> mul(const double m[3][3], double r, double g, double b) {
  return {m[0][0] * r + m[0][1] * g + m[0][2] * b, m[1][0] * r + m[1][1] * g + m[1][2] * b,
          m[2][0] * r + m[2][1] * g + m[2][2] * b};
}

double srgb_decode(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

// A scratch folder per test, removed at the end.
struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_img") {}
};

Json read_json(const std::string& path) {
  std::ifstream f(path);
  return Json::parse(f);
}

// The XYZ of every pixel's spectrum, by our own weights.
std::vector<std::array<double, 3>> integrate_pixels(const e2e::Exr& e, const char* prefix,
                                                    const std::string& illuminant_file = "") {
  auto bands = e2e::spectral_channels(e, prefix);
  std::vector<double> nm;
  for (auto& b : bands) nm.push_back(b.second);
  auto w = e2e::band_weights(nm, "cie1931_2deg_cmf_1nm.csv", illuminant_file);
  std::vector<std::array<double, 3>> out(static_cast<std::size_t>(e.width) * e.height);
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x) {
      std::array<double, 3> xyz{0, 0, 0};
      for (std::size_t i = 0; i < bands.size(); ++i)
        for (int c = 0; c < 3; ++c) xyz[c] += w[i][c] * e.at(x, y, bands[i].first);
      out[static_cast<std::size_t>(y) * e.width + x] = xyz;
    }
  return out;
}

double rel(const std::array<double, 3>& got, const std::array<double, 3>& want) {
  double scale = std::max({std::abs(want[0]), std::abs(want[1]), std::abs(want[2])});
  double diff = std::max(
      {std::abs(got[0] - want[0]), std::abs(got[1] - want[1]), std::abs(got[2] - want[2])});
  return scale > 0 ? diff / scale : diff;
}

// An HDR environment map: emission, layout, and exactness of every pixel with non-negative RGB
// (inside Rec.709, so inside the locus) against our own integration, with --format float.
TEST(CliImage, HdriIsExactInFloatWithTheSpectralLayout) {
  Scratch s;
  const std::string in = kImages + "hdri_sunset_256x128.exr";
  auto r = run(in + " -o " + (s / "out.exr") + " --format float --report " + (s / "r.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  e2e::Exr e = e2e::read_exr(s / "out.exr");
  ASSERT_EQ(e.width, 256);
  ASSERT_EQ(e.height, 128);
  EXPECT_EQ(e.format, "float");
  // Layout: R, G, B preview + 81 S0 bands named by the regex; attributes.
  auto bands = e2e::spectral_channels(e, "S0.");
  ASSERT_EQ(bands.size(), 81u);
  EXPECT_EQ(bands.front().second, 380);
  EXPECT_EQ(bands.back().second, 780);
  EXPECT_GE(e.channel("S0.550,000000nm"), 0);
  EXPECT_GE(e.channel("R"), 0);
  EXPECT_GE(e.channel("B"), 0);
  EXPECT_EQ(e.attributes["spectralLayoutVersion"], "1.0");
  EXPECT_EQ(e.attributes["emissiveUnits"], "W.m^-2.sr^-1");
  EXPECT_EQ(e.attributes["spectralize:mode"], "emission");
  EXPECT_EQ(e.attributes["spectralize:wavelengths"], "380:780:5");
  // Exactness against the input pixels (Linear Rec.709, our matrix and integration).
  e2e::Exr src = e2e::read_exr(in);
  auto xyz = integrate_pixels(e, "S0.");
  double worst = 0, worst_preview = 0;
  int checked = 0;
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x) {
      const float rgb[3] = {src.at(x, y, 0), src.at(x, y, 1), src.at(x, y, 2)};
      if (rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0) continue;
      auto want = mul(kRec709, rgb[0], rgb[1], rgb[2]);
      worst = std::max(worst, rel(xyz[static_cast<std::size_t>(y) * e.width + x], want));
      for (const auto& b : bands) {
        ASSERT_GE(e.at(x, y, b.first), 0.0f);  // non-negative
      }
      // The preview is the spectrum's colour back in Linear Rec.709: the input again.
      for (int c = 0; c < 3; ++c)
        worst_preview = std::max(worst_preview, double(std::abs(e.at(x, y, c) - rgb[c]) /
                                                       std::max({rgb[0], rgb[1], rgb[2]})));
      ++checked;
    }
  EXPECT_GT(checked, 30000);
  // 1e-5: the float bar of docs/DESIGN.md §3 (OCIO's float maths alone is ~1e-7).
  EXPECT_LE(worst, 1e-5);
  EXPECT_LE(worst_preview, 1e-4);  // through OCIO's float matrices twice
  Json rep = read_json(s / "r.json");
  EXPECT_LE(rep["max_relative_xyz_error"].get<double>(), 1e-5);
  EXPECT_EQ(rep["pixels"], 256 * 128);
  EXPECT_EQ(rep["mode"], "emission");
  EXPECT_EQ(rep["colorspace"], "Linear Rec.709 (sRGB)");
  for (const char* key : {"input", "output", "colorspace", "mode", "wavelengths", "pixels",
                          "out_of_gamut_pixels", "out_of_gamut", "invalid_pixels",
                          "max_relative_xyz_error", "mean_relative_xyz_error", "cache", "seconds"})
    EXPECT_TRUE(rep.contains(key)) << key;
  EXPECT_EQ(s.files(), (std::vector<std::string>{"out.exr", "r.json"}));  // no temporary left
}

// Both models through the image path (table, cache nodes, fallbacks): the smooth model's HDRI
// and ColorChecker are exact against the input to 1e-5 (float output), non-negative and <= 1,
// and the files say which model made them.
TEST(CliImage, SmoothModelImagesAreExactAndLabelled) {
  Scratch s;
  const std::string hdri = kImages + "hdri_sunset_256x128.exr";
  auto r = run(hdri + " -o " + (s / "h.exr") + " --format float --model smooth --report " +
               (s / "h.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  e2e::Exr e = e2e::read_exr(s / "h.exr");
  EXPECT_EQ(e.attributes["spectralize:model"], "smooth");
  e2e::Exr src = e2e::read_exr(hdri);
  auto xyz = integrate_pixels(e, "S0.");
  auto bands = e2e::spectral_channels(e, "S0.");
  double worst = 0;
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x) {
      const float rgb[3] = {src.at(x, y, 0), src.at(x, y, 1), src.at(x, y, 2)};
      if (rgb[0] < 0 || rgb[1] < 0 || rgb[2] < 0) continue;
      worst = std::max(worst, rel(xyz[static_cast<std::size_t>(y) * e.width + x],
                                  mul(kRec709, rgb[0], rgb[1], rgb[2])));
      for (const auto& b : bands) {
        ASSERT_GE(e.at(x, y, b.first), 0.0f);
      }
    }
  EXPECT_LE(worst, 1e-5);
  Json rep = read_json(s / "h.json");
  EXPECT_EQ(rep["model"], "smooth");
  EXPECT_FALSE(rep.contains("filter"));  // the paper model's only
  EXPECT_EQ(e.attributes.count("spectralize:filter"), 0u);
  EXPECT_EQ(rep["emission_basis"], "flat");
  EXPECT_LE(rep["max_relative_xyz_error"].get<double>(), 1e-5);

  // The ColorChecker as reflectance, and with a D65 emission basis as light (recipe keys too).
  const std::string cc = kImages + "colorchecker_srgb8.png";
  r = run(cc + " -o " + (s / "c.exr") + " --format float --model smooth --report " +
          (s / "c.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  e2e::Exr c = e2e::read_exr(s / "c.exr");
  for (const auto& b : e2e::spectral_channels(c, "T."))
    for (int y = 0; y < c.height; ++y)
      for (int x = 0; x < c.width; ++x) {
        ASSERT_GE(c.at(x, y, b.first), 0.0f);
        ASSERT_LE(c.at(x, y, b.first), 1.0f);
      }
  EXPECT_LE(read_json(s / "c.json")["max_relative_xyz_error"].get<double>(), 1e-5);
  r = run(cc + " -o " + (s / "l.exr") +
          " --format float --mode emission --emission-basis D65 --report " + (s / "l.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(e2e::read_exr(s / "l.exr").attributes["spectralize:emissionBasis"], "D65");
  EXPECT_LE(read_json(s / "l.json")["max_relative_xyz_error"].get<double>(), 1e-5);
}

// An 8-bit sRGB ColorChecker: reflectance (auto), 0 <= rho <= 1, exact to the white-balanced
// colour under D65, alpha passed through.
TEST(CliImage, ColorCheckerIsAnExactBoundedReflectanceWithAlphaKept) {
  Scratch s;
  const std::string in = kImages + "colorchecker_srgb8_rgba.png";
  auto r = run(in + " -o " + (s / "cc.exr") + " --format float --report " + (s / "r.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  e2e::Exr e = e2e::read_exr(s / "cc.exr");
  e2e::Exr src = e2e::read_exr(in);  // OIIO reads 8-bit as value / 255
  auto bands = e2e::spectral_channels(e, "T.");
  ASSERT_EQ(bands.size(), 81u);
  EXPECT_TRUE(e.attributes.find("emissiveUnits") == e.attributes.end());
  EXPECT_EQ(e.attributes["spectralize:mode"], "reflectance");
  const int a = e.channel("A");
  ASSERT_GE(a, 0);
  std::vector<double> nm;
  for (auto& b : bands) nm.push_back(b.second);
  auto white = e2e::band_weights(nm, "cie1931_2deg_cmf_1nm.csv", "cie_illuminant_d65_1nm.csv");
  std::array<double, 3> w_ref{0, 0, 0};
  for (auto& b : white)
    for (int c = 0; c < 3; ++c) w_ref[c] += b[c];
  auto xyz = integrate_pixels(e, "T.", "cie_illuminant_d65_1nm.csv");
  double worst = 0;
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x) {
      for (const auto& b : bands) {
        ASSERT_GE(e.at(x, y, b.first), 0.0f);
        ASSERT_LE(e.at(x, y, b.first), 1.0f + 1e-6f);  // float rounding of values at 1
      }
      EXPECT_EQ(e.at(x, y, a), src.at(x, y, 3));  // alpha untouched
      // OIIO premultiplies colour by alpha on read: the gutter (alpha 0.5) is black anyway.
      auto lin = mul(kRec709, srgb_decode(src.at(x, y, 0)), srgb_decode(src.at(x, y, 1)),
                     srgb_decode(src.at(x, y, 2)));
      std::array<double, 3> want;
      for (int c = 0; c < 3; ++c) want[c] = lin[c] * w_ref[c] / kD65[c];
      if (want[1] <= 0) continue;
      worst = std::max(worst, rel(xyz[static_cast<std::size_t>(y) * e.width + x], want));
    }
  // 1e-5 with 1e-6 to spare for OCIO's sRGB curve, which differs from the textbook one by 4e-7.
  EXPECT_LE(worst, 1e-5);
  Json rep = read_json(s / "r.json");
  EXPECT_EQ(rep["colorspace"], "sRGB - Texture");
  EXPECT_EQ(rep["out_of_gamut_pixels"], 0);  // every sRGB colour is a reflectance
  EXPECT_TRUE(rep["alpha"].get<bool>());
}

// Wide-gamut float sweeps: their primaries lie outside the locus, some rows have negative
// luminance. The colour space comes from the file's chromaticities. Counts are checked against
// our own classification of the input; mapped pixels keep their luminance and are exact to it.
TEST(CliImage, WideGamutSweepIsMappedAndCountedByKind) {
  Scratch s;
  const std::string in = kImages + "sweep_rec2020_64x32.exr";
  auto r = run(in + " -o " + (s / "sw.exr") + " --format float --report " + (s / "r.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("out of gamut"), std::string::npos) << r.err;
  Json rep = read_json(s / "r.json");
  EXPECT_EQ(rep["colorspace"], "Linear Rec.2020");
  const double m2020[3][3] = {{0.63695804830129129, 0.14461690358620837, 0.16888097516417206},
                              {0.26270021201126703, 0.67799807151887102, 0.05930171646986195},
                              {0.0, 0.02807269304908751, 1.06098505771079091}};
  e2e::Exr src = e2e::read_exr(in);
  e2e::Exr e = e2e::read_exr(s / "sw.exr");
  auto xyz = integrate_pixels(e, "S0.");
  int negative = 0, in_rec709 = 0;
  double worst_in = 0, worst_y = 0;
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x) {
      auto want = mul(m2020, src.at(x, y, 0), src.at(x, y, 1), src.at(x, y, 2));
      const auto& got = xyz[static_cast<std::size_t>(y) * e.width + x];
      if (want[1] < 0) {
        ++negative;
        EXPECT_EQ(got[1], 0.0);  // negative luminance: black
        continue;
      }
      // Inside the Rec.709 triangle (its RGB >= 0) is inside the locus: exact.
      const double inv709[3][3] = {{3.2409699419045226, -1.5373831775700939, -0.4986107602930034},
                                   {-0.9692436362808796, 1.8759675015077202, 0.0415550574071756},
                                   {0.0556300796969937, -0.2039769588889765, 1.0569715142428786}};
      auto rgb709 = mul(inv709, want[0], want[1], want[2]);
      if (rgb709[0] >= 0 && rgb709[1] >= 0 && rgb709[2] >= 0) {
        ++in_rec709;
        worst_in = std::max(worst_in, rel(got, want));
      }
      // Every mapping keeps the luminance (emission: toward white at constant Y).
      if (want[1] > 0) worst_y = std::max(worst_y, std::abs(got[1] - want[1]) / want[1]);
    }
  EXPECT_EQ(rep["out_of_gamut"]["negative_luminance"].get<int>(), negative);
  EXPECT_GT(rep["out_of_gamut"]["outside_locus"].get<int>(), 0);
  EXPECT_GT(in_rec709, 100);
  EXPECT_LE(worst_in, 1e-5);
  EXPECT_LE(worst_y, 1e-5);
  EXPECT_LE(rep["max_relative_xyz_error"].get<double>(), 1e-5);  // exact to the mapped targets
}

TEST(CliImage, AcesSweepAsReflectanceCountsColoursOutsideTheSolid) {
  Scratch s;
  auto r = run(kImages + "sweep_acescg_64x32.exr -o " + (s / "sw.exr") +
               " --mode reflectance --report " + (s / "r.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Json rep = read_json(s / "r.json");
  EXPECT_EQ(rep["colorspace"], "ACEScg");
  EXPECT_GT(rep["out_of_gamut"]["outside_reflectance_solid"].get<int>(), 0);
  EXPECT_GT(rep["out_of_gamut"]["outside_locus"].get<int>(), 0);
  e2e::Exr e = e2e::read_exr(s / "sw.exr");
  for (auto& b : e2e::spectral_channels(e, "T."))
    for (int y = 0; y < e.height; ++y)
      for (int x = 0; x < e.width; ++x) {
        ASSERT_GE(e.at(x, y, b.first), 0.0f);
        ASSERT_LE(e.at(x, y, b.first), 1.0f);
      }
}

// HALF output: exact to HALF's precision (11 bits), values above 65504 clamped with a warning
// (the paper model's spectra of the lamp reach above it).
TEST(CliImage, HalfOutputWarnsAboutOverflow) {
  Scratch s;
  auto r = run(kImages + "hdri_interior_1024x512.exr --model paper -o " + (s / "i.exr") +
               " --report " + (s / "r.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("--format float"), std::string::npos) << r.err;
  Json rep = read_json(s / "r.json");
  EXPECT_GT(rep["half_overflow_pixels"].get<int>(), 0);
  EXPECT_LE(rep["mean_relative_xyz_error"].get<double>(), 1e-3);  // HALF rounding: ~2^-11
  EXPECT_EQ(e2e::exr_format(s / "i.exr"), "half");
}

// Both methods are exact; the table's spectra differ from the direct solutions only in shape.
TEST(CliImage, TableAndExactMethodsAreBothExact) {
  Scratch s;
  const std::string in = kImages + "colorchecker_srgb8.png";
  ASSERT_EQ(
      run(in + " -o " + (s / "t.exr") + " --format float --report " + (s / "t.json")).exit_code, 0);
  ASSERT_EQ(
      run(in + " -o " + (s / "x.exr") + " --format float --method exact --report " + (s / "x.json"))
          .exit_code,
      0);
  EXPECT_LE(read_json(s / "t.json")["max_relative_xyz_error"].get<double>(), 1e-5);
  EXPECT_LE(read_json(s / "x.json")["max_relative_xyz_error"].get<double>(), 1e-5);
  e2e::Exr t = e2e::read_exr(s / "t.exr"), x = e2e::read_exr(s / "x.exr");
  auto bands = e2e::spectral_channels(t, "T.");
  double sum2 = 0, ref2 = 0, worst = 0;
  for (int yy = 0; yy < t.height; ++yy)
    for (int xx = 0; xx < t.width; ++xx)
      for (auto& b : bands) {
        double d = t.at(xx, yy, b.first) - x.at(xx, yy, b.first);
        sum2 += d * d;
        ref2 += x.at(xx, yy, b.first) * x.at(xx, yy, b.first);
        worst = std::max(worst, std::abs(d));
      }
  const double rms = std::sqrt(sum2 / ref2);
  std::printf(
      "  table vs exact on the ColorChecker: relative RMS spectral difference %.3f, "
      "largest sample difference %.3f\n",
      rms, worst);
  EXPECT_GT(rms, 0.0);  // they are different spectra of the same colours...
  EXPECT_LT(rms, 1.0);  // ...of comparable shape
}

TEST(CliImage, OutputDoesNotDependOnTheThreadCount) {
  Scratch s;
  const std::string in = kImages + "hdri_forest_256x128.exr";
  ASSERT_EQ(run(in + " -o " + (s / "1.exr") + " --threads 1").exit_code, 0);
  ASSERT_EQ(run(in + " -o " + (s / "2.exr") + " --threads 2").exit_code, 0);
  ASSERT_EQ(run(in + " -o " + (s / "8.exr") + " --threads 8").exit_code, 0);
  e2e::Exr a = e2e::read_exr(s / "1.exr"), b = e2e::read_exr(s / "2.exr"),
           c = e2e::read_exr(s / "8.exr");
  EXPECT_EQ(a.pixels, b.pixels);
  EXPECT_EQ(a.pixels, c.pixels);
}

TEST(CliImage, CacheIsReusedAndCorruptCachesAreRebuilt) {
  Scratch s;
  const std::string in = kImages + "hdri_forest_256x128.exr";
  const std::string cache = s / "cache";
  ASSERT_EQ(run(in + " -o " + (s / "a.exr") + " --cache " + cache + " --report " + (s / "a.json"))
                .exit_code,
            0);
  ASSERT_EQ(run(in + " -o " + (s / "b.exr") + " --cache " + cache + " --report " + (s / "b.json"))
                .exit_code,
            0);
  Json a = read_json(s / "a.json"), b = read_json(s / "b.json");
  EXPECT_GT(a["cache"]["nodes_computed"].get<int>(), 0);
  EXPECT_EQ(b["cache"]["nodes_computed"].get<int>(), 0);
  EXPECT_EQ(b["cache"]["nodes_reused"], a["cache"]["nodes_computed"]);
  EXPECT_EQ(b["cache"]["status"], "loaded");
  EXPECT_EQ(e2e::read_exr(s / "a.exr").pixels, e2e::read_exr(s / "b.exr").pixels);
  // Corrupt the cache file (flip a byte in the middle), then truncate it: detected, rebuilt.
  const std::string file = b["cache"]["file"];
  {
    std::fstream f(file, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(fs::file_size(file) / 2));
    f.put('\x5a');
  }
  auto r = run(in + " -o " + (s / "c.exr") + " --cache " + cache + " --report " + (s / "c.json"));
  ASSERT_EQ(r.exit_code, 0);
  EXPECT_NE(r.err.find("ignored and rebuilt"), std::string::npos) << r.err;
  EXPECT_GT(read_json(s / "c.json")["cache"]["nodes_computed"].get<int>(), 0);
  EXPECT_EQ(e2e::read_exr(s / "a.exr").pixels, e2e::read_exr(s / "c.exr").pixels);
  fs::resize_file(file, 100);
  r = run(in + " -o " + (s / "d.exr") + " --cache " + cache);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.err.find("ignored and rebuilt"), std::string::npos) << r.err;
  // A foreign cache (an intact table made for a 10 nm grid) under this run's name: rejected.
  const std::string other = s / "other";
  ASSERT_EQ(run(in + " -o " + (s / "e.exr") + " --wavelengths 380:780:10 --cache " + other +
                " --report " + (s / "e.json"))
                .exit_code,
            0);
  fs::copy_file(read_json(s / "e.json")["cache"]["file"].get<std::string>(), file,
                fs::copy_options::overwrite_existing);
  r = run(in + " -o " + (s / "f.exr") + " --cache " + cache);
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.err.find("made for other settings"), std::string::npos) << r.err;
  EXPECT_EQ(e2e::read_exr(s / "a.exr").pixels, e2e::read_exr(s / "f.exr").pixels);
}

TEST(CliImage, TiledOutputHasTheSamePixels) {
  Scratch s;
  const std::string in = kImages + "hdri_sunset_256x128.hdr";  // Radiance input, too
  ASSERT_EQ(run(in + " -o " + (s / "s.exr")).exit_code, 0);
  ASSERT_EQ(run(in + " -o " + (s / "t.exr") + " --tile 64 --compression piz").exit_code, 0);
  e2e::Exr a = e2e::read_exr(s / "s.exr"), b = e2e::read_exr(s / "t.exr");
  EXPECT_FALSE(a.tiled);
  EXPECT_TRUE(b.tiled);
  EXPECT_EQ(a.pixels, b.pixels);
}

// Every lossless OpenEXR compression (scanlines written in parallel blocks) stores the same
// samples, with the same attributes; zip's level is honoured (level 1 larger than level 9);
// lossy ones are written and read back. Independent oracle: OIIO reading the files.
TEST(CliImage, EveryCompressionWritesTheSameSamples) {
  Scratch s;
  const std::string in = kImages + "hdri_forest_256x128.exr";
  ASSERT_EQ(run(in + " -o " + (s / "ref.exr") + " -q").exit_code, 0);
  const e2e::Exr ref = e2e::read_exr(s / "ref.exr");
  ASSERT_FALSE(ref.pixels.empty());
  // OpenEXR 3.4's lossless HTJ2K too, where the binary's OpenEXR has it; refused before.
  std::smatch v;
  const std::string version = run("--version").out;
  ASSERT_TRUE(std::regex_search(version, v, std::regex("OpenEXR ([0-9]+)\\.([0-9]+)"))) << version;
  const bool htj2k = std::stoi(v[1]) > 3 || (std::stoi(v[1]) == 3 && std::stoi(v[2]) >= 4);
  std::vector<std::string> lossless = {"none",  "rle", "zips",  "zip:1",
                                       "zip:9", "piz", "pxr24", "zips:2"};
  for (const char* c : {"htj2k256", "htj2k32"}) {
    if (htj2k) {
      lossless.push_back(c);
    } else {
      const auto r = run(in + " -o " + (s / "h.exr") + " -q --compression " + c);
      EXPECT_EQ(r.exit_code, 2) << r.err;
      EXPECT_NE(r.err.find(c), std::string::npos) << r.err;
    }
  }
  for (const std::string& c : lossless) {
    SCOPED_TRACE(c);
    const std::string out = s / ("c_" + c + ".exr");
    ASSERT_EQ(run(in + " -o " + out + " -q --compression " + c).exit_code, 0);
    const e2e::Exr e = e2e::read_exr(out);
    EXPECT_EQ(e.pixels, ref.pixels);
    auto attributes = e.attributes, want = ref.attributes;
    for (const char* differs : {"compression", "DateTime"}) {
      attributes.erase(differs);
      want.erase(differs);
    }
    EXPECT_EQ(attributes, want);
  }
  // HTJ2K files read back by spectralize's own reader (the plugin's): the RGB of the zip file.
  if (htj2k) {
    ASSERT_EQ(run("--to-rgb " + (s / "ref.exr") + " -o " + (s / "ref_rgb.exr") + " -q").exit_code,
              0);
    for (const std::string c : {"htj2k256", "htj2k32"}) {
      const std::string rgb = s / ("rgb_" + c + ".exr");
      ASSERT_EQ(run("--to-rgb " + (s / ("c_" + c + ".exr")) + " -o " + rgb + " -q").exit_code, 0);
      EXPECT_EQ(e2e::read_exr(rgb).pixels, e2e::read_exr(s / "ref_rgb.exr").pixels) << c;
    }
  }
  EXPECT_GT(fs::file_size(s / "c_zip:1.exr"), fs::file_size(s / "c_zip:9.exr"));
  EXPECT_GT(fs::file_size(s / "c_none.exr"), fs::file_size(s / "c_zip:1.exr"));
  for (const char* c : {"b44", "dwaa:45", "dwab"}) {
    SCOPED_TRACE(c);
    const std::string out = s / (std::string("l_") + c + ".exr");
    ASSERT_EQ(run(in + " -o " + out + " -q --compression " + c).exit_code, 0);
    const e2e::Exr e = e2e::read_exr(out);
    ASSERT_EQ(e.pixels.size(), ref.pixels.size());
  }
}

// Rows wider than OIIO's own 16 MB scanline chunks allow a block of (4096 x 84 float channels:
// 1.4 MB per row, 11 rows per chunk, 16 per ZIP block): the parallel block writer's output
// holds exactly the samples of a tiled write (which OIIO writes itself), for every row,
// including the last partial block.
TEST(CliImage, WideScanlineFileEqualsTheTiledOne) {
  Scratch s;
  ASSERT_EQ(std::system(("oiiotool " + kImages + "hdri_forest_256x128.exr --resize 4096x69 -o " +
                         (s / "wide.exr") + " >/dev/null 2>&1")
                            .c_str()),
            0);
  const std::string args = " --format float -q --threads 2";
  ASSERT_EQ(run(s / "wide.exr" + " -o " + (s / "s.exr") + args).exit_code, 0);
  ASSERT_EQ(run(s / "wide.exr" + " -o " + (s / "t.exr") + args + " --tile 64").exit_code, 0);
  const e2e::Exr a = e2e::read_exr(s / "s.exr"), b = e2e::read_exr(s / "t.exr");
  ASSERT_EQ(a.width, 4096);
  ASSERT_EQ(a.height, 69);
  EXPECT_FALSE(a.tiled);
  EXPECT_EQ(a.pixels, b.pixels);
}

TEST(CliImage, GreyAndSixteenBitInputs) {
  Scratch s;
  ASSERT_EQ(run(kImages + "grey_ramp8.png -o " + (s / "g.exr")).exit_code, 0);
  e2e::Exr g = e2e::read_exr(s / "g.exr");
  // A grey input gives a neutral preview: R = G = B to HALF precision.
  for (int x = 0; x < g.width; ++x) {
    EXPECT_NEAR(g.at(x, 3, 0), g.at(x, 3, 1), 2e-3 * std::max(0.01f, g.at(x, 3, 1)) + 1e-4);
  }
  auto r =
      run(kImages + "colorchecker_srgb16.png -o " + (s / "c.exr") + " --report " + (s / "r.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_json(s / "r.json")["mode"], "reflectance");
}

// Truth: the previews are the round trip of the input, whatever the reference illuminant: a
// grey surface under A (a warm light) is still grey in the preview, at its own linear level
// (the sRGB decoding of the 8-bit value, computed here), because the white balance to A is
// undone for the preview (docs/DESIGN.md §3).
TEST(CliImage, PreviewsAreTheInputUnderAnyReferenceIlluminant) {
  Scratch s;
  for (const char* illuminant : {"A", "FL11", "D50"}) {
    SCOPED_TRACE(illuminant);
    ASSERT_EQ(run(kImages + "grey_ramp8.png -o " + (s / "g.exr") +
                  " --format float -q --illuminant " + illuminant)
                  .exit_code,
              0);
    const e2e::Exr g = e2e::read_exr(s / "g.exr");
    auto in = OIIO::ImageInput::open(kImages + "grey_ramp8.png");
    ASSERT_TRUE(in);
    std::vector<unsigned char> px(static_cast<std::size_t>(in->spec().width) * in->spec().height *
                                  in->spec().nchannels);
    ASSERT_TRUE(in->read_image(0, 0, 0, in->spec().nchannels, OIIO::TypeUInt8, px.data()));
    for (int x = 0; x < g.width; x += 3) {
      const double v = px[static_cast<std::size_t>(3 * g.width + x) * in->spec().nchannels] / 255.0;
      const double linear = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(g.at(x, 3, c), linear, 1e-4 + 1e-4 * linear) << x;
      }
    }
  }
}

struct BadImage {
  const char* name;
  std::string args;  // {in} and {dir} are replaced
  int exit_code;
  const char* expected;  // part of the message
};

class CliImageBad : public ::testing::TestWithParam<BadImage> {};

TEST_P(CliImageBad, FailsWithAMessageAndLeavesNothing) {
  Scratch s;
  // Inputs that are not images.
  {
    std::ofstream(s / "random.png") << "this is not a PNG at all, just bytes";
    std::ofstream(s / "empty.exr");
    std::ifstream src(kImages + "hdri_sunset_256x128.exr", std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(src)), std::istreambuf_iterator<char>());
    std::ofstream(s / "truncated.exr", std::ios::binary) << bytes.substr(0, bytes.size() / 3);
  }
  auto before = s.files();
  std::string args = GetParam().args;
  args = std::regex_replace(args, std::regex("\\{in\\}"), kImages + "hdri_sunset_256x128.exr");
  args = std::regex_replace(args, std::regex("\\{dir\\}"), s.dir.string());
  auto r = run(args);
  EXPECT_EQ(r.exit_code, GetParam().exit_code) << args << "\n" << r.err;
  EXPECT_NE(r.err.find("spectralize ERROR"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(GetParam().expected), std::string::npos) << args << "\n" << r.err;
  EXPECT_EQ(s.files(), before) << "something was left behind";
}

INSTANTIATE_TEST_SUITE_P(
    Cases, CliImageBad,
    ::testing::Values(
        BadImage{"Missing", "{dir}/nope.exr -o {dir}/o.exr", 1, "no such file"},
        BadImage{"Directory", "{dir} -o {dir}/o.exr", 1, "is a directory"},
        BadImage{"RandomBytes", "{dir}/random.png -o {dir}/o.exr", 1, "random.png"},
        BadImage{"Empty", "{dir}/empty.exr -o {dir}/o.exr", 1, "empty.exr"},
        BadImage{"Truncated", "{dir}/truncated.exr -o {dir}/o.exr", 1, "truncated.exr"},
        BadImage{"MissingFolder", "{in} -o {dir}/no/such/o.exr", 1, "does not exist"},
        BadImage{"OutputIsInput", "{dir}/truncated.exr -o {dir}/truncated.exr", 1, "refusing"},
        BadImage{"NotExr", "{in} -o {dir}/o.png", 2, "(.exr)"},
        BadImage{"NoOutput", "{in}", 2, "-o OUTPUT.exr is required"},
        BadImage{"TwoInputs", "{in} {in} -o {dir}/o.exr", 2, "one input image"},
        BadImage{"Format", "{in} -o {dir}/o.exr --format double", 2, "--format: 'double'"},
        BadImage{"Compression", "{in} -o {dir}/o.exr --compression lzma", 2,
                 "--compression: 'lzma'"},
        BadImage{"Tile", "{in} -o {dir}/o.exr --tile 7", 2, "--tile: '7'"},
        BadImage{"TileText", "{in} -o {dir}/o.exr --tile big", 2, "--tile: 'big'"},
        BadImage{"Method", "{in} -o {dir}/o.exr --method fast", 2, "--method: 'fast'"},
        BadImage{"Threads", "{in} -o {dir}/o.exr --threads -2", 2, "--threads: '-2'"},
        BadImage{"Mode", "{in} -o {dir}/o.exr --mode glow", 2, "--mode: 'glow'"},
        BadImage{"Space", "{in} -o {dir}/o.exr --colorspace Nope", 2,
                 "unknown colour space 'Nope'"},
        BadImage{"Grid", "{in} -o {dir}/o.exr --wavelengths 700:400:5", 2, "reversed"}),
    [](const auto& info) { return info.param.name; });

// Truth (the guide's "Files and guarantees" (docs/guide/files.md)): a tiled input streams in the
// memory of a scanline one, whatever its tile size: the strips follow the output's blocks, and only
// the current row of input tiles (input channels only) is kept. Oracle: peak RSS of the same image
// stored both ways.
TEST(CliImage, TiledInputsStreamInTheMemoryOfScanlineOnes) {
#ifdef SPECTRALIZE_SANITIZED
  GTEST_SKIP() << "peak memory is not meaningful under sanitizers (shadow memory)";
#endif
  Scratch s;
  const std::string scan = s / "scan.exr", tiled = s / "tiled.exr";
  const std::string make = "oiiotool " + kImages + "hdri_interior_1024x512.exr --resize 4096x256 ";
  ASSERT_EQ(std::system((make + "-o " + scan + " >/dev/null 2>&1").c_str()), 0);
  ASSERT_EQ(std::system((make + "--tile 256 256 -o " + tiled + " >/dev/null 2>&1").c_str()), 0);
  const auto peak = [&](const std::string& in) {
    const e2e::Measured m = e2e::run_measured(std::string(SPECTRALIZE_BINARY) + " " + in + " -o " +
                                              (s / "o.exr") + " -q --threads 2");
    EXPECT_EQ(m.exit_code, 0) << in;
    return m.peak_mb;
  };
  const double scan_mb = peak(scan), tiled_mb = peak(tiled);
  std::printf("  4096x256: scanline input %.0f MB, 256-pixel tiles %.0f MB peak RSS\n", scan_mb,
              tiled_mb);
  // One row of 256-pixel tiles of RGB as float, 4096 x 256 x 3 x 4 B = 12 MB, and OIIO's HALF
  // copy while reading it, 6 MB. Strips aligned to those tiles would hold two 256-row output
  // strips of 84 HALF channels: 350 MB.
  EXPECT_LE(tiled_mb, scan_mb + 40.0);
}

// Memory does not depend on how the input is stored: every OpenEXR compression and sample type
// streams in the memory of a zip-compressed float map. OpenEXR decodes whole chunks (256 rows
// for DWAB, 32 for PIZ, B44 and DWAA, 16 for zip) and, read through OIIO, kept 2 per OpenEXR
// thread of them: a 2048-wide float DWAB map held 4 x 6 MB on two cores (100 MB at 8192 wide,
// an 8K DWAB map peaked at 538 MB against 446 for zip). The reader keeps at most 16 MB of
// them, so the bound is the zip map's peak + 12 MB (one 6 MB DWAB chunk and its decoder's
// buffers, and a few MB of RSS noise), at any width the same margin in proportion. Oracle:
// peak RSS of the same image stored each way.
TEST(CliImage, InputCompressionAndSampleTypeDoNotChangePeakMemory) {
#ifdef SPECTRALIZE_SANITIZED
  GTEST_SKIP() << "peak memory is not meaningful under sanitizers (shadow memory)";
#endif
  Scratch s;
  // One chunk size per kind of codec (16, 32 and 256 rows), both sample types.
  const std::vector<std::pair<std::string, std::string>> stored = {
      {"float", "zip"}, {"float", "piz"}, {"float", "dwab"}, {"half", "b44"}, {"half", "dwab"}};
  std::string make = "oiiotool " + kImages + "hdri_interior_1024x512.exr --resize 2048x1024";
  for (const auto& [type, compression] : stored)
    make += " -d " + type + " --compression " + compression + " -o " +
            (s / (type + "_" + compression + ".exr"));
  ASSERT_EQ(std::system((make + " >/dev/null 2>&1").c_str()), 0);
  // Few bands and no output compression: the input's share of the memory is what is measured.
  // The smaller of two runs: peak RSS of one run varies by ~7 MB on a busy machine (threads'
  // timing), always upwards.
  const auto peak = [&](const std::string& type, const std::string& compression) {
    double least = 0;
    for (int run = 0; run < 2; ++run) {
      const e2e::Measured m = e2e::run_measured(
          std::string(SPECTRALIZE_BINARY) + " " + (s / (type + "_" + compression + ".exr")) +
          " -o " + (s / "o.exr") + " -q --threads 2 --wavelengths 400:700:100 --compression none");
      EXPECT_EQ(m.exit_code, 0) << type << " " << compression;
      least = run == 0 ? m.peak_mb : std::min(least, m.peak_mb);
    }
    return least;
  };
  const double zip = peak("float", "zip");
  for (std::size_t i = 1; i < stored.size(); ++i) {
    const auto& [type, compression] = stored[i];
    const double mb = peak(type, compression);
    std::printf("  2048x1024 %s %s: %.0f MB peak RSS (float zip: %.0f MB)\n", type.c_str(),
                compression.c_str(), mb, zip);
    EXPECT_LE(mb, zip + 12.0) << type << " " << compression;
  }
}

// Streaming: an 8192x4096 map at 81 bands (5.6 GB of HALF samples, written in parallel
// compression blocks) in <= 500 MB peak RSS (the OIIO libraries alone take ~130 MB), with no
// page-fault storm (minor faults: first touches of the buffers, not a fault per row), and the
// last rows of the file exact.
TEST(CliImageSlow, LargeMapRunsInBoundedMemory) {
#ifdef SPECTRALIZE_SANITIZED
  GTEST_SKIP() << "peak memory is not meaningful under sanitizers (shadow memory)";
#endif
  Scratch s;
  const std::string big = s / "big.exr";
  ASSERT_EQ(
      std::system(("oiiotool " + kImages + "hdri_interior_1024x512.exr --resize 8192x4096 -o " +
                   big + " >/dev/null 2>&1")
                      .c_str()),
      0);
  const std::string cmd =
      std::string(SPECTRALIZE_BINARY) + " " + big + " -o " + (s / "o.exr") + " -q";
  const e2e::Measured m = e2e::run_measured(cmd);
  EXPECT_EQ(m.exit_code, 0);
  std::printf("  8192x4096 -> 81 bands: peak RSS %.0f MB, %.0f s, %ld minor faults\n", m.peak_mb,
              m.seconds, m.minor_faults);
  EXPECT_LE(m.peak_mb, 500.0);
  EXPECT_LT(m.minor_faults, 400000);  // 4.3 million when OIIO converted each chunk
  int width = 0;
  EXPECT_EQ(e2e::exr_format(s / "o.exr", &width), "half");
  EXPECT_EQ(width, 8192);
}

}  // namespace
