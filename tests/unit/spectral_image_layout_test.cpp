// The layout of a written spectral image (pipeline/spectral_image_layout.h) against
// docs/DESIGN.md §7: R, G, B previews, A only when the input has alpha, then one band per
// wavelength of the grid by increasing wavelength, named "S0.<nm>nm" (emission) or "T.<nm>nm"
// (reflectance) with six decimals and a decimal comma; spectralLayoutVersion "1.0",
// emissiveUnits for emission only; the settings as spectralize:* attributes; the input's
// descriptive metadata carried over but never its colour tags or encoding; the previews tagged
// with their own space. The bare layout of arrays holds the bands only. Oracles: the channel
// names written out here from §7's rule, the grid's wavelengths, the CIE xy of the Rec.709 and
// AP1 primaries as published, and the attributes each case puts in.

#include "pipeline/spectral_image_layout.h"

#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "file_test_support.h"
#include "spectralize/version.h"

namespace spectralize {
namespace {

const std::string kRec709 = "Linear Rec.709 (sRGB)";

const ColourSpaces& spaces() {
  static const ColourSpaces s = ColourSpaces::load();
  return s;
}

// "<prefix><nm with six decimals, a comma for the point>nm", as §7 writes it.
std::string band_name(const std::string& prefix, double nm) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", nm);
  std::string number = buf;
  for (char& c : number)
    if (c == '.') c = ',';
  return prefix + number + "nm";
}

Settings settings_of(Mode mode, bool half = false) {
  Settings s;
  s.colorspace = kRec709;
  s.preview_colorspace = kRec709;
  s.mode = mode == Mode::emission ? ModeChoice::emission : ModeChoice::reflectance;
  s.spectral.mode = mode;
  s.half = half;
  return s;
}

struct Made {
  OIIO::ImageSpec input{8, 4, 3, OIIO::TypeFloat};
  std::unique_ptr<SpectralImageLayout> layout;
  const OIIO::ImageSpec& spec() const { return layout->spec(); }
};

Made make(const Settings& s, bool alpha, const std::string& preview = kRec709,
          OIIO::ImageSpec input = OIIO::ImageSpec(8, 4, 3, OIIO::TypeFloat),
          std::map<std::string, std::string> attributes = {},
          std::vector<std::pair<std::string, double>> numbers = {}) {
  Made m;
  m.input = std::move(input);
  m.layout =
      spectral_exr_layout({m.input, alpha, s, s.colorspace, preview, spaces(),
                           "2026:03:04 05:06:07", std::move(attributes), std::move(numbers)});
  return m;
}

TEST(SpectralImageLayout, EmissionIsPreviewsThenS0BandsByIncreasingWavelength) {
  const Settings s = settings_of(Mode::emission);
  const Made m = make(s, false);
  const OIIO::ImageSpec& spec = m.spec();
  ASSERT_EQ(spec.nchannels, 3 + 81);  // the default grid, 380:780:5
  EXPECT_EQ(spec.channelnames[0], "R");
  EXPECT_EQ(spec.channelnames[1], "G");
  EXPECT_EQ(spec.channelnames[2], "B");
  EXPECT_EQ(m.layout->preview_channel(), 0);
  EXPECT_EQ(m.layout->band_channel(), 3);
  EXPECT_EQ(m.layout->alpha_channel(), -1);
  // 84 channels, none of them alpha (an ImageSpec of 4 or more channels would take channel 3).
  EXPECT_EQ(spec.alpha_channel, -1);
  EXPECT_EQ(spec.channelnames[3], "S0.380,000000nm");
  EXPECT_EQ(spec.channelnames[83], "S0.780,000000nm");
  for (int i = 0; i < 81; ++i) EXPECT_EQ(spec.channelnames[3 + i], band_name("S0.", 380 + 5 * i));
  EXPECT_EQ(spec.get_string_attribute("spectralLayoutVersion"), "1.0");
  EXPECT_EQ(spec.get_string_attribute("emissiveUnits"), "W.m^-2.sr^-1");
}

TEST(SpectralImageLayout, AReflectanceWithAlphaHasAThenTBandsAndNoEmissiveUnits) {
  Settings s = settings_of(Mode::reflectance);
  s.spectral.grid = WavelengthGrid(400, 700, 10);
  const Made m = make(s, true);
  const OIIO::ImageSpec& spec = m.spec();
  ASSERT_EQ(spec.nchannels, 4 + 31);
  EXPECT_EQ(spec.channelnames[3], "A");
  EXPECT_EQ(spec.alpha_channel, 3);
  EXPECT_EQ(m.layout->alpha_channel(), 3);
  EXPECT_EQ(m.layout->band_channel(), 4);
  EXPECT_EQ(m.layout->preview_channel(), 0);
  for (int i = 0; i < 31; ++i) EXPECT_EQ(spec.channelnames[4 + i], band_name("T.", 400 + 10 * i));
  EXPECT_EQ(spec.get_string_attribute("spectralLayoutVersion"), "1.0");
  EXPECT_EQ(spec.find_attribute("emissiveUnits"), nullptr);  // reflectances have no units
  EXPECT_EQ(spec.get_string_attribute("spectralize:mode"), "reflectance");
  EXPECT_EQ(spec.get_string_attribute("spectralize:wavelengths"), "400:700:10");
}

TEST(SpectralImageLayout, SizeWindowsSampleTypeTilesAndCompressionFollowTheRequest) {
  OIIO::ImageSpec input(8, 4, 3, OIIO::TypeUInt8);  // the input's type does not carry over
  input.x = 3, input.y = -2;
  input.full_x = 1, input.full_y = -5, input.full_width = 20, input.full_height = 11;
  Settings s = settings_of(Mode::emission, true);
  s.compression = "piz";
  s.tile_width = 32, s.tile_height = 16;
  const Made half = make(s, false, kRec709, input);
  EXPECT_EQ(half.spec().format, OIIO::TypeHalf);
  EXPECT_EQ(half.spec().width, 8);
  EXPECT_EQ(half.spec().height, 4);
  EXPECT_EQ(half.spec().x, 3);
  EXPECT_EQ(half.spec().y, -2);
  EXPECT_EQ(half.spec().full_x, 1);
  EXPECT_EQ(half.spec().full_y, -5);
  EXPECT_EQ(half.spec().full_width, 20);
  EXPECT_EQ(half.spec().full_height, 11);
  EXPECT_EQ(half.spec().tile_width, 32);
  EXPECT_EQ(half.spec().tile_height, 16);
  EXPECT_EQ(half.spec().get_string_attribute("compression"), "piz");
  s.half = false;
  s.tile_width = s.tile_height = 0;
  const Made flt = make(s, false, kRec709, input);
  EXPECT_EQ(flt.spec().format, OIIO::TypeFloat);
  EXPECT_EQ(flt.spec().tile_width, 0);  // scanlines
}

TEST(SpectralImageLayout, DescriptiveMetadataIsCarriedOverButNeverTheInputsTagsOrEncoding) {
  OIIO::ImageSpec input(8, 4, 3, OIIO::TypeFloat);
  input.attribute("Artist", "Ada");
  input.attribute("Copyright", "CC0");
  input.attribute("oiio:ColorSpace", "ACEScg");
  input.attribute("colorInteropID", "lin_ap1_scene");
  const float ap0[8] = {0.7347f, 0.2653f, 0.0f, 1.0f, 0.0001f, -0.077f, 0.32168f, 0.33767f};
  input.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), ap0);
  input.attribute("compression", "dwaa");
  input.attribute("DateTime", "1999:01:01 00:00:00");
  input.attribute("spectralize:mode", "reflectance");  // a stale record of another conversion
  const Made m = make(settings_of(Mode::emission), false, kRec709, input);
  const OIIO::ImageSpec& spec = m.spec();
  EXPECT_EQ(spec.get_string_attribute("Artist"), "Ada");
  EXPECT_EQ(spec.get_string_attribute("Copyright"), "CC0");
  EXPECT_EQ(spec.get_string_attribute("oiio:ColorSpace"),
            test::oiio_colour_space(kRec709, "lin_rec709_scene"));
  EXPECT_NE(spec.get_string_attribute("colorInteropID"), "lin_ap1_scene");
  EXPECT_EQ(spec.get_string_attribute("compression"), "zip");  // the settings'
  EXPECT_EQ(spec.get_string_attribute("DateTime"), "2026:03:04 05:06:07");
  EXPECT_EQ(spec.get_string_attribute("spectralize:mode"), "emission");
  EXPECT_EQ(spec.get_string_attribute("Software"), "spectralize " SPECTRALIZE_VERSION);
  EXPECT_EQ(spec.get_string_attribute("spectralize:version"), SPECTRALIZE_VERSION);
  // Each attribute once: nothing of the input's shadows what the layout sets.
  std::map<std::string, int> seen;
  for (const auto& p : spec.extra_attribs) ++seen[p.name().string()];
  for (const auto& [name, n] : seen) EXPECT_EQ(n, 1) << name;
}

TEST(SpectralImageLayout, PreviewsAreTaggedWithTheirOwnSpacesPrimaries) {
  // Rec.709 (IEC 61966-2-1) and AP1 with the ACES white (SMPTE ST 2065-1 / S-2014-004).
  struct Case {
    std::string preview, id;
    std::array<float, 8> xy;
  };
  const Case cases[] = {
      {kRec709, "lin_rec709_scene", {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f}},
      {"ACEScg",
       "lin_ap1_scene",
       {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f}}};
  for (const auto& [preview, id, xy] : cases) {
    SCOPED_TRACE(preview);
    const Made m = make(settings_of(Mode::reflectance), false, preview);
    EXPECT_EQ(m.layout->preview_colorspace(), preview);
    EXPECT_EQ(m.spec().get_string_attribute("oiio:ColorSpace"),
              test::oiio_colour_space(preview, id));
    float got[8] = {};
    ASSERT_TRUE(
        m.spec().getattribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), got));
    for (int k = 0; k < 8; ++k) EXPECT_NEAR(got[k], xy[k], 1e-4) << k;
  }
}

TEST(SpectralImageLayout, TheRequestsAttributesAndNumbersAreRecordedAsGiven) {
  const double big = 9007199254740991.0;  // 2^53 - 1: a double attribute holds it exactly
  const Made m =
      make(settings_of(Mode::emission), false, kRec709, OIIO::ImageSpec(8, 4, 3, OIIO::TypeFloat),
           {{"spectralize:modeReason", "--mode emission"}, {"custom", "x"}},
           {{"spectralize:invalidPixels", big}, {"spectralize:zero", 0.0}});
  const OIIO::ImageSpec& spec = m.spec();
  EXPECT_EQ(spec.get_string_attribute("spectralize:modeReason"), "--mode emission");
  EXPECT_EQ(spec.get_string_attribute("custom"), "x");
  for (const auto& [name, want] : {std::pair<std::string, double>{"spectralize:invalidPixels", big},
                                   {"spectralize:zero", 0.0}}) {
    const OIIO::ParamValue* p = spec.find_attribute(name);
    ASSERT_NE(p, nullptr) << name;
    EXPECT_EQ(p->type(), OIIO::TypeDesc::DOUBLE) << name;
    double v = -1;
    ASSERT_TRUE(spec.getattribute(name, OIIO::TypeDesc::DOUBLE, &v));
    EXPECT_EQ(v, want) << name;
  }
}

TEST(SpectralImageLayout, TheSettingsAreRecordedAsResolvedForTheFile) {
  Settings s = settings_of(Mode::reflectance);
  s.colorspace = "sRGB - Texture";  // the space decided for the input
  s.spectral.illuminant = "A";
  s.spectral.observer = "cie1964";
  const Made m = make(s, false);
  const OIIO::ImageSpec& spec = m.spec();
  EXPECT_EQ(spec.get_string_attribute("spectralize:colorspace"), "sRGB - Texture");
  EXPECT_EQ(spec.get_string_attribute("spectralize:illuminant"), "A");
  EXPECT_EQ(spec.get_string_attribute("spectralize:observer"), "cie1964");
  EXPECT_EQ(spec.get_string_attribute("spectralize:mode"), "reflectance");
  // How a job runs is not what the file is: no threads, cache or config attributes.
  for (const auto& p : spec.extra_attribs) {
    const std::string name = p.name().string();
    EXPECT_NE(name, "spectralize:threads");
    EXPECT_NE(name, "spectralize:cache");
  }
}

TEST(SpectralImageLayout, BareSpectraAreTheBandsOnlyAsFloats) {
  SpectralizerSettings sp;
  sp.grid = WavelengthGrid(400, 700, 20);
  for (const Mode mode : {Mode::emission, Mode::reflectance}) {
    sp.mode = mode;
    const auto layout = bare_spectra_layout(sp);
    const OIIO::ImageSpec& spec = layout->spec();
    ASSERT_EQ(spec.nchannels, 16);
    EXPECT_EQ(spec.width, 1);
    EXPECT_EQ(spec.height, 1);
    EXPECT_EQ(spec.format, OIIO::TypeFloat);
    EXPECT_EQ(spec.alpha_channel, -1);  // 16 channels, none alpha
    EXPECT_EQ(layout->band_channel(), 0);
    EXPECT_EQ(layout->preview_channel(), -1);
    EXPECT_EQ(layout->alpha_channel(), -1);
    EXPECT_EQ(layout->preview_colorspace(), "");
    const std::string prefix = mode == Mode::emission ? "S0." : "T.";
    for (int i = 0; i < 16; ++i) EXPECT_EQ(spec.channelnames[i], band_name(prefix, 400 + 20 * i));
  }
}

}  // namespace
}  // namespace spectralize
