// The scanline OpenEXR writer (imagefile/exr_scanline_writer.h): files read back by OpenEXR's own
// InputFile (an independent reader) hold every sample written, bit for bit for the lossless
// compressions, with the channel names, compression and windows of the spec; lossy ones decode
// exactly as the file OpenImageIO's own writer makes of the same pixels; the header holds the
// attributes OIIO writes for the spec; block sizes are those OpenEXR's core library reports;
// short writes and bad channels are errors naming the file. Oracles: OpenEXR's readers, OIIO's
// own OpenEXR writer, and the pixels generated here.

#include "imagefile/exr_scanline_writer.h"

#include <Imath/half.h>
#include <ImfChannelList.h>
#include <ImfCompression.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>
#include <openexr.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "file_test_support.h"
#include "spectralize/core/error.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

struct TempDir : test::TempDir {
  TempDir() : test::TempDir("exr_writer") {}
};

const std::vector<std::string> kChannels = {
    "S0.400,000000nm", "S0.550,000000nm", "S0.700,000000nm", "R", "G", "B", "A"};
constexpr int kWidth = 37, kHeight = 150;  // 150 rows: no block size divides it

// A spec of kChannels in `type`, with a data window at (-3, 5) inside a larger display window.
OIIO::ImageSpec make_spec(OIIO::TypeDesc type, const std::string& compression) {
  OIIO::ImageSpec spec(kWidth, kHeight, static_cast<int>(kChannels.size()), type);
  spec.channelnames = kChannels;
  spec.alpha_channel = 6;
  spec.x = -3;
  spec.y = 5;
  spec.full_x = -10;
  spec.full_y = 0;
  spec.full_width = 60;
  spec.full_height = 200;
  spec.attribute("compression", compression);
  spec.attribute("spectralLayoutVersion", "1.0");
  spec.attribute("emissiveUnits", "W.m^-2.sr^-1");
  spec.attribute("spectralize:someCount", 12345);
  spec.attribute("spectralize:someValue", 0.25f);
  return spec;
}

// Samples of every sign and magnitude, each exactly representable in `type` (so that a lossless
// file must give them back bit for bit).
std::vector<float> make_pixels(OIIO::TypeDesc type) {
  std::vector<float> px(static_cast<std::size_t>(kWidth) * kHeight * kChannels.size());
  for (std::size_t i = 0; i < px.size(); ++i) {
    float v = static_cast<float>(std::sin(0.731 * static_cast<double>(i)) *
                                 std::pow(10.0, static_cast<double>(i % 7) - 3.0));
    if (i % 97 == 0) v = 0.0f;
    if (type == OIIO::TypeHalf) v = static_cast<float>(Imath::half(v));
    px[i] = v;
  }
  return px;
}

// The pixels as the writer takes them: interleaved samples of the spec's type.
std::vector<unsigned char> as_bytes(const std::vector<float>& px, OIIO::TypeDesc type) {
  std::vector<unsigned char> bytes(px.size() * type.size());
  if (type == OIIO::TypeHalf) {
    for (std::size_t i = 0; i < px.size(); ++i) {
      const Imath::half h(px[i]);
      const unsigned short bits = h.bits();
      std::memcpy(bytes.data() + 2 * i, &bits, 2);
    }
  } else {
    std::memcpy(bytes.data(), px.data(), bytes.size());
  }
  return bytes;
}

// Writes `px` with ExrScanlineWriter to `path`, `strip` rows per call (0: the compression's
// block rows times 3, as the image job writes whole blocks).
void write_with_writer(const std::string& path, const OIIO::ImageSpec& spec,
                       const std::vector<float>& px, int strip = 0, int workers = 2) {
  const std::vector<unsigned char> bytes = as_bytes(px, spec.format);
  OIIO::Filesystem::IOFile file(path, OIIO::Filesystem::IOProxy::Write);
  ASSERT_TRUE(file.opened());
  if (strip == 0) strip = 3 * exr_block_rows(spec.get_string_attribute("compression"));
  const std::size_t row_bytes = spec.scanline_bytes(true);
  ExrScanlineWriter writer(spec, &file, path, workers);
  for (int y = spec.y; y < spec.y + spec.height; y += strip) {
    const int rows = std::min(strip, spec.y + spec.height - y);
    writer.write(y, rows, bytes.data() + static_cast<std::size_t>(y - spec.y) * row_bytes);
  }
  writer.close();
  file.close();
}

// The same pixels written by OIIO's own OpenEXR writer.
void write_with_oiio(const std::string& path, const OIIO::ImageSpec& spec,
                     const std::vector<float>& px) {
  auto out = OIIO::ImageOutput::create("openexr");
  ASSERT_TRUE(out);
  ASSERT_TRUE(out->open(path, spec)) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeFloat, px.data())) << out->geterror();
  ASSERT_TRUE(out->close());
}

// What OpenEXR reads: every channel of the data window as float, interleaved in kChannels'
// order, and the header.
struct Read {
  Imf::Header header;
  std::vector<float> px;
};
Read read_with_openexr(const std::string& path) {
  Imf::InputFile in(path.c_str());
  Read r{in.header(), {}};
  const Imath::Box2i dw = in.header().dataWindow();
  const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
  const std::size_t nch = kChannels.size();
  r.px.assign(static_cast<std::size_t>(w) * h * nch, -12345.0f);
  Imf::FrameBuffer fb;
  const std::size_t xs = nch * sizeof(float), ys = xs * static_cast<std::size_t>(w);
  char* origin = reinterpret_cast<char*>(r.px.data()) -
                 static_cast<std::ptrdiff_t>(dw.min.x) * static_cast<std::ptrdiff_t>(xs) -
                 static_cast<std::ptrdiff_t>(dw.min.y) * static_cast<std::ptrdiff_t>(ys);
  for (std::size_t c = 0; c < nch; ++c)
    fb.insert(kChannels[c], Imf::Slice(Imf::FLOAT, origin + c * sizeof(float), xs, ys));
  in.setFrameBuffer(fb);
  in.readPixels(dw.min.y, dw.max.y);
  return r;
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::set<std::string> channel_names(const Imf::Header& h) {
  std::set<std::string> names;
  for (auto it = h.channels().begin(); it != h.channels().end(); ++it) names.insert(it.name());
  return names;
}

struct Compression {
  const char* oiio;
  Imf::Compression imf;
};

// --- Samples, channels, compression, windows ---

TEST(ExrScanlineWriter, LosslessFilesHoldEverySampleBitForBit) {
  TempDir t;
  const Compression lossless[] = {
      {"none", Imf::NO_COMPRESSION},     {"rle", Imf::RLE_COMPRESSION},
      {"zips", Imf::ZIPS_COMPRESSION},   {"zip", Imf::ZIP_COMPRESSION},
      {"zip:9", Imf::ZIP_COMPRESSION},   {"piz", Imf::PIZ_COMPRESSION},
      {"pxr24", Imf::PXR24_COMPRESSION},  // lossless for HALF only
      {"b44", Imf::B44_COMPRESSION},      // lossy for HALF only
  };
  for (const OIIO::TypeDesc& type : {OIIO::TypeHalf, OIIO::TypeFloat})
    for (const Compression& c : lossless) {
      if (type == OIIO::TypeFloat && c.imf == Imf::PXR24_COMPRESSION) continue;
      if (type == OIIO::TypeHalf && c.imf == Imf::B44_COMPRESSION) continue;
      SCOPED_TRACE(std::string(c.oiio) + " " + type.c_str());
      const OIIO::ImageSpec spec = make_spec(type, c.oiio);
      const std::vector<float> px = make_pixels(type);
      const std::string path = t / "lossless.exr";
      write_with_writer(path, spec, px);
      const Read r = read_with_openexr(path);
      EXPECT_EQ(r.header.compression(), c.imf);
      EXPECT_EQ(channel_names(r.header), std::set<std::string>(kChannels.begin(), kChannels.end()));
      for (auto it = r.header.channels().begin(); it != r.header.channels().end(); ++it) {
        EXPECT_EQ(it.channel().type, type == OIIO::TypeHalf ? Imf::HALF : Imf::FLOAT) << it.name();
      }
      EXPECT_EQ(r.header.dataWindow(), Imath::Box2i({-3, 5}, {-3 + kWidth - 1, 5 + kHeight - 1}));
      EXPECT_EQ(r.header.displayWindow(), Imath::Box2i({-10, 0}, {49, 199}));
      EXPECT_EQ(r.header.lineOrder(), Imf::INCREASING_Y);
      ASSERT_EQ(r.px.size(), px.size());
      for (std::size_t i = 0; i < px.size(); ++i) {
        ASSERT_EQ(r.px[i], px[i]) << "sample " << i << " (pixel " << i / kChannels.size()
                                  << ", channel " << kChannels[i % kChannels.size()] << ")";
      }
    }
}

TEST(ExrScanlineWriter, StripsOfAnyHeightMakeTheSameFile) {
  // Strips that cut blocks (7 rows of piz's 32), single rows, and all rows at once.
  TempDir t;
  const OIIO::ImageSpec spec = make_spec(OIIO::TypeHalf, "piz");
  const std::vector<float> px = make_pixels(OIIO::TypeHalf);
  for (const int strip : {1, 7, 32, kHeight}) {
    SCOPED_TRACE(strip);
    const std::string path = t / ("strip" + std::to_string(strip) + ".exr");
    write_with_writer(path, spec, px, strip);
    EXPECT_EQ(read_with_openexr(path).px, px);
  }
}

TEST(ExrScanlineWriter, TheNumberOfWorkersDoesNotChangeABit) {
  TempDir t;
  // One DateTime (capDate) for both: written from the clock, two files made a second apart
  // would differ in it whatever the workers did.
  OIIO::ImageSpec spec = make_spec(OIIO::TypeFloat, "zip");
  spec.attribute("DateTime", "2026:01:02 03:04:05");
  const std::vector<float> px = make_pixels(OIIO::TypeFloat);
  write_with_writer(t / "one.exr", spec, px, 0, 1);
  write_with_writer(t / "four.exr", spec, px, 0, 4);
  EXPECT_EQ(file_bytes(t / "one.exr"), file_bytes(t / "four.exr"));
  EXPECT_FALSE(file_bytes(t / "one.exr").empty());
}

TEST(ExrScanlineWriter, LossyFilesDecodeAsOpenImageIOsOwnFileDoes) {
  // The same header and the same blocks: OpenEXR decodes both files to the same samples, at
  // every DWA level asked (OpenEXR keeps the level in memory only: a writer that dropped it
  // would write level 45 whatever the user said).
  TempDir t;
  const Compression lossy[] = {
      {"b44", Imf::B44_COMPRESSION},       {"b44a", Imf::B44A_COMPRESSION},
      {"dwaa", Imf::DWAA_COMPRESSION},     {"dwaa:45", Imf::DWAA_COMPRESSION},
      {"dwab", Imf::DWAB_COMPRESSION},     {"pxr24", Imf::PXR24_COMPRESSION},
      {"dwaa:200", Imf::DWAA_COMPRESSION}, {"dwab:10", Imf::DWAB_COMPRESSION},
  };
  for (const OIIO::TypeDesc& type : {OIIO::TypeHalf, OIIO::TypeFloat})
    for (const Compression& c : lossy) {
      SCOPED_TRACE(std::string(c.oiio) + " " + type.c_str());
      const OIIO::ImageSpec spec = make_spec(type, c.oiio);
      const std::vector<float> px = make_pixels(type);
      write_with_writer(t / "ours.exr", spec, px);
      write_with_oiio(t / "oiio.exr", spec, px);
      const Read ours = read_with_openexr(t / "ours.exr"), oiio = read_with_openexr(t / "oiio.exr");
      EXPECT_EQ(ours.header.compression(), c.imf);
      ASSERT_EQ(ours.px.size(), oiio.px.size());
      for (std::size_t i = 0; i < ours.px.size(); ++i) {
        ASSERT_EQ(ours.px[i], oiio.px[i]) << "sample " << i;
      }
    }
}

TEST(ExrScanlineWriter, TheHeaderHoldsWhatOpenImageIOWritesForTheSpec) {
  TempDir t;
  OIIO::ImageSpec spec = make_spec(OIIO::TypeHalf, "dwaa:45");
  spec.attribute("oiio:ColorSpace", "ACEScg");
  const float chroma[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
  spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), chroma);
  spec.attribute("spectralize:warnings", "[\"a warning\"]");
  const double zero = 0;
  spec.attribute("spectralize:blackPixels", OIIO::TypeDesc::DOUBLE, &zero);
  // OpenImageIO stamps the current time when the spec has none: the two files would differ
  // whenever their writes straddle a second.
  spec.attribute("DateTime", "2026:01:02 03:04:05");
  const std::vector<float> px = make_pixels(OIIO::TypeHalf);
  write_with_writer(t / "ours.exr", spec, px);
  write_with_oiio(t / "oiio.exr", spec, px);
  auto a = OIIO::ImageInput::open(t / "ours.exr");
  auto b = OIIO::ImageInput::open(t / "oiio.exr");
  ASSERT_TRUE(a && b);
  // Every attribute OIIO reads from its own file, with the same value, and no other.
  auto attributes = [](const OIIO::ImageSpec& s) {
    std::map<std::string, std::string> m;
    for (const OIIO::ParamValue& p : s.extra_attribs)
      m[p.name().string()] = std::string(p.type().c_str()) + " " + p.get_string(0);
    return m;
  };
  EXPECT_EQ(attributes(a->spec()), attributes(b->spec()));
  EXPECT_EQ(a->spec().get_string_attribute("spectralLayoutVersion"), "1.0");
  // OpenEXR records the method, not the level.
  EXPECT_EQ(a->spec().get_string_attribute("compression"), "dwaa");
  EXPECT_EQ(a->spec().get_int_attribute("spectralize:someCount"), 12345);
  // The windows and channels too.
  EXPECT_EQ(a->spec().x, -3);
  EXPECT_EQ(a->spec().y, 5);
  EXPECT_EQ(a->spec().full_width, 60);
  EXPECT_EQ(a->spec().full_height, 200);
  EXPECT_EQ(a->spec().channelnames, b->spec().channelnames);
  EXPECT_EQ(a->spec().alpha_channel, b->spec().alpha_channel);
}

// --- Block sizes ---

TEST(ExrScanlineWriter, BlockRowsAreThoseOpenExrWrites) {
  // OpenEXR's core library reads the scanlines per chunk from a file OIIO wrote.
  TempDir t;
  for (const char* c : {"none", "rle", "zips", "zip", "zip:9", "piz", "pxr24", "b44", "b44a",
                        "dwaa", "dwaa:45", "dwab"}) {
    SCOPED_TRACE(c);
    const std::string path = t / "blocks.exr";
    write_with_oiio(path, make_spec(OIIO::TypeHalf, c), make_pixels(OIIO::TypeHalf));
    exr_context_t ctx = nullptr;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    ASSERT_EQ(exr_start_read(&ctx, path.c_str(), &init), EXR_ERR_SUCCESS);
    int32_t lines = 0;
    EXPECT_EQ(exr_get_scanlines_per_chunk(ctx, 0, &lines), EXR_ERR_SUCCESS);
    exr_finish(&ctx);
    EXPECT_EQ(exr_block_rows(c), lines);
  }
  // Names as users spell them.
  EXPECT_EQ(exr_block_rows("ZIP"), 16);
  EXPECT_EQ(exr_block_rows("DWAB:45"), 256);
}

// --- Failures ---

// An IOProxy in memory that accepts at most `budget` bytes in all, then writes short.
class LimitedProxy final : public OIIO::Filesystem::IOProxy {
 public:
  explicit LimitedProxy(std::size_t budget) : IOProxy("limited", Write), budget_(budget) {}
  const char* proxytype() const override { return "limited"; }
  size_t write(const void* buf, size_t size) override {
    const size_t n = pwrite(buf, size, m_pos);
    m_pos += static_cast<int64_t>(n);
    return n;
  }
  size_t pwrite(const void* buf, size_t size, int64_t offset) override {
    const size_t n = std::min(size, budget_ - std::min(budget_, accepted_));
    const auto at = static_cast<std::size_t>(offset);
    if (bytes_.size() < at + n) bytes_.resize(at + n);
    std::memcpy(bytes_.data() + at, buf, n);
    accepted_ += n;
    return n;
  }
  size_t size() const override { return bytes_.size(); }
  std::size_t accepted() const { return accepted_; }

 private:
  std::size_t budget_, accepted_ = 0;
  std::vector<unsigned char> bytes_;
};

// The message of the Error `fn` throws ("" and a failure if none).
template <class Fn>
std::string error_of(Fn&& fn) {
  try {
    fn();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not a spectralize::Error: " << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no Error thrown";
  return "";
}

// The bytes a whole file of `spec` takes, written without a limit: after the constructor (the
// header), after the pixels, and after the close (the line offset table).
struct WrittenBytes {
  std::size_t header = 0, before_close = 0, total = 0;
};
WrittenBytes written_bytes(const OIIO::ImageSpec& spec, const std::vector<unsigned char>& bytes,
                           const std::string& file) {
  WrittenBytes n;
  LimitedProxy all(SIZE_MAX);
  ExrScanlineWriter w(spec, &all, file, 1);
  n.header = all.accepted();
  w.write(spec.y, kHeight, bytes.data());
  n.before_close = all.accepted();
  w.close();
  n.total = all.accepted();
  return n;
}

TEST(ExrScanlineWriter, AShortWriteIsAnErrorNamingTheFile) {
  const OIIO::ImageSpec spec = make_spec(OIIO::TypeHalf, "zip");
  const std::vector<unsigned char> bytes = as_bytes(make_pixels(OIIO::TypeHalf), OIIO::TypeHalf);
  const std::string file = "/somewhere/out.exr";
  const auto [header, before_close, total] = written_bytes(spec, bytes, file);
  ASSERT_GT(header, 0u);
  ASSERT_GT(before_close, header);
  ASSERT_GT(total, before_close);  // the line offset table is written at the close
  // Short in the header: the constructor refuses.
  {
    LimitedProxy p(header / 2);
    const std::string why = error_of([&] { ExrScanlineWriter w(spec, &p, file, 1); });
    EXPECT_NE(why.find("'" + file + "'"), std::string::npos) << why;
  }
  // Short in the pixels: write() refuses.
  {
    LimitedProxy p(header + (before_close - header) / 2);
    ExrScanlineWriter w(spec, &p, file, 1);
    const std::string why = error_of([&] { w.write(spec.y, kHeight, bytes.data()); });
    EXPECT_NE(why.find("'" + file + "'"), std::string::npos) << why;
    EXPECT_NE(why.find("write failed"), std::string::npos) << why;
  }
}

// The line offset table is written when OpenEXR's OutputFile is destroyed, which swallows any
// error: a disk that fills up there must still make close() fail, or an image whose chunks
// cannot be found would be taken for a complete file.
TEST(ExrScanlineWriter, AShortWriteOfTheLineOffsetTableIsAnErrorOfTheClose) {
  const OIIO::ImageSpec spec = make_spec(OIIO::TypeHalf, "zip");
  const std::vector<unsigned char> bytes = as_bytes(make_pixels(OIIO::TypeHalf), OIIO::TypeHalf);
  const std::string file = "/somewhere/table.exr";
  const auto [header, before_close, total] = written_bytes(spec, bytes, file);
  ASSERT_GT(total, before_close);
  // Every pixel fits; half of the table does not.
  LimitedProxy p(before_close + (total - before_close) / 2);
  ExrScanlineWriter w(spec, &p, file, 1);
  w.write(spec.y, kHeight, bytes.data());
  ASSERT_EQ(p.accepted(), before_close);
  const std::string why = error_of([&] { w.close(); });
  EXPECT_NE(why.find("'" + file + "'"), std::string::npos) << why;
  EXPECT_NE(why.find("write failed"), std::string::npos) << why;
  EXPECT_LT(p.accepted(), total);  // the table was indeed cut short
}

TEST(ExrScanlineWriter, ChannelsOtherThanHalfOrFloatAreRefused) {
  OIIO::ImageSpec spec = make_spec(OIIO::TypeHalf, "zip");
  spec.channelformats.assign(kChannels.size(), OIIO::TypeHalf);
  spec.channelformats[3] = OIIO::TypeUInt8;
  OIIO::Filesystem::IOVecOutput memory;
  const std::string why =
      error_of([&] { ExrScanlineWriter w(spec, &memory, "/somewhere/u8.exr", 1); });
  EXPECT_NE(why.find("'/somewhere/u8.exr'"), std::string::npos) << why;
  EXPECT_NE(why.find("channel R"), std::string::npos) << why;
  OIIO::ImageSpec u16 = make_spec(OIIO::TypeUInt16, "zip");
  EXPECT_NE(error_of([&] {
              ExrScanlineWriter w(u16, &memory, "/somewhere/u16.exr", 1);
            }).find("'/somewhere/u16.exr'"),
            std::string::npos);
}

}  // namespace
}  // namespace spectralize
