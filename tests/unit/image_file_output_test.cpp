// Whole in-memory images written to files (imagefile/image_file_output.h): OpenEXR, PNG, TIFF,
// JPEG and Radiance HDR files read back by OpenImageIO with the size, channels, sample type
// and pixels written (within the type's quantisation); the format is checked before anything
// is written, an input is never replaced, a file in the way is replaced whole and no temporary
// is left behind; the formats written through an I/O proxy are those the output table says.
// Oracles: the pixels written, the types' steps (1/255, 1/65535, half's 2^-11 relative), the
// files OIIO reads back, and the file system.

#include "imagefile/image_file_output.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "file_test_support.h"
#include "imagefile/safe_output.h"
#include "spectralize/core/error.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

struct TempDir : test::TempDir {
  TempDir() : test::TempDir("image_file_output") {}
};

constexpr int kW = 23, kH = 11;

// A float image of `channels` channels with a ramp in every colour channel, values in [0, 1];
// a fourth channel is an opaque alpha (PNG stores straight colour: OIIO divides by alpha on the
// way out and multiplies on the way in, exact only where alpha is 1).
OIIO::ImageBuf ramp(int channels) {
  OIIO::ImageSpec spec(kW, kH, channels, OIIO::TypeFloat);
  if (channels == 4) spec.alpha_channel = 3;
  OIIO::ImageBuf buf(spec);
  std::vector<float> px;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (int c = 0; c < channels; ++c)
        px.push_back(c == 3 ? 1.0f : static_cast<float>((x + 2 * y + 7 * c) % 29) / 28.0f);
  buf.set_pixels(OIIO::ROI::All(), OIIO::TypeFloat, px.data());
  return buf;
}

std::vector<float> pixels_of(const OIIO::ImageBuf& buf) {
  std::vector<float> px(static_cast<std::size_t>(kW) * kH * buf.nchannels());
  buf.get_pixels(OIIO::ROI::All(), OIIO::TypeFloat, px.data());
  return px;
}

struct ReadBack {
  OIIO::ImageSpec spec;
  std::vector<float> pixels;
};

// The file as OIIO's reader of its format reads it.
ReadBack read_back(const std::string& path) {
  ReadBack r;
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    ADD_FAILURE() << path << ": " << OIIO::geterror();
    return r;
  }
  r.spec = in->spec();
  r.pixels.resize(static_cast<std::size_t>(r.spec.image_pixels()) * r.spec.nchannels);
  EXPECT_TRUE(in->read_image(0, 0, 0, r.spec.nchannels, OIIO::TypeFloat, r.pixels.data()))
      << in->geterror();
  in->close();
  return r;
}

std::string bytes_of(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// The names in `dir` (a temporary file left behind would show here).
std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

TEST(ImageFileOutput, EachFormatReadsBackWithTheSizeTypeAndPixelsWritten) {
  TempDir t;
  struct Case {
    const char* name;
    OIIO::TypeDesc type;
    int channels;
    double tolerance;  // absolute, on values in [0, 1]
  };
  const Case cases[] = {
      {"a.exr", OIIO::TypeFloat, 4, 0},             // float: exact
      {"b.exr", OIIO::TypeHalf, 3, 1.0 / 2048},     // half: 11 significant bits
      {"c.png", OIIO::TypeUInt8, 4, 0.5 / 255},     // 8-bit codes, rounded
      {"d.png", OIIO::TypeUInt16, 3, 0.5 / 65535},  // 16-bit codes
      {"e.tif", OIIO::TypeUInt16, 3, 0.5 / 65535},  // written by name, not through a proxy
      {"f.tif", OIIO::TypeFloat, 4, 0},
      {"g.hdr", OIIO::TypeFloat, 3, 1.0 / 128},  // RGBE: 8-bit mantissas of a shared exponent
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const OIIO::ImageBuf image = ramp(c.channels);
    const std::string path = t / c.name;
    write_image_file(image, path, c.type);
    const ReadBack r = read_back(path);
    EXPECT_EQ(r.spec.width, kW);
    EXPECT_EQ(r.spec.height, kH);
    ASSERT_EQ(r.spec.nchannels, c.channels);
    if (c.channels == 4) {
      EXPECT_EQ(r.spec.alpha_channel, 3);
    }
    // The sample type asked for, where the format says which it stores (RGBE is its own).
    if (c.type != OIIO::TypeFloat || std::string(c.name) != "g.hdr") {
      EXPECT_EQ(r.spec.format, c.type) << r.spec.format.c_str();
    }
    const std::vector<float> want = pixels_of(image);
    ASSERT_EQ(r.pixels.size(), want.size());
    double worst = 0;
    for (std::size_t i = 0; i < want.size(); ++i)
      worst = std::max(worst, std::abs(static_cast<double>(r.pixels[i]) - want[i]));
    EXPECT_LE(worst, c.tolerance + 1e-6);  // and float rounding
  }
  // JPEG: lossy, 8-bit RGB; the image is there, of its size, close to what was written (a
  // smooth grey ramp: what JPEG keeps well).
  OIIO::ImageBuf image(OIIO::ImageSpec(kW, kH, 3, OIIO::TypeFloat));
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x) {
      const float v = static_cast<float>(x + y) / (kW + kH);
      const float rgb[3] = {v, v, v};
      image.setpixel(x, y, rgb);
    }
  write_image_file(image, t / "h.jpg", OIIO::TypeUInt8);
  const ReadBack r = read_back(t / "h.jpg");
  EXPECT_EQ(r.spec.width, kW);
  EXPECT_EQ(r.spec.format, OIIO::TypeUInt8);
  const std::vector<float> want = pixels_of(image);
  ASSERT_EQ(r.pixels.size(), want.size());
  double sum = 0;
  for (std::size_t i = 0; i < want.size(); ++i) sum += std::abs(r.pixels[i] - want[i]);
  EXPECT_LT(sum / want.size(), 0.02);  // a mean error of a few codes, not another image
  // Nothing but the files asked for: no temporary left behind.
  EXPECT_EQ(names_in(t.dir), (std::vector<std::string>{"a.exr", "b.exr", "c.png", "d.png", "e.tif",
                                                       "f.tif", "g.hdr", "h.jpg"}));
}

TEST(ImageFileOutput, WhatTheFormatCannotHoldIsRefusedBeforeAnythingIsWritten) {
  TempDir t;
  // PNG holds no half samples; JPEG no alpha; Radiance HDR no 16-bit codes; an unknown
  // extension names no format.
  test::expect_error_mentioning([&] { write_image_file(ramp(3), t / "a.png", OIIO::TypeHalf); },
                                {t / "a.png", "half"}, "half into PNG");
  test::expect_error_mentioning([&] { write_image_file(ramp(4), t / "b.jpg", OIIO::TypeUInt8); },
                                {t / "b.jpg"}, "alpha into JPEG");
  test::expect_error_mentioning([&] { write_image_file(ramp(3), t / "c.hdr", OIIO::TypeUInt16); },
                                {t / "c.hdr", "uint16"}, "uint16 into Radiance HDR");
  test::expect_error_mentioning(
      [&] { write_image_file(ramp(3), t / "d.nosuchformat", OIIO::TypeUInt8); },
      {t / "d.nosuchformat"}, "an unknown extension");
  EXPECT_TRUE(names_in(t.dir).empty());
}

TEST(ImageFileOutput, AnInputIsNeverReplacedAndAFileInTheWayIsReplacedWhole) {
  TempDir t;
  const std::string input = t / "input.png";
  write_image_file(ramp(3), input, OIIO::TypeUInt8);
  const std::string before = bytes_of(input);
  const std::vector<std::string> inputs = {input};
  // The input itself, and the input by another spelling.
  for (const std::string& path : {input, (t.dir / "." / "input.png").string()}) {
    SCOPED_TRACE(path);
    try {
      write_image_file(ramp(4), path, OIIO::TypeUInt8, inputs);
      ADD_FAILURE() << "an input was written over";
    } catch (const FileError& e) {
      EXPECT_NE(std::string(e.what()).find("input.png"), std::string::npos) << e.what();
    }
    EXPECT_EQ(bytes_of(input), before);
  }
  // A file in the way that is not an input: replaced by the whole new image.
  const std::string other = t / "other.png";
  std::ofstream(other) << "an old file";
  write_image_file(ramp(4), other, OIIO::TypeUInt8, inputs);
  EXPECT_EQ(read_back(other).spec.nchannels, 4);
  // A folder is never a destination.
  fs::create_directories(t.dir / "folder.png");
  test::expect_error_mentioning(
      [&] { write_image_file(ramp(3), t / "folder.png", OIIO::TypeUInt8); }, {t / "folder.png"},
      "a folder");
  EXPECT_TRUE(fs::is_directory(t.dir / "folder.png"));
  EXPECT_EQ(names_in(t.dir), (std::vector<std::string>{"folder.png", "input.png", "other.png"}));
}

TEST(ImageFileOutput, TheFormatsWrittenThroughAProxyAreTheOutputTablesFact) {
  // OpenEXR, PNG, JPEG and Radiance HDR through a proxy; TIFF by name (its writer leaves an
  // unreadable file through one); names of no format: not at all.
  for (const char* f : {"openexr", "png", "jpeg", "hdr"}) EXPECT_TRUE(writes_through_proxy(f)) << f;
  for (const char* f : {"tiff", "nosuchformat", ""}) EXPECT_FALSE(writes_through_proxy(f)) << f;
}

TEST(ImageFileOutput, TheFontFoundIsADejaVuSansFileOrNothing) {
  const std::string font = find_font();
  if (font.empty()) GTEST_SKIP() << "no DejaVu Sans in the usual folders";
  EXPECT_TRUE(fs::is_regular_file(font)) << font;
  EXPECT_EQ(fs::path(font).filename(), "DejaVuSans.ttf");
  EXPECT_TRUE(fs::path(font).is_absolute());
}

}  // namespace
}  // namespace spectralize
