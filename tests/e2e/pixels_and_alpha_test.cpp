// Pixel values through the real binary (the guide's "Files and guarantees" (docs/guide/files.md),
// Pixels; the guide's "Alpha" (docs/guide/images.md)): NaN, infinite, negative and HALF-overflowing
// pixels, in images and in the spectral files
// --to-rgb reads, become finite samples, counted in the report and named in warnings; colour is
// read straight and written premultiplied by alpha, and alpha that is not finite or outside
// 0..1 is counted and clamped. The oracles are OIIO reading the outputs back, the report and the
// messages.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "exr_support.h"

namespace fs = std::filesystem;
using e2e::read_json;
using e2e::run;
using e2e::tool;
using e2e::write_exr;
using e2e::write_image;
using Json = nlohmann::json;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_pixels") {}
};

// NaN, +Inf, -Inf, negative and HALF-overflowing pixels: the job completes, the output is
// finite, the counts are right, warnings are printed.
TEST(BadPixels, BadPixelsAreCountedAndWrittenFinite) {
  Scratch s;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  write_exr(s / "bad.exr", 4, 2,
            {nan,  0.5f, 0.5f, inf,  0.5f, 0.5f, -inf, 0.5f, 0.5f, -0.2f, -0.3f, -0.1f,  // row 0
             1e6f, 1e6f, 1e6f, 0.2f, 0.3f, 0.4f, 0,    0,    0,    1,     1,     1});    // row 1
  auto r = run((s / "bad.exr") + " -o " + (s / "out.exr") + " --report " + (s / "r.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("3 pixels are NaN or infinite"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--format float"), std::string::npos) << r.err;  // HALF overflow warning
  std::ifstream f(s / "r.json");
  Json rep = Json::parse(f);
  EXPECT_EQ(rep["invalid_pixels"], 3);
  EXPECT_EQ(rep["out_of_gamut"]["negative_luminance"], 1);
  EXPECT_EQ(rep["black_pixels"], 1);
  EXPECT_EQ(rep["half_overflow_pixels"], 1);
  e2e::Exr e = e2e::read_exr(s / "out.exr");
  for (float v : e.pixels) {
    ASSERT_TRUE(std::isfinite(v));
  }
}

// Truth: --to-rgb never writes a NaN, Inf or silently clamped sample: non-finite samples become
// 0 and HALF overflow is clamped, both counted in a warning naming the file; channels that
// look spectral but do not parse are named; a file with no band where colour is defined
// (360-830 nm) is refused. Oracle: the written file read back with OIIO, and the messages.
TEST(BadPixels, ToRgbNamesWhatItCannotWrite) {
  Scratch s;
  const std::vector<std::string> bands = {"S0.400nm", "S0.500nm", "S0.600nm", "S0.700nm"};
  std::vector<float> px(4 * 2 * bands.size(), 1.0f);
  px[0] = std::numeric_limits<float>::quiet_NaN();  // pixel 0: NaN
  px[4] = std::numeric_limits<float>::infinity();   // pixel 1: +Inf
  for (int b = 0; b < 4; ++b) px[8 + b] = 1e7f;     // pixel 2: far beyond HALF
  std::vector<std::string> names = bands;
  names.push_back("S0.5x0nm");  // spectral-looking, unparseable
  std::vector<float> with_odd;
  for (std::size_t p = 0; p < 8; ++p) {
    for (std::size_t b = 0; b < 4; ++b) with_odd.push_back(px[p * 4 + b]);
    with_odd.push_back(1.0f);
  }
  write_image(s / "odd.exr", 4, 2, names, OIIO::TypeFloat, with_odd);
  auto r = run("--to-rgb " + (s / "odd.exr") + " -o " + (s / "rgb.exr"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("2 pixels have NaN or infinite samples"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("exceed HALF's range"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("S0.5x0nm"), std::string::npos) << r.err;
  const e2e::Exr out = e2e::read_exr(s / "rgb.exr");
  for (float v : out.pixels) {
    EXPECT_TRUE(std::isfinite(v));
  }
  EXPECT_LE(out.at(2, 0, out.channel("G")), 65504.0f);
  // The NaN and Inf samples count as 0: the same pixels as a file with zeros there.
  with_odd[0] = 0.0f;
  with_odd[5] = 0.0f;
  write_image(s / "zeros.exr", 4, 2, names, OIIO::TypeFloat, with_odd);
  ASSERT_EQ(run("--to-rgb " + (s / "zeros.exr") + " -q -o " + (s / "zeros_rgb.exr")).exit_code, 0);
  const e2e::Exr ref = e2e::read_exr(s / "zeros_rgb.exr");
  for (int x : {0, 1})
    for (const char* c : {"R", "G", "B"}) {
      EXPECT_EQ(out.at(x, 0, out.channel(c)), ref.at(x, 0, ref.channel(c))) << x << c;
    }
  // No band inside 360-830 nm: refused, nothing written.
  write_image(s / "ir.exr", 2, 2, {"S0.900nm", "S0.1000nm"}, OIIO::TypeFloat);
  r = run("--to-rgb " + (s / "ir.exr") + " -o " + (s / "ir_rgb.exr"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("360-830 nm"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(s / "ir_rgb.exr"));
}

// Truth (the guide's "Alpha" (docs/guide/images.md)): colour is straight in PNGs; a white 8-bit
// pixel at alpha 64/255 is a reflectance of 64/255 everywhere (a white surface covering a quarter
// of the pixel); the plugin reports no alpha for sources without one; non-finite alpha is counted
// and clamped.
TEST(Alpha, AlphaFollowsItsStatedRules) {
  Scratch s;
  std::vector<float> px;
  for (int i = 0; i < 4; ++i) px.insert(px.end(), {1, 1, 1, 64 / 255.0f});
  write_image(s / "white.png", 2, 2, {"R", "G", "B", "A"}, OIIO::TypeUInt8, px);
  auto r = run((s / "white.png") + " -o " + (s / "w.exr") + " --format float -q");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const e2e::Exr w = e2e::read_exr(s / "w.exr");
  const int a = w.channel("A");
  ASSERT_GE(a, 0);
  for (const auto& [c, nm] : e2e::spectral_channels(w, "T.")) {
    EXPECT_NEAR(w.at(1, 1, c), 64 / 255.0, 1e-5) << nm;
  }
  EXPECT_NEAR(w.at(1, 1, a), 64 / 255.0, 1e-6);
  EXPECT_NEAR(w.at(1, 1, w.channel("R")), 64 / 255.0, 1e-4);  // previews are premultiplied too
  // A source without alpha: no alpha channel, neither in the file nor through the plugin.
  std::ofstream(s / "r.spectral") << "{\"source\": \"" << kImages << "hdri_forest_256x128.exr\"}";
  auto t = tool("iinfo -v " + (s / "r.spectral"));
  ASSERT_EQ(t.exit_code, 0) << t.out;
  EXPECT_EQ(t.out.find("alpha channel"), std::string::npos) << t.out.substr(0, 400);
  // Non-finite and out-of-range alpha in an EXR: counted, written finite within 0..1.
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = INFINITY;
  write_image(s / "bad_alpha.exr", 4, 1, {"R", "G", "B", "A"}, OIIO::TypeFloat,
              {0.5f, 0.5f, 0.5f, nan, 0.5f, 0.5f, 0.5f, inf, 0.5f, 0.5f, 0.5f, 1e30f, 0.5f, 0.5f,
               0.5f, 0.5f});
  r = run((s / "bad_alpha.exr") + " -o " + (s / "ba.exr") + " --report " + (s / "ba.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(read_json(s / "ba.json")["invalid_alpha_pixels"], 3);
  EXPECT_NE(r.err.find("alpha"), std::string::npos) << r.err;
  const e2e::Exr ba = e2e::read_exr(s / "ba.exr");
  for (float v : ba.pixels) {
    ASSERT_TRUE(std::isfinite(v));
  }
  EXPECT_EQ(ba.at(0, 0, ba.channel("A")), 0.0f);
  EXPECT_EQ(ba.at(1, 0, ba.channel("A")), 1.0f);
  EXPECT_EQ(ba.at(2, 0, ba.channel("A")), 1.0f);
}

}  // namespace
