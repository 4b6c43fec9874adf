// Light or surface (classify/light_or_surface.h): the order of the clues, decided by hand for each
// combination, and the brightest pixel of generated images read back by the real reader.

#include "classify/light_or_surface.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "classify/input_interpretation.h"
#include "file_test_support.h"

namespace spectralize {
namespace {

ModeClues clues(MapKind name, bool float_data, int w, int h, double peak, int* reads = nullptr) {
  ModeClues c;
  c.name.kind = name;
  c.name.reason = "name word 'x'";
  c.float_data = float_data;
  c.can_exceed_white = float_data;
  c.colorspace = "Linear Rec.709 (sRGB)";
  c.width = w;
  c.height = h;
  c.brightest = [peak, reads] {
    if (reads) ++*reads;
    return Brightest{peak, 3, true};
  };
  return c;
}

TEST(LightOrSurface, TheCluesInTheirOrder) {
  struct Case {
    const char* what;
    ModeClues c;
    Mode mode;
    std::size_t warnings;
  };
  ModeClues asked = clues(MapKind::emission, true, 64, 32, 50);
  asked.asked = ModeChoice::reflectance;
  const Case cases[] = {
      {"--mode outranks a light word", asked, Mode::reflectance, 0},
      {"a surface word outranks a bright image", clues(MapKind::reflectance, true, 64, 32, 50),
       Mode::reflectance, 0},
      {"a light word outranks a dim 8-bit image", clues(MapKind::emission, false, 64, 64, 0.5),
       Mode::emission, 0},
      {"8-bit, no word: a surface", clues(MapKind::none, false, 64, 32, 0.9), Mode::reflectance, 0},
      {"float within white: a surface", clues(MapKind::none, true, 64, 64, 0.93), Mode::reflectance,
       0},
      {"float within white, 2:1: a surface, warned", clues(MapKind::none, true, 64, 32, 0.93),
       Mode::reflectance, 1},
      {"float above white: light", clues(MapKind::none, true, 64, 64, 40), Mode::emission, 0},
      {"float above white, 2:1: light", clues(MapKind::none, true, 64, 32, 40), Mode::emission, 0},
      {"float barely above white: light, warned", clues(MapKind::none, true, 64, 64, 1.2),
       Mode::emission, 1},
      {"data says nothing about the mode: the image decides",
       clues(MapKind::data, true, 64, 64, 40), Mode::emission, 0},
  };
  // What spectralize recorded on RGB it made from spectra, after --mode and the words.
  ModeClues recorded = clues(MapKind::none, true, 64, 64, 40);
  recorded.recorded_mode = "reflectance";
  ModeClues recorded_light = clues(MapKind::none, false, 64, 64, 0.5);
  recorded_light.recorded_mode = "emission";
  ModeClues worded = clues(MapKind::emission, true, 64, 64, 0.5);
  worded.recorded_mode = "reflectance";
  ModeClues garbled = clues(MapKind::none, true, 64, 64, 40);
  garbled.recorded_mode = "glossy";
  const Case more[] = {
      {"a recorded surface outranks a bright image", recorded, Mode::reflectance, 0},
      {"a recorded light outranks 8-bit data", recorded_light, Mode::emission, 0},
      {"a light word outranks a recorded surface", worded, Mode::emission, 0},
      {"an unknown record is no clue", garbled, Mode::emission, 0},
  };
  for (const Case& k : more) {
    const ModeDecision d = decide_mode(k.c);
    EXPECT_EQ(d.mode, k.mode) << k.what << ": " << d.reason;
    EXPECT_EQ(d.warnings.size(), k.warnings) << k.what;
  }
  for (const Case& k : cases) {
    const ModeDecision d = decide_mode(k.c);
    EXPECT_EQ(d.mode, k.mode) << k.what << ": " << d.reason;
    EXPECT_EQ(d.warnings.size(), k.warnings) << k.what;
    EXPECT_FALSE(d.reason.empty()) << k.what;
  }
  // The image is read only when the earlier clues leave the decision open.
  int reads = 0;
  decide_mode(clues(MapKind::reflectance, true, 64, 64, 40, &reads));
  decide_mode(clues(MapKind::none, false, 64, 64, 0.5, &reads));
  ModeClues known = clues(MapKind::none, true, 64, 64, 40, &reads);
  known.recorded_mode = "emission";
  decide_mode(known);
  EXPECT_EQ(reads, 0);
  decide_mode(clues(MapKind::none, true, 64, 64, 0.5, &reads));
  EXPECT_EQ(reads, 1);
}

struct TempDir : test::TempDir {
  TempDir() : test::TempDir("mode_clues") {}
};

// A float RGB image of `value` everywhere but pixel (x, y), which is `spot`.
std::string write_exr(const std::filesystem::path& file, int w, int h, float value, int x, int y,
                      float spot, bool tiled = false) {
  OIIO::ImageSpec spec(w, h, 3, OIIO::TypeFloat);
  if (tiled) spec.tile_width = spec.tile_height = 16;
  std::vector<float> px(static_cast<std::size_t>(w) * h * 3, value);
  for (int c = 0; c < 3; ++c) px[(static_cast<std::size_t>(y) * w + x) * 3 + c] = spot;
  auto out = OIIO::ImageOutput::create(file.string());
  EXPECT_TRUE(out && out->open(file.string(), spec));
  EXPECT_TRUE(out->write_image(OIIO::TypeFloat, px.data()));
  out->close();
  return file.string();
}

TEST(LightOrSurface, TheBrightestPixelOfTheImage) {
  TempDir t;
  const ColourSpaces spaces = ColourSpaces::load();
  const ColourTransform to_xyz = spaces.to_xyz("Linear Rec.709 (sRGB)");
  ChannelRoles rgb;
  rgb.colour = {0, 1, 2};
  // One bright pixel in the last row, scanline and tiled: found, Y of (8, 8, 8) is 8.
  for (const bool tiled : {false, true}) {
    const std::string f =
        write_exr(t.dir / (tiled ? "t.exr" : "s.exr"), 40, 37, 0.2f, 5, 36, 8, tiled);
    const Brightest b = brightest_pixel(f, rgb, to_xyz, 1e30);
    EXPECT_NEAR(b.y, 8.0, 1e-4);
    EXPECT_EQ(b.row, 36);
    EXPECT_TRUE(b.complete);
  }
  // Within white everywhere: the peak is the brightest value, read to the end.
  const std::string dim = write_exr(t.dir / "dim.exr", 33, 20, 0.25f, 0, 0, 0.9f);
  Brightest b = brightest_pixel(dim, rgb, to_xyz, kClearlyLightY);
  EXPECT_NEAR(b.y, 0.9, 1e-5);
  EXPECT_TRUE(b.complete);
  // Reading stops at a clearly bright pixel.
  const std::string sun = write_exr(t.dir / "sun.exr", 64, 2000, 0.5f, 3, 1, 5e4f);
  b = brightest_pixel(sun, rgb, to_xyz, kClearlyLightY);
  EXPECT_GT(b.y, kClearlyLightY);
  EXPECT_FALSE(b.complete);
  // Through interpret_input: the float texture is a surface, the bright one light.
  Settings s;
  OIIO::ImageSpec spec(33, 20, 3, OIIO::TypeFloat);
  EXPECT_EQ(interpret_input(dim, spec, s, spaces).mode, Mode::reflectance);
  spec = OIIO::ImageSpec(64, 2000, 3, OIIO::TypeFloat);
  EXPECT_EQ(interpret_input(sun, spec, s, spaces).mode, Mode::emission);
}

}  // namespace
}  // namespace spectralize
