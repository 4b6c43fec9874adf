// The output formats table (imagefile/output_formats.h) against what OIIO's writers really do on
// this machine: every stated fact is checked by writing files with OIIO and reading them back
// (sample types kept, alpha kept, real tiles, compressions honoured and their defaults, the
// reasons for refusals), and check_output refuses what a format cannot hold, naming the format
// and an alternative.

#include <gtest/gtest.h>

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "colour/icc_profile.h"
#include "file_test_support.h"
#include "imagefile/output_formats.h"
#include "spectralize/core/error.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

struct TempDir : test::TempDir {
  TempDir() : test::TempDir("output_formats") {}
};

OIIO::TypeDesc type_of(std::string_view name) {
  return name == "uint8"    ? OIIO::TypeUInt8
         : name == "uint16" ? OIIO::TypeUInt16
         : name == "half"   ? OIIO::TypeHalf
                            : OIIO::TypeFloat;
}

// A smooth gradient with a little texture: compressible, so levels change the size.
std::vector<float> pixels(int w, int h, int nch) {
  std::vector<float> px(static_cast<std::size_t>(w) * h * nch);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < nch; ++c)
        px[(static_cast<std::size_t>(y) * w + x) * nch + c] =
            c == 3 ? 0.5f
                   : static_cast<float>(0.1 + 0.8 * x / w + 0.05 * std::sin(0.7 * (x * 3 + y + c)));
  return px;
}

struct Written {
  bool ok = false;
  OIIO::ImageSpec spec;  // as read back
  std::vector<float> px;
  std::uintmax_t bytes = 0;
};

// Writes w x h of `nch` channels in `type` with `attrs` (and tiles), reads it back with OIIO.
Written write_read(const std::string& path, OIIO::TypeDesc type, int nch, int w = 64, int h = 48,
                   int tile = 0, const std::function<void(OIIO::ImageSpec&)>& attrs = {}) {
  Written r;
  OIIO::ImageSpec spec(w, h, nch, type);
  spec.alpha_channel = nch == 4 ? 3 : -1;
  if (tile) spec.tile_width = spec.tile_height = tile;
  if (attrs) attrs(spec);
  auto out = OIIO::ImageOutput::create(path);
  const std::vector<float> px = pixels(w, h, nch);
  if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeFloat, px.data()) ||
      !out->close()) {
    (void)OIIO::geterror();
    return r;
  }
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    (void)OIIO::geterror();
    return r;
  }
  r.spec = in->spec();
  r.px.resize(static_cast<std::size_t>(r.spec.image_pixels()) * r.spec.nchannels);
  r.ok = in->read_image(0, 0, 0, r.spec.nchannels, OIIO::TypeFloat, r.px.data());
  r.bytes = fs::file_size(path);
  return r;
}

std::string path_for(const TempDir& t, const OutputFormat& f, const std::string& tag) {
  return (t.dir / (std::string(f.name) + "_" + tag + std::string(f.extension))).string();
}

TEST(OutputFormats, EveryFormatThisOiioWritesIsInTheTable) {
  std::string list;
  OIIO::getattribute("output_format_list", list);
  for (const auto& name : OIIO::Strutil::splits(list, ",")) {
    const OutputFormat* f = output_format_named(name);
    ASSERT_TRUE(f) << name << ": written by OIIO, unknown to the table";
    EXPECT_TRUE(f->available) << name;
  }
}

TEST(OutputFormats, TheSampleTypesHeldAreTheOnesKept) {
  TempDir t;
  for (const OutputFormat& f : output_formats()) {
    if (!f.available || !f.refused.empty()) continue;
    for (const char* type : {"uint8", "uint16", "half", "float"}) {
      const Written w = write_read(path_for(t, f, type), type_of(type), 3);
      if (f.holds(type)) {
        ASSERT_TRUE(w.ok) << f.name << " " << type;
      }
      EXPECT_EQ(f.holds(type), w.ok && w.spec.format == type_of(type))
          << f.name << ": asked " << type << ", stored " << (w.ok ? w.spec.format.c_str() : "-");
    }
  }
}

// The colour slot the table states is where a file keeps the space: an ICC profile read back
// byte for byte, or OpenEXR's colorInteropID attribute.
TEST(OutputFormats, TheColourSlotIsWhereTheFileKeepsItsSpace) {
  TempDir t;
  const std::array<float, 8> rec709 = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
  const std::vector<unsigned char> icc =
      icc_profile(rec709, {IccTransfer::srgb, 2.4}, "sRGB - Texture (srgb_rec709_scene)");
  ASSERT_FALSE(icc.empty());
  int checked = 0;
  for (const OutputFormat& f : output_formats()) {
    if (!f.available || !f.refused.empty() || !cannot_write_here(f).empty()) continue;
    if (f.colour != ColourSlot::icc_profile && f.colour != ColourSlot::attributes) continue;
    SCOPED_TRACE(std::string(f.name));
    const Written w = write_read(
        path_for(t, f, "tagged"), type_of(f.samples.front()), 3, 64, 48, 0,
        [&](OIIO::ImageSpec& s) {
          s.attribute("ICCProfile", OIIO::TypeDesc(OIIO::TypeDesc::UINT8, icc.size()), icc.data());
          s.attribute("colorInteropID", "srgb_rec709_scene");
        });
    ASSERT_TRUE(w.ok);
    ++checked;
    if (f.colour == ColourSlot::attributes) {
      EXPECT_EQ(w.spec.get_string_attribute("colorInteropID"), "srgb_rec709_scene");
      continue;
    }
    const OIIO::ParamValue* kept = w.spec.find_attribute("ICCProfile");
    ASSERT_TRUE(kept) << "no ICC profile read back";
    const auto* bytes = static_cast<const unsigned char*>(kept->data());
    EXPECT_EQ(std::vector<unsigned char>(bytes, bytes + kept->datasize()), icc);
  }
  EXPECT_GE(checked, 4);  // OpenEXR, TIFF, PNG, JPEG at least
}

TEST(OutputFormats, AlphaIsKeptWhereTheTableSaysSo) {
  TempDir t;
  for (const OutputFormat& f : output_formats()) {
    if (!f.available || !f.refused.empty()) continue;
    const Written w = write_read(path_for(t, f, "rgba"), type_of(f.samples.front()), 4);
    const bool kept = w.ok && w.spec.nchannels == 4 && w.spec.alpha_channel == 3;
    EXPECT_EQ(f.alpha, kept) << f.name;
  }
}

TEST(OutputFormats, TilesAreRealWhereTheTableSaysSo) {
  TempDir t;
  for (const OutputFormat& f : output_formats()) {
    if (!f.available || !f.refused.empty()) continue;
    const Written w =
        write_read(path_for(t, f, "tiled"), type_of(f.samples.front()), 3, 64, 48, 32);
    const bool tiled = w.ok && w.spec.tile_width == 32 && w.spec.tile_height == 32;
    EXPECT_EQ(f.tiles, tiled) << f.name << " (emulated tiles are not tiles)";
    if (f.tiles && f.tile_multiple > 1) {
      OIIO::ImageSpec spec(64, 48, 3, type_of(f.samples.front()));
      spec.tile_width = spec.tile_height = f.tile_multiple + 1;
      auto out = OIIO::ImageOutput::create(path_for(t, f, "odd"));
      EXPECT_FALSE(out->open(path_for(t, f, "odd"), spec)) << f.name << ": odd tiles accepted";
      (void)out->geterror();
    }
  }
}

TEST(OutputFormats, CompressionsAreHonouredAndTheDefaultsAreTheWritersOwn) {
  TempDir t;
  for (const OutputFormat& f : output_formats()) {
    if (!f.available || !f.refused.empty()) continue;
    const OIIO::TypeDesc type = type_of(f.samples.front());
    auto with = [&](const std::string& text) {
      return [&f, text](OIIO::ImageSpec& s) { apply_compression(s, f, text); };
    };
    const Written by_default =
        write_read(path_for(t, f, "default"), type, 3, 64, 48, 0, [](OIIO::ImageSpec&) {});
    const Written stated = write_read(path_for(t, f, "stated"), type, 3, 64, 48, 0,
                                      with(std::string(f.default_compression)));
    ASSERT_TRUE(by_default.ok && stated.ok) << f.name;
    EXPECT_EQ(by_default.bytes, stated.bytes)
        << f.name << ": the stated default " << f.default_compression
        << " is not what the writer does unasked";
    for (const CompressionChoice& c : f.compressions) {
      SCOPED_TRACE(std::string(f.name) + " " + std::string(c.name));
      const Written a = write_read(path_for(t, f, std::string(c.name) + "_a"), type, 3, 64, 48, 0,
                                   with(std::string(c.name)));
      ASSERT_TRUE(a.ok);
      if (!c.lossy && type != OIIO::TypeHalf) {
        const std::vector<float> want = pixels(64, 48, 3);
        const double step = type == OIIO::TypeUInt8    ? 1 / 255.0
                            : type == OIIO::TypeUInt16 ? 1 / 65535.0
                                                       : 0;
        for (std::size_t i = 0; i < want.size(); ++i) {
          ASSERT_NEAR(a.px[i], want[i], step / 2 + 1e-7) << "lossless, sample " << i;
        }
      }
      if (c.max_level > 0) {
        const Written lo =
            write_read(path_for(t, f, "lo"), type, 3, 64, 48, 0,
                       with(std::string(c.name) + ":" + std::to_string(c.min_level)));
        const Written hi =
            write_read(path_for(t, f, "hi"), type, 3, 64, 48, 0,
                       with(std::string(c.name) + ":" + std::to_string(c.max_level)));
        ASSERT_TRUE(lo.ok && hi.ok);
        EXPECT_NE(lo.bytes, hi.bytes) << "the level is ignored";
      }
    }
  }
}

// Why apply_compression spells PNG's level as png:compressionLevel: "compression" is ignored.
TEST(OutputFormats, PngIgnoresTheCompressionAttribute) {
  TempDir t;
  auto png = [&](const char* tag, const std::function<void(OIIO::ImageSpec&)>& a) {
    return write_read((t.dir / (std::string(tag) + ".png")).string(), OIIO::TypeUInt8, 3, 64, 48, 0,
                      a)
        .bytes;
  };
  EXPECT_EQ(png("a", [](OIIO::ImageSpec& s) { s.attribute("compression", "zip:1"); }),
            png("b", [](OIIO::ImageSpec& s) { s.attribute("compression", "zip:9"); }));
  EXPECT_NE(png("c", [](OIIO::ImageSpec& s) { s.attribute("png:compressionLevel", 1); }),
            png("d", [](OIIO::ImageSpec& s) { s.attribute("png:compressionLevel", 9); }));
}

// The refusals' reasons, as OIIO behaves.
TEST(OutputFormats, RefusedFormatsDoWhatTheReasonSays) {
  TempDir t;
  auto refused = [](std::string_view name) {
    const OutputFormat* f = output_format_named(name);
    return f && !f->refused.empty() && f->available;
  };
  if (refused("gif")) {  // RGB comes back as four channels (a palette with transparency)
    const Written w = write_read((t.dir / "a.gif").string(), OIIO::TypeUInt8, 3);
    EXPECT_TRUE(!w.ok || w.spec.nchannels == 4);
  }
  if (refused("ico")) {
    const Written w = write_read((t.dir / "a.ico").string(), OIIO::TypeUInt8, 3, 32, 32);
    EXPECT_TRUE(!w.ok || w.spec.nchannels == 4);
  }
  if (refused("zfile")) {
    EXPECT_FALSE(write_read((t.dir / "a.zfile").string(), OIIO::TypeFloat, 3).ok);
  }
  if (refused("iff")) {  // tiles only: scanlines are refused
    OIIO::ImageSpec spec(16, 16, 3, OIIO::TypeUInt8);
    auto out = OIIO::ImageOutput::create((t.dir / "a.iff").string());
    ASSERT_TRUE(out && out->open((t.dir / "a.iff").string(), spec));
    std::vector<unsigned char> row(16 * 3, 128);
    EXPECT_FALSE(out->write_scanline(0, 0, OIIO::TypeUInt8, row.data()));
    (void)out->geterror();
    out->close();
  }
  if (refused("jpeg2000")) {  // a side under 32 pixels: unreadable; RGBA: other values
    const std::string_view why = output_format_named("jpeg2000")->refused;
    EXPECT_NE(why.find("a side is under 32 pixels"), std::string_view::npos) << why;
    EXPECT_NE(why.find("RGBA"), std::string_view::npos) << why;
    for (const auto& [w, h] : {std::pair{16, 16}, {31, 31}, {1000, 16}, {16, 1000}})
      EXPECT_FALSE(write_read((t.dir / "a.jp2").string(), OIIO::TypeUInt8, 3, w, h).ok)
          << w << "x" << h;
    const Written rgb = write_read((t.dir / "b.jp2").string(), OIIO::TypeUInt8, 3, 32, 32);
    EXPECT_TRUE(rgb.ok) << "the limit is 32, as the reason says";
    const Written rgba = write_read((t.dir / "c.jp2").string(), OIIO::TypeUInt8, 4, 32, 32);
    ASSERT_TRUE(rgba.ok);
    const std::vector<float> want = pixels(32, 32, 4);
    double worst = 0;
    for (std::size_t i = 0; i < want.size(); ++i)
      worst = std::max(worst, std::abs(double(rgba.px[i]) - std::round(want[i] * 255) / 255));
    EXPECT_GT(worst, 0.1) << "RGBA comes back with other values";
  }
  // TIFF's jpeg compression is left out: float samples are silently zip-compressed.
  const Written j = write_read((t.dir / "j.tif").string(), OIIO::TypeFloat, 3, 64, 48, 0,
                               [](OIIO::ImageSpec& s) { s.attribute("compression", "jpeg"); });
  ASSERT_TRUE(j.ok);
  EXPECT_EQ(j.spec.get_string_attribute("compression"), "zip");
}

TEST(OutputFormats, CheckOutputRefusesWhatTheFormatCannotHoldNamingAnAlternative) {
  auto refusal = [](const std::string& path, const OutputRequest& r) {
    try {
      check_output(path, r);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  OutputRequest r;
  r.samples = "uint16";
  EXPECT_NE(refusal("a.jpg", r).find("JPEG stores uint8 samples, not uint16: use --format uint8"),
            std::string::npos)
      << refusal("a.jpg", r);
  EXPECT_EQ(refusal("a.png", r), "");
  // Python's users read keywords, not flags.
  try {
    check_output("a.jpg", r, "");
    ADD_FAILURE() << "uint16 JPEG accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("use format='uint8'"), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find("--"), std::string::npos) << e.what();
  }
  r.samples = "half";
  EXPECT_NE(refusal("a.tif", r).find("use --format float"), std::string::npos);
  r.samples = "uint8";
  EXPECT_NE(refusal("a.gif", r).find("write .png"), std::string::npos);
  r.compression = "zip:9";
  EXPECT_EQ(refusal("a.png", r), "");
  EXPECT_NE(refusal("a.jpg", r).find("JPEG takes jpeg[:1-100]"), std::string::npos);
  r.compression = "";
  r.alpha = true;
  r.channels = 4;
  EXPECT_NE(refusal("a.jpg", r).find("no alpha channel"), std::string::npos);
  r.alpha = false;
  r.channels = 3;
  r.tile_width = r.tile_height = 64;
  EXPECT_NE(refusal("a.png", r).find("not tiled"), std::string::npos);
  // OpenEXR: at most INT_MAX bytes per tile; 84 half channels fit 2048, not 4096.
  r.samples = "half";
  r.channels = 84;
  r.tile_width = r.tile_height = 4096;
  EXPECT_NE(refusal("a.exr", r).find("use --tile 2048 or less"), std::string::npos)
      << refusal("a.exr", r);
  r.tile_width = r.tile_height = 2048;
  EXPECT_EQ(refusal("a.exr", r), "");
  EXPECT_NE(refusal("a.nosuch", r).find("OpenImageIO writes no '.nosuch' file"), std::string::npos);
}

TEST(OutputFormats, CompressionNamesAndLevelsAcrossFormats) {
  const auto names = all_compression_names();
  for (const char* n : {"zip", "piz", "dwab", "lzw", "jpeg", "packbits", "rle"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  }
  // Each name offered is one a format this OIIO writes (by its own list) takes: JPEG XL's
  // only where OIIO writes .jxl (OIIO 3 with libjxl; not Debian 12's OIIO 2.4).
  std::string list;
  OIIO::getattribute("output_format_list", list);
  const std::vector<std::string> writes = OIIO::Strutil::splits(list, ",");
  auto written = [&](std::string_view format) {
    return std::find(writes.begin(), writes.end(), format) != writes.end();
  };
  for (std::string_view n : names) {
    bool taken = false;
    for (const OutputFormat& f : output_formats())
      for (const CompressionChoice& c : f.compressions)
        taken = taken || (c.name == n && f.refused.empty() && written(f.name));
    EXPECT_TRUE(taken) << n;
  }
  EXPECT_EQ(std::find(names.begin(), names.end(), "jpegxl") != names.end(), written("jpegxl"));
  int lo = 0, hi = 0;
  ASSERT_TRUE(compression_level_range("zip", lo, hi));
  EXPECT_EQ(lo, 0);  // PNG's deflate level 0
  EXPECT_EQ(hi, 9);
  ASSERT_TRUE(compression_level_range("jpeg", lo, hi));
  EXPECT_EQ(hi, 100);
  EXPECT_FALSE(compression_level_range("piz", lo, hi));
}

}  // namespace
}  // namespace spectralize
