// The OpenEXR header reader and the scanline structure check (imagefile/exr_header.h): the string
// and double attributes of files written here by OpenEXR and by OpenImageIO read back exactly
// (every string, every double bit for bit, nothing of other types), also from headers far beyond
// the first read and from files whose pixels are cut short; the extents of the values are where the
// file's bytes hold them; a missing, truncated, multi-part, foreign, oversized or malformed file, a
// folder and a FIFO give nothing at all (never part of a header, never a block). Oracles: the
// values written, the file's own bytes, and the OpenEXR file layout (magic, version, name\0 type\0
// size value, \0) written out by hand.

#include "imagefile/exr_header.h"

#include <ImfChannelList.h>
#include <ImfCompressionAttribute.h>
#include <ImfDoubleAttribute.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfMultiPartOutputFile.h>
#include <ImfOutputFile.h>
#include <ImfOutputPart.h>
#include <ImfPartType.h>
#include <ImfStringAttribute.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "file_test_support.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

struct TempDir : test::TempDir {
  TempDir() : test::TempDir("exr_header") {}
};

using Strings = std::map<std::string, std::string>;
using Doubles = std::map<std::string, double>;

// A 4 x 3 one-channel FLOAT scanline OpenEXR with these attributes, written by OpenEXR.
void write_exr(const std::string& path, const Strings& strings, const Doubles& doubles) {
  Imf::Header h(4, 3);
  h.channels().insert("Y", Imf::Channel(Imf::FLOAT));
  for (const auto& [name, value] : strings) h.insert(name, Imf::StringAttribute(value));
  for (const auto& [name, value] : doubles) h.insert(name, Imf::DoubleAttribute(value));
  std::vector<float> px(4 * 3, 0.5f);
  Imf::FrameBuffer fb;
  fb.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(px.data()), sizeof(float),
                            4 * sizeof(float)));
  Imf::OutputFile out(path.c_str(), h);
  out.setFrameBuffer(fb);
  out.writePixels(3);
}

std::string bytes_of(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// One attribute as the OpenEXR layout stores it: name\0 type\0 size (4 bytes, little-endian)
// value.
std::string attribute_bytes(const std::string& name, const std::string& type,
                            const std::string& value) {
  const auto n = static_cast<std::uint32_t>(value.size());
  std::string out = name + '\0' + type + '\0';
  for (int i = 0; i < 4; ++i) out += static_cast<char>((n >> (8 * i)) & 0xff);
  return out + value;
}

std::string double_bytes(double v) {
  std::string out(8, '\0');
  std::memcpy(out.data(), &v, 8);  // little-endian on every machine spectralize builds for
  return out;
}

// The magic number and a single-part scanline version field (version 2, no flags).
const std::string kMagicAndVersion("\x76\x2f\x31\x01\x02\x00\x00\x00", 8);

bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}

TEST(ExrHeader, StringsDoublesAndWindowsWrittenByOpenExrReadBackExactly) {
  TempDir t;
  const Strings strings = {{"spectralize:mode", "emission"},
                           {"spectralize:wavelengths", "380:780:5"},
                           {"owner", ""},  // an empty string is still a string
                           {"comments", std::string("caf\xc3\xa9 \xff\x01 bytes")}};
  const Doubles doubles = {{"spectralize:scale", 0.1},
                           {"tiny", -2.5e-300},
                           {"huge", 1.7976931348623157e308},
                           {"third", 1.0 / 3.0}};
  const std::string path = t / "a.exr";
  write_exr(path, strings, doubles);
  const ExrHeaderValues v = exr_header_values(path);
  // OpenEXR's own attributes (channels, compression, windows, ...) are of other types: the
  // strings and doubles are exactly those written.
  EXPECT_EQ(v.strings, strings);
  ASSERT_EQ(v.doubles.size(), doubles.size());
  for (const auto& [name, value] : doubles) {
    ASSERT_TRUE(v.doubles.count(name)) << name;
    EXPECT_TRUE(same_bits(v.doubles.at(name), value)) << name << ": " << v.doubles.at(name);
  }
  EXPECT_EQ(exr_string_attributes(path), strings);
  // The windows, as OpenEXR wrote them for a 4 x 3 image: (0, 0) to (3, 2).
  const std::array<std::int32_t, 4> window = {0, 0, 3, 2};
  ASSERT_TRUE(v.boxes.count("dataWindow"));
  EXPECT_EQ(v.boxes.at("dataWindow"), window);
  EXPECT_EQ(v.boxes.at("displayWindow"), window);
}

TEST(ExrHeader, AttributesWrittenByOpenImageIoReadBack) {
  TempDir t;
  const std::string path = t / "oiio.exr";
  OIIO::ImageSpec spec(5, 2, 3, OIIO::TypeHalf);
  spec.attribute("spectralize:illuminant", "D65");
  spec.attribute("oiio:ColorSpace", "ACEScg");
  const double pi = 3.141592653589793;
  spec.attribute("spectralize:pi", OIIO::TypeDesc::DOUBLE, &pi);
  spec.attribute("spectralize:count", 7);     // an int: not a string, not a double
  spec.attribute("spectralize:ratio", 0.5f);  // a float: not a double
  std::vector<float> px(5 * 2 * 3, 0.25f);
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->open(path, spec)) << OIIO::geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeFloat, px.data()));
  ASSERT_TRUE(out->close());
  const ExrHeaderValues v = exr_header_values(path);
  ASSERT_TRUE(v.strings.count("spectralize:illuminant"));
  EXPECT_EQ(v.strings.at("spectralize:illuminant"), "D65");
  ASSERT_TRUE(v.doubles.count("spectralize:pi"));
  EXPECT_TRUE(same_bits(v.doubles.at("spectralize:pi"), pi));
  for (const char* other : {"spectralize:count", "spectralize:ratio"}) {
    EXPECT_FALSE(v.strings.count(other)) << other;
    EXPECT_FALSE(v.doubles.count(other)) << other;
  }
}

TEST(ExrHeader, AHandWrittenHeaderIsReadByItsLayoutAlone) {
  TempDir t;
  // A header and nothing after it: the values are complete once its terminating NUL is read.
  const std::string header = kMagicAndVersion + attribute_bytes("a", "string", "xyz") +
                             attribute_bytes("d", "double", double_bytes(-0.75)) +
                             attribute_bytes("f", "float", std::string("\0\0\x80\x3f", 4)) +
                             attribute_bytes("odd", "double", "1234") +  // not 8 bytes
                             std::string(1, '\0');
  const std::string path = t / "hand.exr";
  write_bytes(path, header);
  const ExrHeaderValues v = exr_header_values(path);
  EXPECT_EQ(v.strings, (Strings{{"a", "xyz"}}));
  EXPECT_EQ(v.doubles, (Doubles{{"d", -0.75}}));
  // Without the terminating NUL the header is unfinished: nothing.
  write_bytes(path, header.substr(0, header.size() - 1));
  EXPECT_TRUE(exr_header_values(path).strings.empty());
  EXPECT_TRUE(exr_header_values(path).doubles.empty());
}

TEST(ExrHeader, AHeaderBeyondTheFirstReadIsReadWholeUpToOneMegabyte) {
  TempDir t;
  // 300 KB of one string: past the first 64 KB read and the second (256 KB).
  const std::string long_text(300 * 1024, 'q');
  const std::string path = t / "long.exr";
  write_exr(path, {{"a_first", "1"}, {"long", long_text}, {"z_last", "2"}}, {{"zz", 4.5}});
  const ExrHeaderValues v = exr_header_values(path);
  EXPECT_EQ(v.strings, (Strings{{"a_first", "1"}, {"long", long_text}, {"z_last", "2"}}));
  EXPECT_EQ(v.doubles, (Doubles{{"zz", 4.5}}));
  // A header longer than the documented 1 MB: nothing, not its first part.
  const std::string too_long = t / "too_long.exr";
  write_exr(too_long, {{"a_first", "1"}, {"long", std::string(1100 * 1024, 'q')}}, {});
  EXPECT_TRUE(exr_header_values(too_long).strings.empty());
  EXPECT_TRUE(exr_string_attributes(too_long).empty());
}

TEST(ExrHeader, PixelsCutShortLeaveTheHeaderReadableAndACutHeaderGivesNothing) {
  TempDir t;
  const std::string path = t / "cut.exr";
  write_exr(path, {{"first", "a"}, {"marker", "MARKER-VALUE-0123456789"}, {"z", "b"}},
            {{"d", 2.0}});
  const std::string whole = bytes_of(path);
  // The pixels lose their last byte: the header is whole.
  write_bytes(path, whole.substr(0, whole.size() - 1));
  EXPECT_EQ(exr_header_values(path).strings.at("marker"), "MARKER-VALUE-0123456789");
  // Cut inside a value, and inside a name: nothing of the header, not the part before the cut.
  const std::size_t at = whole.find("MARKER-VALUE");
  ASSERT_NE(at, std::string::npos);
  for (const std::size_t cut : {at + 6, whole.find("marker") + 3, std::size_t{8}, std::size_t{5}}) {
    SCOPED_TRACE("cut at byte " + std::to_string(cut));
    write_bytes(path, whole.substr(0, cut));
    const ExrHeaderValues v = exr_header_values(path);
    EXPECT_TRUE(v.strings.empty());
    EXPECT_TRUE(v.doubles.empty());
    EXPECT_TRUE(exr_attribute_extents(path).empty());
  }
}

TEST(ExrHeader, MissingForeignMultiPartAndMalformedFilesGiveNothing) {
  TempDir t;
  auto expect_nothing = [](const std::string& path, const std::string& what) {
    const ExrHeaderValues v = exr_header_values(path);
    EXPECT_TRUE(v.strings.empty()) << what;
    EXPECT_TRUE(v.doubles.empty()) << what;
    EXPECT_TRUE(exr_string_attributes(path).empty()) << what;
    EXPECT_TRUE(exr_attribute_extents(path).empty()) << what;
  };
  expect_nothing(t / "missing.exr", "a missing file");
  write_bytes(t / "empty.exr", "");
  expect_nothing(t / "empty.exr", "an empty file");
  expect_nothing(t.dir.string(), "a folder");
  // A PNG (OIIO's), and text: not OpenEXR.
  {
    const std::string png = t / "a.png";
    OIIO::ImageSpec spec(4, 4, 3, OIIO::TypeUInt8);
    spec.attribute("Comment", "a string attribute of another format");
    std::vector<unsigned char> px(4 * 4 * 3, 7);
    auto out = OIIO::ImageOutput::create(png);
    ASSERT_TRUE(out && out->open(png, spec)) << OIIO::geterror();
    ASSERT_TRUE(out->write_image(OIIO::TypeUInt8, px.data()));
    ASSERT_TRUE(out->close());
    expect_nothing(png, "a PNG");
  }
  write_bytes(t / "text.exr", "plain text, not an OpenEXR file");
  expect_nothing(t / "text.exr", "text");
  // The magic number, then a name with no NUL within 255 bytes.
  write_bytes(t / "noname.exr", kMagicAndVersion + std::string(4096, 'n'));
  expect_nothing(t / "noname.exr", "a name that never ends");
  // An attribute whose size runs past the end of the file.
  std::string past = kMagicAndVersion + attribute_bytes("a", "string", "xyz");
  past[past.size() - 7] = '\x7f';  // the size's low byte: 127 bytes, 3 there
  write_bytes(t / "past.exr", past + std::string(1, '\0'));
  expect_nothing(t / "past.exr", "a size past the end");
  // A multi-part file (version flag 0x1000), written by OpenEXR: not what spectralize writes.
  {
    const std::string multi = t / "multi.exr";
    std::vector<Imf::Header> headers(2, Imf::Header(2, 2));
    for (int i = 0; i < 2; ++i) {
      headers[i].channels().insert("Y", Imf::Channel(Imf::FLOAT));
      headers[i].setName("part" + std::to_string(i));
      headers[i].setType(Imf::SCANLINEIMAGE);
      headers[i].insert("note", Imf::StringAttribute("in part " + std::to_string(i)));
    }
    std::vector<float> px(4, 1.0f);
    {
      Imf::MultiPartOutputFile out(multi.c_str(), headers.data(), 2);
      for (int i = 0; i < 2; ++i) {
        Imf::OutputPart part(out, i);
        Imf::FrameBuffer fb;
        fb.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(px.data()), sizeof(float),
                                  2 * sizeof(float)));
        part.setFrameBuffer(fb);
        part.writePixels(2);
      }
    }
    // The version field says multi-part (bit 12).
    ASSERT_TRUE(bytes_of(multi)[5] & 0x10);
    expect_nothing(multi, "a multi-part file");
  }
}

TEST(ExrHeader, AFifoWithoutAWriterGivesNothingAtOnce) {
  TempDir t;
  const std::string fifo = t / "pipe.exr";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_TRUE(exr_header_values(fifo).strings.empty());
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));  // not blocked
}

TEST(ExrHeader, ExtentsAreWhereTheFilesBytesHoldEachValue) {
  TempDir t;
  const std::string path = t / "extents.exr";
  const Strings strings = {{"spectralize:mode", "reflectance"}, {"x", "abc"}};
  write_exr(path, strings, {{"d", -123.5}});
  const std::string bytes = bytes_of(path);
  const auto extents = exr_attribute_extents(path);
  for (const auto& [name, value] : strings) {
    ASSERT_TRUE(extents.count(name)) << name;
    const auto [offset, size] = extents.at(name);
    EXPECT_EQ(size, value.size()) << name;
    EXPECT_EQ(bytes.substr(offset, size), value) << name;
  }
  ASSERT_TRUE(extents.count("d"));
  EXPECT_EQ(bytes.substr(extents.at("d").first, extents.at("d").second), double_bytes(-123.5));
  // Every attribute, whatever its type: OpenEXR's own float pixelAspectRatio (1) too.
  ASSERT_TRUE(extents.count("pixelAspectRatio"));
  const auto [offset, size] = extents.at("pixelAspectRatio");
  ASSERT_EQ(size, 4u);
  float ratio = 0;
  std::memcpy(&ratio, bytes.data() + offset, 4);
  EXPECT_EQ(ratio, 1.0f);
  // The value's bytes follow its name, type and size: name\0 type\0 size.
  EXPECT_EQ(bytes.substr(offset - 4 - 6 - 17, 17), std::string("pixelAspectRatio\0", 17));
}

// A finished scanline file is checked to its last byte (what a writer does before its rename):
// files OpenEXR wrote, in every compression, pass; each way of being incomplete or other than
// meant is named. Oracle: the OpenEXR layout (header, one 8-byte offset per block of the
// compression's rows, chunks of y, size and data), the bytes changed by hand.
TEST(ExrHeader, AScanlineFileIsCheckedToItsLastByte) {
  TempDir t;
  const int w = 7, h = 37;  // rows: not a whole number of 16-, 32- or 256-row blocks
  auto write = [&](const std::string& path, Imf::Compression c, int channels) {
    Imf::Header header(w, h);
    header.compression() = c;
    std::vector<std::string> names;
    for (int k = 0; k < channels; ++k) names.emplace_back(1, static_cast<char>('A' + k));
    for (const std::string& n : names) header.channels().insert(n, Imf::Channel(Imf::HALF));
    std::vector<std::uint16_t> px(static_cast<std::size_t>(w * h * channels), 0x3c00);  // 1.0
    Imf::FrameBuffer fb;
    for (int k = 0; k < channels; ++k)
      fb.insert(names[k], Imf::Slice(Imf::HALF, reinterpret_cast<char*>(px.data() + k),
                                     2 * channels, 2 * channels * w));
    Imf::OutputFile out(path.c_str(), header);
    out.setFrameBuffer(fb);
    out.writePixels(h);
  };
  for (const Imf::Compression c :
       {Imf::NO_COMPRESSION, Imf::ZIP_COMPRESSION, Imf::PIZ_COMPRESSION, Imf::DWAB_COMPRESSION}) {
    SCOPED_TRACE(static_cast<int>(c));
    const std::string path = t / "whole.exr";
    write(path, c, 5);
    EXPECT_EQ(exr_scanline_problem(path, w, h, 5), "");
    EXPECT_NE(exr_scanline_problem(path, w, h + 1, 5).find("data window is 7x37"),
              std::string::npos);
    EXPECT_NE(exr_scanline_problem(path, w, h, 6).find("5 channels, not 6"), std::string::npos);
    const std::string bytes = bytes_of(path);
    // Cut short by one byte, or one byte too long: the chunks do not end at the last byte.
    write_bytes(t / "short.exr", bytes.substr(0, bytes.size() - 1));
    EXPECT_NE(exr_scanline_problem(t / "short.exr", w, h, 5), "");
    std::string longer = bytes;
    longer.push_back('x');
    write_bytes(t / "long.exr", longer);
    EXPECT_NE(exr_scanline_problem(t / "long.exr", w, h, 5).find("end at byte"), std::string::npos);
  }
  // The line offset table: an offset never written (0), or one pointing at another block.
  const std::string path = t / "zip.exr";
  write(path, Imf::ZIP_COMPRESSION, 2);  // 3 blocks of 16 rows
  const std::string bytes = bytes_of(path);
  const auto extents = exr_attribute_extents(path);
  ASSERT_TRUE(extents.count("type") == 0 && extents.count("channels") == 1);
  std::size_t table = 0;  // after the last value and the header's closing NUL
  for (const auto& [name, at] : extents)
    table = std::max<std::size_t>(table, at.first + at.second + 1);
  std::string zeroed = bytes;
  std::memset(zeroed.data() + table + 8, 0, 8);
  write_bytes(t / "zeroed.exr", zeroed);
  EXPECT_NE(exr_scanline_problem(t / "zeroed.exr", w, h, 2).find("outside the file"),
            std::string::npos);
  std::string twice = bytes;
  std::memcpy(twice.data() + table + 8, twice.data() + table, 8);  // block 1 -> block 0's chunk
  write_bytes(t / "twice.exr", twice);
  EXPECT_NE(exr_scanline_problem(t / "twice.exr", w, h, 2).find("not a block of its rows"),
            std::string::npos);
  // Not OpenEXR, or missing.
  write_bytes(t / "text.exr", "not an image");
  EXPECT_NE(exr_scanline_problem(t / "text.exr", w, h, 2), "");
  EXPECT_EQ(exr_scanline_problem(t / "missing.exr", w, h, 2), "cannot be opened");
}

}  // namespace
}  // namespace spectralize
