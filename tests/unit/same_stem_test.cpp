// Same-stem siblings (ingest/same_stem.h): files written here with the header maketx writes
// ("Software: OpenImageIO 2.4.7.1 : maketx a.tif -o a.tx", as stock maketx 2.4 wrote it when
// this test was made) and without; the expected decisions are written by hand.

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

std::string write(const fs::path& file, const std::string& software = "") {
  OIIO::ImageSpec spec(4, 4, 3, OIIO::TypeUInt8);
  if (!software.empty()) spec.attribute("Software", software);
  std::vector<unsigned char> px(4 * 4 * 3, 100);
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
  EXPECT_EQ(maketx_source(tx, {png, tif, tx}), tif);
  const std::string tx2 =
      write(t.dir / "tex/b.tx", "OpenImageIO 2.4.7.1 : maketx --hicomp lib/tex/a.png -o b.tx");
  EXPECT_EQ(maketx_source(tx2, {png, tif, tx2}), png);
  // A name that merely contains the file name is not it ("aa.tif").
  const std::string tx3 = write(t.dir / "tex/c.tx", "OpenImageIO 2.4.7.1 : maketx aa.tif -o c.tx");
  EXPECT_EQ(maketx_source(tx3, {tif, tx3}), "");
  EXPECT_EQ(maketx_source(png, {png, tif}), "");  // no maketx command line

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

}  // namespace
}  // namespace spectralize
