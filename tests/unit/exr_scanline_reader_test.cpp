// The scanline OpenEXR reader (imagefile/exr_scanline_reader.h): the same samples OIIO reads, for
// every compression and sample type, in strips of any height and any channel order, with a data
// window off the origin; the decoded chunks it keeps within its budget; files it does not take.

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "file_test_support.h"
#include "imagefile/exr_scanline_reader.h"
#include "spectralize/core/error.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

struct TempDir : test::TempDir {
  TempDir() : test::TempDir("exr_reader") {}
};

// A W x H image of channels B, G, R, A (stored in that order by OIIO's spec, written sorted by
// OpenEXR) with a data window at (-3, 5), in `type` samples and `compression`.
std::string write(const fs::path& dir, OIIO::TypeDesc type, const std::string& compression, int w,
                  int h, bool tiled = false) {
  OIIO::ImageSpec spec(w, h, 4, type);
  spec.channelnames = {"B", "G", "R", "A"};
  spec.alpha_channel = 3;
  spec.x = -3;
  spec.y = 5;
  spec.attribute("compression", compression);
  if (tiled) spec.tile_width = spec.tile_height = 16;
  std::vector<float> px(static_cast<std::size_t>(w) * h * 4);
  for (std::size_t i = 0; i < px.size(); ++i) px[i] = std::sin(0.37 * static_cast<double>(i)) * 4;
  const std::string path =
      (dir / (compression + "_" + type.c_str() + (tiled ? "_tiled" : "") + ".exr")).string();
  auto out = OIIO::ImageOutput::create(path);
  EXPECT_TRUE(out && out->open(path, spec) && out->write_image(OIIO::TypeFloat, px.data()) &&
              out->close());
  return path;
}

TEST(ExrScanlineReader, ReadsWhatOiioReadsForEveryCompressionAndType) {
  TempDir t;
  const int w = 37, h = 300;
  for (const OIIO::TypeDesc& type : {OIIO::TypeHalf, OIIO::TypeFloat})
    for (const char* c :
         {"none", "rle", "zips", "zip", "piz", "pxr24", "b44", "b44a", "dwaa", "dwab"}) {
      SCOPED_TRACE(std::string(c) + " " + type.c_str());
      const std::string path = write(t.dir, type, c, w, h);
      auto oiio = OIIO::ImageInput::open(path);
      ASSERT_TRUE(oiio);
      const OIIO::ImageSpec spec = oiio->spec();
      std::vector<float> expected(static_cast<std::size_t>(w) * h * 4);
      ASSERT_TRUE(oiio->read_image(0, 0, 0, 4, OIIO::TypeFloat, expected.data()));
      // A channel order of our own: the caller's buffer decides.
      const std::vector<std::string> names = {"A", "R", "G", "B"};
      auto reader = ExrScanlineReader::open(path, names, 16u << 20, 2);
      ASSERT_TRUE(reader);
      std::vector<float> got(expected.size());
      for (int y0 = 0; y0 < h;) {
        const int y1 = std::min(h, y0 + 23);  // strips across chunk boundaries
        reader->read(y0, y1, got.data() + static_cast<std::size_t>(y0) * w * 4);
        y0 = y1;
      }
      int index[4];
      for (int c2 = 0; c2 < 4; ++c2)
        index[c2] = static_cast<int>(
            std::find(spec.channelnames.begin(), spec.channelnames.end(), names[c2]) -
            spec.channelnames.begin());
      for (std::size_t p = 0; p < static_cast<std::size_t>(w) * h; ++p)
        for (int c2 = 0; c2 < 4; ++c2) {
          ASSERT_EQ(got[p * 4 + c2], expected[p * 4 + index[c2]]) << "pixel " << p;
        }
    }
}

TEST(ExrScanlineReader, KeepsTheDecodedChunksWithinItsBudget) {
  TempDir t;
  // 2048 float RGBA: a 256-row DWAB chunk is 8 MB, a 16-row zip chunk 0.5 MB.
  const std::string dwab = write(t.dir, OIIO::TypeFloat, "dwab", 2048, 8);
  const std::string zip = write(t.dir, OIIO::TypeFloat, "zip", 2048, 8);
  const std::vector<std::string> names = {"R", "G", "B", "A"};
  auto a = ExrScanlineReader::open(dwab, names, 16u << 20, 8);
  ASSERT_TRUE(a);
  EXPECT_EQ(a->chunk_rows(), 256);
  EXPECT_EQ(a->chunks_kept(), 1);  // 2 x 8 MB: the budget holds one
  auto b = ExrScanlineReader::open(zip, names, 16u << 20, 8);
  ASSERT_TRUE(b);
  EXPECT_EQ(b->chunk_rows(), 16);
  EXPECT_EQ(b->chunks_kept(), 16);  // 16 x 2 x 0.5 MB, from 8 threads
  auto c = ExrScanlineReader::open(zip, names, 16u << 20, 2);
  EXPECT_EQ(c->chunks_kept(), 4);  // never more threads than workers
}

TEST(ExrScanlineReader, LeavesOtherFilesToOiio) {
  TempDir t;
  const std::string tiled = write(t.dir, OIIO::TypeHalf, "zip", 64, 64, true);
  EXPECT_FALSE(ExrScanlineReader::open(tiled, {"R", "G", "B", "A"}, 16u << 20, 2));
  const std::string plain = write(t.dir, OIIO::TypeHalf, "zip", 8, 8);
  EXPECT_FALSE(ExrScanlineReader::open(plain, {"R", "G", "B", "Z"}, 16u << 20, 2));
  EXPECT_FALSE(ExrScanlineReader::open((t.dir / "missing.exr").string(), {"R"}, 16u << 20, 2));
  // A file truncated after its header: opened, and a read says which file and rows.
  fs::resize_file(plain, fs::file_size(plain) - 40);
  auto r = ExrScanlineReader::open(plain, {"R", "G", "B", "A"}, 16u << 20, 2);
  if (r) {
    std::vector<float> row(8 * 4 * 8);
    try {
      r->read(0, 8, row.data());
      ADD_FAILURE() << "a truncated file read without an error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("cannot read rows 0..7"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace spectralize
