// The input reader (imagefile/image_reader.h) on small files written here by OpenImageIO:
// scanline and tiled OpenEXR, tiled TIFF and PNG give their spec and, in strips of any size and
// order (across tile rows, back again), exactly the samples written; a MIP-mapped file reads as
// its level 0 and counts its levels, a multi-page TIFF counts its pages and reads the first;
// straight alpha is kept when asked (the colour of a transparent pixel survives) and
// associated otherwise; strips align to the tile height. Missing files, folders, FIFOs, foreign
// bytes, declared sizes beyond the documented limits and unreadable rows are refused naming
// the file. Oracles: the samples and specs written, 8 and 16-bit encodings (v / 255, v / 65535),
// ImageLimits' documented values.

#include "imagefile/image_reader.h"

#include <ImfChannelList.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "file_test_support.h"
#include "spectralize/core/error.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

struct TempDir : test::TempDir {
  TempDir() : test::TempDir("image_reader") {}
};

// A sample of pixel (x, y), channel c, distinct everywhere and exact in every type used here
// (a multiple of 1/8 below 256: half, float; uint8 and uint16 take their own codes).
float sample(int x, int y, int c) {
  return static_cast<float>((x * 3 + y * 17 + c * 5) % 256) / 8.0f;
}
unsigned char code8(int x, int y, int c) {
  return static_cast<unsigned char>((x * 7 + y * 13 + c * 50) % 256);
}
unsigned short code16(int x, int y, int c) {
  return static_cast<unsigned short>((x * 701 + y * 1301 + c * 5003) % 65536);
}

// The samples of a whole image, row by row, as float (what read_rows returns).
std::vector<float> expected(const OIIO::ImageSpec& spec) {
  std::vector<float> out;
  for (int y = 0; y < spec.height; ++y)
    for (int x = 0; x < spec.width; ++x)
      for (int c = 0; c < spec.nchannels; ++c)
        out.push_back(spec.format == OIIO::TypeUInt8    ? code8(x, y, c) / 255.0f
                      : spec.format == OIIO::TypeUInt16 ? code16(x, y, c) / 65535.0f
                                                        : sample(x, y, c));
  return out;
}

// Writes one image (subimage or MIP level) of `spec` with the pattern above.
void write_pattern(OIIO::ImageOutput& out, const std::string& path, const OIIO::ImageSpec& spec,
                   OIIO::ImageOutput::OpenMode mode = OIIO::ImageOutput::Create) {
  ASSERT_TRUE(out.open(path, spec, mode)) << out.geterror();
  if (spec.format == OIIO::TypeUInt8 || spec.format == OIIO::TypeUInt16) {
    std::vector<unsigned short> px16;
    std::vector<unsigned char> px8;
    for (int y = 0; y < spec.height; ++y)
      for (int x = 0; x < spec.width; ++x)
        for (int c = 0; c < spec.nchannels; ++c) {
          px8.push_back(code8(x, y, c));
          px16.push_back(code16(x, y, c));
        }
    ASSERT_TRUE(spec.format == OIIO::TypeUInt8 ? out.write_image(OIIO::TypeUInt8, px8.data())
                                               : out.write_image(OIIO::TypeUInt16, px16.data()))
        << out.geterror();
  } else {
    const std::vector<float> px = expected(spec);
    ASSERT_TRUE(out.write_image(OIIO::TypeFloat, px.data())) << out.geterror();
  }
}

void write_file(const std::string& path, const OIIO::ImageSpec& spec) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << OIIO::geterror();
  write_pattern(*out, path, spec);
  ASSERT_TRUE(out->close()) << out->geterror();
}

// Rows [y0, y1) of `all` (width x channels per row).
std::vector<float> rows_of(const std::vector<float>& all, const OIIO::ImageSpec& spec, int y0,
                           int y1) {
  const std::size_t row = static_cast<std::size_t>(spec.width) * spec.nchannels;
  return {all.begin() + y0 * row, all.begin() + y1 * row};
}

// Reads the strips (y0, y1) in the order given and checks each against the samples written.
void expect_strips(ImageReader& r, const OIIO::ImageSpec& written,
                   const std::vector<std::pair<int, int>>& strips) {
  const std::vector<float> all = expected(written);
  for (const auto& [y0, y1] : strips) {
    SCOPED_TRACE("rows " + std::to_string(y0) + ".." + std::to_string(y1 - 1));
    std::vector<float> got(static_cast<std::size_t>(y1 - y0) * written.width * written.nchannels,
                           -1.0f);
    r.read_rows(y0, y1, got.data());
    const std::vector<float> want = rows_of(all, written, y0, y1);
    if (written.format == OIIO::TypeUInt8 || written.format == OIIO::TypeUInt16) {
      // Integer codes: within float rounding of code / (2^bits - 1), far below one code step.
      ASSERT_EQ(got.size(), want.size());
      double worst = 0;
      for (std::size_t i = 0; i < got.size(); ++i)
        worst = std::max(worst, static_cast<double>(std::abs(got[i] - want[i])));
      EXPECT_LE(worst, 1e-6);
    } else {
      EXPECT_EQ(got, want);  // half and float: bit for bit
    }
  }
}

TEST(ImageReader, ScanlineOpenExrGivesItsSpecAndTheSamplesWrittenInAnyStrips) {
  TempDir t;
  const std::string path = t / "scan.exr";
  for (const OIIO::TypeDesc& type : {OIIO::TypeFloat, OIIO::TypeHalf}) {
    SCOPED_TRACE(type.c_str());
    // R, G, B first: the order OIIO gives OpenEXR channels in.
    OIIO::ImageSpec spec =
        test::spec_of({"R", "G", "B", "S0.400,000000nm", "S0.550,000000nm"}, type, 37, 50);
    spec.x = -3;  // a data window away from the origin: rows are counted from its top
    spec.y = 5;
    spec.attribute("compression", "zip");  // 16-row chunks: strips cut through them
    write_file(path, spec);
    ImageReader r(path, 5);
    EXPECT_EQ(r.format_name(), "openexr");
    EXPECT_EQ(r.spec().width, 37);
    EXPECT_EQ(r.spec().height, 50);
    EXPECT_EQ(r.spec().x, -3);
    EXPECT_EQ(r.spec().y, 5);
    EXPECT_EQ(r.spec().channelnames, spec.channelnames);
    EXPECT_EQ(r.spec().format, type);
    EXPECT_EQ(r.tile_height(), 0);
    EXPECT_EQ(r.mip_levels(), 1);
    EXPECT_EQ(r.subimages(), 1);
    EXPECT_FALSE(r.straight_alpha());
    // Scanlines: any strip reads efficiently.
    EXPECT_EQ(r.aligned_rows(7), 7);
    EXPECT_EQ(r.aligned_rows(0), 1);
    expect_strips(r, spec, {{0, 7}, {7, 23}, {23, 50}, {3, 4}, {0, 50}});
  }
}

TEST(ImageReader, TiledFilesReadInStripsAcrossTileRowsAndBack) {
  TempDir t;
  // 37 x 50 in 16 x 16 tiles: partial tiles at the right and the bottom.
  for (const auto& [name, type] :
       {std::pair<std::string, OIIO::TypeDesc>{"tiled.exr", OIIO::TypeFloat},
        {"tiled.tif", OIIO::TypeUInt16}}) {
    SCOPED_TRACE(name);
    OIIO::ImageSpec spec = test::spec_of({"R", "G", "B"}, type, 37, 50);
    spec.tile_width = spec.tile_height = 16;
    const std::string path = t / name;
    write_file(path, spec);
    ImageReader r(path, 3);
    EXPECT_EQ(r.tile_height(), 16);
    EXPECT_EQ(r.spec().width, 37);
    EXPECT_EQ(r.spec().height, 50);
    // Strips are whole rows of tiles, at least as many rows as wanted.
    EXPECT_EQ(r.aligned_rows(1), 16);
    EXPECT_EQ(r.aligned_rows(16), 16);
    EXPECT_EQ(r.aligned_rows(17), 32);
    EXPECT_EQ(r.aligned_rows(0), 16);
    expect_strips(r, spec, {{10, 20}, {0, 5}, {45, 50}, {20, 45}, {15, 17}, {0, 50}});
  }
}

TEST(ImageReader, AMipMappedFileReadsAsItsLevelZeroAndCountsItsLevels) {
  TempDir t;
  // A texture as maketx makes one: tiled, MIP-mapped (32x16, 16x8, 8x4, 4x2, 2x1, 1x1).
  const OIIO::ImageSpec spec = test::spec_of({"R", "G", "B"}, OIIO::TypeUInt16, 32, 16);
  const std::string source = t / "source.tif", path = t / "mip.tx";
  write_file(source, spec);
  OIIO::ImageSpec config;
  config.tile_width = config.tile_height = 16;  // TIFF's tiles are multiples of 16
  ASSERT_TRUE(
      OIIO::ImageBufAlgo::make_texture(OIIO::ImageBufAlgo::MakeTxTexture, source, path, config))
      << OIIO::geterror();
  ImageReader r(path, 3);
  EXPECT_EQ(r.mip_levels(), 6);
  EXPECT_EQ(r.subimages(), 1);
  EXPECT_EQ(r.spec().width, 32);
  EXPECT_EQ(r.spec().height, 16);
  EXPECT_EQ(r.tile_height(), 16);
  expect_strips(r, spec, {{0, 16}, {5, 9}, {0, 3}});
}

TEST(ImageReader, AMultiPageTiffCountsItsPagesAndReadsTheFirst) {
  TempDir t;
  const std::string path = t / "pages.tif";
  const OIIO::ImageSpec first = test::spec_of({"R", "G", "B"}, OIIO::TypeUInt8, 9, 6);
  const OIIO::ImageSpec second = test::spec_of({"R", "G", "B"}, OIIO::TypeUInt16, 4, 3);
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->supports("multiimage"));
  write_pattern(*out, path, first);
  write_pattern(*out, path, second, OIIO::ImageOutput::AppendSubimage);
  ASSERT_TRUE(out->close());
  ImageReader r(path, 3);
  EXPECT_EQ(r.format_name(), "tiff");
  EXPECT_EQ(r.subimages(), 2);
  EXPECT_EQ(r.mip_levels(), 1);
  EXPECT_EQ(r.spec().width, 9);
  EXPECT_EQ(r.spec().format, OIIO::TypeUInt8);
  expect_strips(r, first, {{0, 6}, {2, 3}});
}

TEST(ImageReader, StraightAlphaKeepsTheColourOfATransparentPixelWhenAsked) {
  TempDir t;
  const std::string path = t / "rgba.png";
  // Pixel 0 opaque, pixel 1 transparent, both of colour (200, 100, 50).
  OIIO::ImageSpec spec(2, 1, 4, OIIO::TypeUInt8);
  const unsigned char px[] = {200, 100, 50, 255, 200, 100, 50, 0};
  {
    auto out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out && out->open(path, spec)) << OIIO::geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeUInt8, px));
    ASSERT_TRUE(out->close());
  }
  const float kTol = 1e-6f;
  for (const bool straight : {true, false}) {
    SCOPED_TRACE(straight ? "straight" : "associated");
    ImageReader r(path, 4, straight);
    EXPECT_EQ(r.straight_alpha(), straight);
    EXPECT_EQ(r.format_name(), "png");
    float got[8] = {};
    r.read_rows(0, 1, got);
    for (int c = 0; c < 4; ++c)
      EXPECT_NEAR(got[c], px[c] / 255.0f, kTol) << c;  // opaque: the same either way
    EXPECT_NEAR(got[7], 0.0f, kTol);
    for (int c = 0; c < 3; ++c)  // transparent: its colour as stored, or multiplied by 0
      EXPECT_NEAR(got[4 + c], straight ? px[4 + c] / 255.0f : 0.0f, kTol) << c;
  }
  // Without an alpha channel there is nothing to keep straight.
  const std::string rgb = t / "rgb.png";
  write_file(rgb, test::spec_of({"R", "G", "B"}, OIIO::TypeUInt8, 5, 4));
  ImageReader r(rgb, 3, true);
  EXPECT_FALSE(r.straight_alpha());
  expect_strips(r, test::spec_of({"R", "G", "B"}, OIIO::TypeUInt8, 5, 4), {{0, 4}});
}

TEST(ImageReader, FilesThatAreNotImagesAreRefusedNamingTheFile) {
  TempDir t;
  test::expect_error_mentioning([&] { ImageReader(t / "missing.exr", 3); }, {t / "missing.exr"},
                                "a missing file");
  fs::create_directories(t.dir / "folder.exr");
  test::expect_error_mentioning([&] { ImageReader(t / "folder.exr", 3); }, {t / "folder.exr"},
                                "a folder");
  const std::string fifo = t / "pipe.exr";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  test::expect_error_mentioning([&] { ImageReader(fifo, 3); }, {fifo}, "a FIFO");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));  // not blocked
  std::ofstream(t / "text.png") << "not a PNG at all";
  test::expect_error_mentioning([&] { ImageReader(t / "text.png", 3); },
                                {t / "text.png", "cannot read"}, "text named .png");
}

// A header-only scanline OpenEXR of `width` x `height` FLOAT channels (OpenEXR writes the
// header and an empty offset table; the declared size is what is checked).
void write_declared_exr(const std::string& path, int width, int height, int channels) {
  Imf::Header h(width, height);
  for (int c = 0; c < channels; ++c) {
    char name[16];
    std::snprintf(name, sizeof name, "C%d", 1000 + c);
    h.channels().insert(name, Imf::Channel(Imf::FLOAT));
  }
  Imf::OutputFile out(path.c_str(), h);
}

TEST(ImageReader, DeclaredSizesBeyondTheLimitsAreRefusedBeforeAnyAllocation) {
  TempDir t;
  // Sides up to ImageLimits::kMaxSide (2^20): one more is refused, naming the file and the size.
  const std::string wide = t / "wide.exr";
  write_declared_exr(wide, (1 << 20) + 1, 1, 1);
  test::expect_error_mentioning([&] { ImageReader(wide, 1); }, {wide, "1048577x1", "limit"},
                                "a side of 2^20 + 1");
  // A side of exactly 2^20 is allowed.
  const std::string at_limit = t / "at_limit.exr";
  write_declared_exr(at_limit, 1 << 20, 1, 1);
  EXPECT_NO_THROW(ImageReader(at_limit, 1));
  // 2^17 x (2^15 + 1) = 2^32 + 2^17 pixels: each side allowed, the product beyond kMaxPixels
  // (2^32).
  const std::string many = t / "many.exr";
  write_declared_exr(many, 1 << 17, (1 << 15) + 1, 1);
  test::expect_error_mentioning([&] { ImageReader(many, 1); }, {many, "131072x32769"},
                                "2^32 + 2^17 pixels");
  // More than kMaxChannels (1024) channels: refused (by spectralize or by OIIO's own limit of
  // the same size), naming the file.
  const std::string deep = t / "channels.exr";
  write_declared_exr(deep, 1, 1, 1025);
  test::expect_error_mentioning([&] { ImageReader(deep, 1); }, {deep, "channels"}, "1025 channels");
  // One row of 1000 pixels: 3 channels are 12 KB, but 70000 float samples per pixel to write
  // would take 280 MB, beyond kMaxRowBytes (256 MB).
  const std::string row = t / "row.exr";
  write_file(row, test::spec_of({"R", "G", "B"}, OIIO::TypeHalf, 1000, 1));
  EXPECT_NO_THROW(ImageReader(row, 3));
  EXPECT_NO_THROW(ImageReader(row, 67108));  // 268,432,000 bytes: just under 256 MB
  test::expect_error_mentioning([&] { ImageReader(row, 70000); }, {row, "256 MB"},
                                "a row of 280 MB to write");
}

TEST(ImageReader, RowsThatCannotBeReadAreRefusedNamingTheFileAndTheRows) {
  TempDir t;
  for (const bool tiled : {false, true}) {
    SCOPED_TRACE(tiled ? "tiled" : "scanlines");
    OIIO::ImageSpec spec = test::spec_of({"R", "G", "B"}, OIIO::TypeFloat, 64, 64);
    spec.attribute("compression", "none");
    if (tiled) spec.tile_width = spec.tile_height = 16;
    const std::string path = t / (tiled ? "cut_tiled.exr" : "cut_scan.exr");
    write_file(path, spec);
    // The second half of the pixels is lost.
    fs::resize_file(path, fs::file_size(path) / 2);
    ImageReader r(path, 3);
    std::vector<float> rows(64 * 3 * 64);
    test::expect_error_mentioning([&] { r.read_rows(0, 64, rows.data()); },
                                  {path, "cannot read rows"}, "pixels cut short");
  }
}

}  // namespace
}  // namespace spectralize
