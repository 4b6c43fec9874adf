// Same-stem siblings (ingest/same_stem.h): files written here with the header maketx writes
// ("Software: OpenImageIO 2.4.7.1 : maketx a.tif -o a.tx", as stock maketx 2.4 wrote it when
// this test was made; "OpenImageIO 3.1.18.1 : <a hash>" and a textureformat, as maketx 3.1 writes
// it without --history) and without; the expected decisions are written by hand.

#include "ingest/same_stem.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "file_test_support.h"

namespace spectralize {
namespace {

namespace fs = std::filesystem;

// A fresh folder with an empty tex/ in it.
struct TempDir : test::TempDir {
  TempDir() : test::TempDir("same_stem") { fs::create_directories(dir / "tex"); }
};

std::string write(const fs::path& file, const std::string& software = "", int side = 4,
                  bool texture = false, unsigned char value = 100) {
  OIIO::ImageSpec spec(side, side, 3, OIIO::TypeUInt8);
  if (!software.empty()) spec.attribute("Software", software);
  if (texture) spec.attribute("textureformat", "Plain Texture");
  std::vector<unsigned char> px(static_cast<std::size_t>(side) * side * 3, value);
  auto out = OIIO::ImageOutput::create(file.string());
  EXPECT_TRUE(out && out->open(file.string(), spec));
  EXPECT_TRUE(out->write_image(OIIO::TypeUInt8, px.data()));
  out->close();
  return file.string();
}

TEST(SameStem, ADerivedTextureIsItsSourcesAssetOthersKeepTheirOwnNames) {
  TempDir t;
  const std::string png = write(t.dir / "tex/a.png");
  const std::string tif = write(t.dir / "tex/a.tif");
  // maketx run in tex/, and run from elsewhere with a path.
  const std::string tx = write(t.dir / "tex/a.tx", "OpenImageIO 2.4.7.1 : maketx a.tif -o a.tx");
  EXPECT_EQ(texture_source(tx, {png, tif, tx}).source, tif);
  EXPECT_EQ(texture_source(tx, {png, tif, tx}).how, "its header's command line");
  const std::string tx2 =
      write(t.dir / "tex/b.tx", "OpenImageIO 2.4.7.1 : maketx --hicomp lib/tex/a.png -o b.tx");
  EXPECT_EQ(texture_source(tx2, {png, tif, tx2}).source, png);
  // A name that merely contains the file name is not it ("aa.tif").
  const std::string tx3 = write(t.dir / "tex/c.tx", "OpenImageIO 2.4.7.1 : maketx aa.tif -o c.tx");
  EXPECT_EQ(texture_source(tx3, {tif, tx3}).source, "");
  EXPECT_EQ(texture_source(png, {png, tif}).source, "");  // no command line, no texture

  // a.png, a.tif, a.tx (from a.tif): the .tx follows the .tif, the two others keep both.
  auto d = decide_same_stem({png, tif, tx}, "tex/a.exr");
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[0].relative, "tex/a.png.exr");
  EXPECT_EQ(d[1].relative, "tex/a.tif.exr");
  EXPECT_EQ(d[2].relative, "tex/a.tif.exr");
  EXPECT_EQ(d[2].derived_from, tif);
  EXPECT_TRUE(d[0].derived_from.empty());
  EXPECT_NE(d[2].note.find("maketx"), std::string::npos);
  EXPECT_NE(d[0].note.find("a.tif"), std::string::npos);
  // a.tif and its a.tx: one asset, the output keeps its plain name.
  d = decide_same_stem({tx, tif}, "tex/a.exr");
  EXPECT_EQ(d[0].relative, "tex/a.exr");
  EXPECT_EQ(d[0].derived_from, tif);
  EXPECT_EQ(d[1].relative, "tex/a.exr");
  EXPECT_TRUE(d[1].note.empty());
  // Unrelated images of one name: both kept.
  const std::string jpg = write(t.dir / "tex/a.jpg");
  d = decide_same_stem({png, jpg}, "tex/a.exr");
  EXPECT_EQ(d[0].relative, "tex/a.png.exr");
  EXPECT_EQ(d[1].relative, "tex/a.jpg.exr");
}

// maketx of OIIO 3 records no command line (unless --history): a texture is made from the one
// image of its name whose pixels it holds, and from none when two could be.
TEST(SameStem, ATextureWithoutACommandLineIsMadeFromTheOneImageWhosePixelsItHolds) {
  TempDir t;
  const std::string tif = write(t.dir / "tex/a.tif", "", 4);
  const std::string big = write(t.dir / "tex/a.png", "", 8);
  const std::string other = write(t.dir / "tex/a.bmp", "", 4, false, 30);  // its size, not pixels
  const std::string tx =
      write(t.dir / "tex/a.tx", "OpenImageIO 3.1.18.1 : 3F22E6CFC2B33ED564501A121671555CC6508E7E",
            4, true);
  const TextureSource found = texture_source(tx, {big, other, tif, tx});
  EXPECT_EQ(found.source, tif);
  EXPECT_NE(found.how.find("pixels"), std::string::npos) << found.how;
  auto d = decide_same_stem({big, tif, tx}, "tex/a.exr");
  ASSERT_EQ(d.size(), 3u);
  EXPECT_EQ(d[2].derived_from, tif);
  EXPECT_EQ(d[2].relative, "tex/a.tif.exr");
  EXPECT_NE(d[2].note.find("records no command line"), std::string::npos) << d[2].note;
  // Two images of its pixels: neither is assumed.
  const std::string tga = write(t.dir / "tex/a.tga", "", 4);
  EXPECT_EQ(texture_source(tx, {big, tif, tga, tx}).source, "");
  // One of its size with other pixels only: made from none.
  EXPECT_EQ(texture_source(tx, {big, other, tx}).source, "");
  // An image without a texture format and without a command line is made from nothing.
  EXPECT_EQ(texture_source(tif, {big, tif, tx}).source, "");
}

}  // namespace
}  // namespace spectralize
