// Formats that cannot hold what is asked are refused before any work, naming the format and what
// to use instead; what is accepted is what the file holds (read back with OIIO): sample types,
// compressions, tiles, float overflow named as such (docs/DESIGN.md §9). The whole matrix of
// formats x --format / --compression / --tile runs through Python (tests/python/
// test_output_formats.py); here the listed cases through the real binary.

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>

#include "cli_support.h"

namespace fs = std::filesystem;
using e2e::run;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";

struct Scratch : e2e::Scratch {
  Scratch() : e2e::Scratch("spectralize_formats") {}
};

// A small spectral EXR (emissive, 5 bands) whose samples are `value`.
std::string spectral(const Scratch& s, const std::string& name, float value) {
  const std::string path = s / name;
  OIIO::ImageSpec spec(8, 4, 5, OIIO::TypeFloat);
  spec.channelnames = {"S0.400nm", "S0.480nm", "S0.560nm", "S0.640nm", "S0.720nm"};
  std::vector<float> px(8 * 4 * 5, value);
  auto out = OIIO::ImageOutput::create(path);
  EXPECT_TRUE(out && out->open(path, spec) && out->write_image(OIIO::TypeFloat, px.data()) &&
              out->close());
  return path;
}

OIIO::ImageSpec spec_of(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  return in ? in->spec() : OIIO::ImageSpec();
}

struct Refusal {
  const char* name;
  const char* args;      // after "--to-rgb IN -o"
  const char* expected;  // in the message: the format and the alternative
};

class FormatRefusal : public ::testing::TestWithParam<Refusal> {};

// Reproductions: uint16 for .jpg/.bmp/.webp and half for .tif became uint8 / float (exit 0);
// GIF failed after the work with an empty reason. Now: exit 2 before any work, nothing left.
TEST_P(FormatRefusal, BeforeAnyWorkNamingTheFormatAndTheAlternative) {
  Scratch s;
  const std::string in = spectral(s, "in.exr", 0.5f);
  auto r = run("--to-rgb " + in + " -o " + (s / GetParam().args));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(GetParam().expected), std::string::npos) << r.err;
  EXPECT_EQ(s.files(), std::vector<std::string>{"in.exr"});  // no output, no temporary
}

INSTANTIATE_TEST_SUITE_P(
    Cases, FormatRefusal,
    ::testing::Values(
        Refusal{"JpegUint16", "o.jpg --format uint16",
                "JPEG stores uint8 samples, not uint16: use --format uint8, or write .tif, .png"},
        Refusal{"BmpUint16", "o.bmp --format uint16", "BMP stores uint8 samples, not uint16"},
        Refusal{"WebpUint16", "o.webp --format uint16", "WebP stores uint8 samples, not uint16"},
        Refusal{"TiffHalf", "o.tif --format half",
                "TIFF stores uint8 or uint16 or float samples, not half: use --format float, or "
                "write .exr for half"},
        Refusal{"PngFloat", "o.png --format float", "PNG stores uint8 or uint16 samples"},
        Refusal{"ExrUint8", "o.exr --format uint8", "OpenEXR stores half or float samples"},
        Refusal{"Gif", "o.gif", "GIF stores a palette of at most 256 colours"},
        Refusal{"Ico", "o.ico", "ICO holds icons"},
        Refusal{"PngCompressionOfJpeg", "o.png --compression jpeg:50", "PNG takes zip[:0-9]"},
        Refusal{"PngLevel", "o.png --compression zip:10", "'zip:10': the zip level"},
        Refusal{"JpegZip", "o.jpg --compression zip", "JPEG takes jpeg[:1-100]"},
        Refusal{"HdrCompression", "o.hdr --compression piz",
                "Radiance HDR has no compression to choose"},
        Refusal{"BmpCompression", "o.bmp --compression rle", "BMP has no compression to choose"},
        Refusal{"TiffJpeg", "o.tif --compression jpeg", "TIFF takes none, lzw, zip"},
        Refusal{"PngTiles", "o.png --tile 64", "PNG files are not tiled (tiles: .exr, .tif)"},
        Refusal{"WebpTiles", "o.webp --tile 64", "WebP files are not tiled"},
        Refusal{"TiffOddTiles", "o.tif --tile 40", "TIFF tiles are multiples of 16 pixels"}),
    [](const auto& info) { return info.param.name; });

// What is accepted is what the file holds: OIIO reads back the sample type, the compression
// and the tiles asked for. Reproduction: --compression for PNG was ignored.
TEST(OutputFormats, WhatIsAcceptedIsWhatTheFileHolds) {
  Scratch s;
  const std::string in = spectral(s, "in.exr", 0.5f);
  struct Case {
    std::string out, args, type, compression;
    int tile;
  };
  for (const Case& c : std::vector<Case>{
           {"a.png", "--format uint16", "uint16", "", 0},
           {"a.tif", "--format uint16 --compression lzw", "uint16", "lzw", 0},
           {"b.tif", "--format float --tile 32", "float", "zip", 32},
           {"a.exr", "--format float --compression piz --tile 16", "float", "piz", 16},
           {"a.jpg", "", "uint8", "", 0},
           {"a.hdr", "", "float", "", 0},
           {"a.dpx", "--format uint16", "uint16", "", 0}}) {
    auto r = run("--to-rgb " + in + " -o " + (s / c.out) + " -q " + c.args);
    ASSERT_EQ(r.exit_code, 0) << c.out << ": " << r.err;
    const OIIO::ImageSpec spec = spec_of(s / c.out);
    EXPECT_EQ(std::string(spec.format.c_str()), c.type) << c.out;
    if (!c.compression.empty()) {
      EXPECT_EQ(spec.get_string_attribute("compression"), c.compression) << c.out;
    }
    EXPECT_EQ(spec.tile_width, c.tile) << c.out;
  }
  // PNG's deflate level is honoured: level 0 stores, 9 compresses (file sizes).
  ASSERT_EQ(run("--to-rgb " + in + " -o " + (s / "z0.png") + " -q --compression zip:0").exit_code,
            0);
  ASSERT_EQ(run("--to-rgb " + in + " -o " + (s / "z9.png") + " -q --compression zip:9").exit_code,
            0);
  EXPECT_GT(fs::file_size(s / "z0.png"), fs::file_size(s / "z9.png"));
  // JPEG's quality too.
  const std::string photo = s / "photo.exr";
  ASSERT_EQ(run(kImages + "hdri_forest_256x128.exr -o " + photo + " -q").exit_code, 0);
  ASSERT_EQ(
      run("--to-rgb " + photo + " -o " + (s / "q10.jpg") + " -q --compression jpeg:10").exit_code,
      0);
  ASSERT_EQ(
      run("--to-rgb " + photo + " -o " + (s / "q95.jpg") + " -q --compression jpeg:95").exit_code,
      0);
  EXPECT_LT(fs::file_size(s / "q10.jpg"), fs::file_size(s / "q95.jpg"));
}

// Reproduction: --tile 4096 (the documented maximum) always failed inside OpenEXR for spectral
// outputs (a 4096 x 4096 tile of 84 half channels is 2.7 GB, beyond OpenEXR's 2 GB per tile).
// Now refused before any work with the largest tile that fits; RGB outputs take 4096.
TEST(OutputFormats, TilesBeyondOpenExrsLimitAreRefusedBeforeAnyWork) {
  Scratch s;
  fs::copy_file(kImages + "hdri_sunset_256x128.exr", s / "in.exr");
  auto r = run((s / "in.exr") + " -o " + (s / "o.exr") + " --tile 4096");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("OpenEXR holds at most 2 GB per tile: use --tile 2048 or less"),
            std::string::npos)
      << r.err;
  EXPECT_EQ(s.files(), std::vector<std::string>{"in.exr"});
  // A tile that fits is written as asked (few bands: a small tile buffer).
  r = run((s / "in.exr") + " -o " + (s / "o.exr") + " -q --tile 512 --wavelengths 400:700:100");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(spec_of(s / "o.exr").tile_width, 512);
  const std::string in = spectral(s, "rgb_in.exr", 0.5f);
  r = run("--to-rgb " + in + " -o " + (s / "rgb.exr") + " -q --tile 4096");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(spec_of(s / "rgb.exr").tile_width, 4096);
}

// Reproduction: float output of samples near float's limit advised "use --format float".
// Oracle: the samples (3e38 in every band) integrate beyond float's range.
TEST(OutputFormats, FloatOverflowIsNamedAsSuch) {
  Scratch s;
  const std::string in = spectral(s, "bright.exr", 3e38f);
  auto r =
      run("--to-rgb " + in + " -o " + (s / "f.exr") + " --format float --report " + (s / "r.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("32 pixels exceed float's range"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("use --format float"), std::string::npos) << r.err;
  const auto rep = nlohmann::json::parse(e2e::slurp(s / "r.json"));
  EXPECT_EQ(rep["float_overflow_pixels"], 32);
  EXPECT_EQ(rep["half_overflow_pixels"], 0);
  auto in_px = OIIO::ImageInput::open(s / "f.exr");
  std::vector<float> px(8 * 4 * 3);
  ASSERT_TRUE(in_px && in_px->read_image(0, 0, 0, 3, OIIO::TypeFloat, px.data()));
  for (float v : px) {
    EXPECT_TRUE(std::isfinite(v)) << v;  // clamped, never inf or NaN
  }
  // Half output of the same: HALF's range, and the advice that fits.
  r = run("--to-rgb " + in + " -o " + (s / "h.exr") + " --format half");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("exceed HALF's range (65504) and were clamped; use --format float"),
            std::string::npos)
      << r.err;
}

// Plots and spectral outputs consult the same table before any drawing or conversion.
TEST(OutputFormats, PlotsAndSpectralOutputsAreCheckedToo) {
  Scratch s;
  auto r = run("--color 0.2,0.4,0.6 -o " + (s / "p.gif"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("GIF stores a palette"), std::string::npos) << r.err;
  r = run("--color 0.2,0.4,0.6 -o " + (s / "p.zfile"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("Zfile holds one depth channel"), std::string::npos) << r.err;
  fs::copy_file(kImages + "hdri_sunset_256x128.exr", s / "in.exr");
  r = run((s / "in.exr") + " -o " + (s / "o.exr") + " --compression jpeg:90");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("OpenEXR takes none, rle, zips[:1-9], zip[:1-9], piz"), std::string::npos)
      << r.err;
  EXPECT_EQ(s.files(), std::vector<std::string>{"in.exr"});
}

}  // namespace
