// The pixel kernel (pipeline/spectral_converter.h): the written bands of every in-gamut pixel
// integrate back to its colour (emission: its XYZ; reflectance: its XYZ white-balanced to the
// reference illuminant, docs/DESIGN.md §3) and reflectances stay in [0, 1]; alpha follows the
// rules of docs/DESIGN.md §9 (emission premultiplied, a reflectance the straight colour's
// spectrum times alpha, associated colour at alpha 0 kept as light, bad alpha clamped and
// counted); previews are the written samples integrated back; HALF output is rounded and
// clamped; every pixel is counted by kind. Oracles: the reference integration written again in
// tests/unit/test_support.h, the Rec.709 matrix written out there, and the colours each case
// constructs.

#include "pipeline/spectral_converter.h"

#include <Imath/half.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <vector>

#include "test_support.h"

namespace spectralize {
namespace {

const std::string kRec709 = "Linear Rec.709 (sRGB)";

const ColourSpaces& spaces() {
  static const ColourSpaces s = ColourSpaces::load();
  return s;
}

// A kernel as the image job sets it up: the spectralizer and table of the mode, the spectral
// OpenEXR layout with Linear Rec.709 previews, input in `input_space`.
struct Kernel {
  Settings settings;
  std::unique_ptr<Spectralizer> spectralizer;
  std::unique_ptr<SpectralTable> table;
  OIIO::ImageSpec input;
  std::unique_ptr<SpectralImageLayout> layout;
  std::unique_ptr<SpectralConverter> converter;
  int in_nch = 3, out_nch = 0, band0 = 0, preview0 = 0, alpha = -1;
  std::size_t bands = 0;

  Kernel(Mode mode, bool with_alpha, bool straight_alpha, bool half,
         const std::string& input_space = kRec709, ChannelRoles roles = {{0, 1, 2}, -1, {}}) {
    settings.colorspace = input_space;
    settings.preview_colorspace = kRec709;
    settings.mode = mode == Mode::emission ? ModeChoice::emission : ModeChoice::reflectance;
    settings.spectral.mode = mode;
    settings.half = half;
    spectralizer = std::make_unique<Spectralizer>(settings.spectral);
    table = std::make_unique<SpectralTable>(*spectralizer);
    if (with_alpha) roles.alpha = 3;
    in_nch = with_alpha ? 4 : static_cast<int>(std::max<std::size_t>(3, roles.colour.size()));
    input = OIIO::ImageSpec(16, 16, in_nch, OIIO::TypeFloat);
    layout = spectral_exr_layout(
        {input, with_alpha, settings, input_space, kRec709, spaces(), "2026:01:01 00:00:00"});
    converter = std::make_unique<SpectralConverter>(SpectralConverter::Setup{
        *spectralizer, *table, roles, in_nch, straight_alpha, spaces().to_xyz(input_space),
        spaces().from_xyz(kRec709), *layout, half, 2, nullptr});
    out_nch = layout->spec().nchannels;
    band0 = layout->band_channel();
    preview0 = layout->preview_channel();
    alpha = layout->alpha_channel();
    bands = settings.spectral.grid.size();
  }

  // Converts pixels given as in_nch floats each; returns the output pixels.
  std::vector<float> run(const std::vector<float>& in) {
    const std::size_t n = in.size() / static_cast<std::size_t>(in_nch);
    std::vector<float> out(n * static_cast<std::size_t>(out_nch), -999.0f);
    converter->convert(in.data(), n, out.data());
    return out;
  }
  std::vector<double> spectrum(const std::vector<float>& out, std::size_t pixel) const {
    const float* s = out.data() + pixel * static_cast<std::size_t>(out_nch) + band0;
    return std::vector<double>(s, s + bands);
  }
  // The XYZ of a written spectrum by the reference integration (reflectance: under the
  // reference illuminant, rho == 1 at Y = 1).
  Xyz integrated(const std::vector<double>& values) const {
    const Observer& obs = Observer::get(settings.spectral.observer);
    if (settings.spectral.mode == Mode::emission)
      return test::reference_xyz(settings.spectral.grid, values, obs, nullptr);
    const Illuminant e = Illuminant::get(settings.spectral.illuminant);
    return test::reference_xyz(settings.spectral.grid, values, obs, &e.spd);
  }
  // The reference white (rho == 1) over the D65 white: the white balance of a reflectance.
  Xyz balance() const {
    const Xyz w = integrated(std::vector<double>(bands, 1.0));
    const Xyz d65 = test::d65_white();
    return {w.X / d65.X, w.Y / d65.Y, w.Z / d65.Z};
  }
};

Xyz rec709(double r, double g, double b) {
  return test::rgb(test::kRec709ToXyz, r, g, b);
}

Xyz times(const Xyz& a, const Xyz& b) {
  return {a.X * b.X, a.Y * b.Y, a.Z * b.Z};
}

// Float samples and OCIO's float maths (docs/DESIGN.md §3: float files, 1e-5).
constexpr double kFloatTolerance = 1e-5;

// --- Colours ---

TEST(SpectralConverter, EmissionSamplesIntegrateBackToTheColour) {
  Kernel k(Mode::emission, false, false, false);
  const std::vector<std::array<float, 3>> colours = {
      {1, 1, 1}, {0.18f, 0.18f, 0.18f}, {0.8f, 0.2f, 0.1f}, {0.05f, 0.6f, 0.3f}, {40, 30, 20}};
  std::vector<float> in;
  for (const auto& c : colours) in.insert(in.end(), c.begin(), c.end());
  const std::vector<float> out = k.run(in);
  for (std::size_t p = 0; p < colours.size(); ++p) {
    SCOPED_TRACE(p);
    const Xyz expected = rec709(colours[p][0], colours[p][1], colours[p][2]);
    EXPECT_LT(test::rel_err(k.integrated(k.spectrum(out, p)), expected), kFloatTolerance);
    for (double v : k.spectrum(out, p)) {
      EXPECT_GE(v, 0.0);  // light is never negative
    }
  }
  const PixelCounts c = k.converter->counts();
  EXPECT_EQ(c.error_pixels, colours.size());
  EXPECT_LT(c.max_error, kFloatTolerance);
  EXPECT_EQ(c.invalid + c.negative + c.black + c.outside_locus + c.negative_component, 0u);
}

TEST(SpectralConverter, AReflectanceIsBoundedAndIntegratesToItsBalancedColour) {
  Kernel k(Mode::reflectance, false, false, false);
  const std::vector<std::array<float, 3>> colours = {
      {1, 1, 1}, {0.5f, 0.5f, 0.5f}, {0.6f, 0.3f, 0.2f}, {0.1f, 0.4f, 0.2f}, {0.05f, 0.05f, 0.3f}};
  std::vector<float> in;
  for (const auto& c : colours) in.insert(in.end(), c.begin(), c.end());
  const std::vector<float> out = k.run(in);
  const Xyz balance = k.balance();
  for (std::size_t p = 0; p < colours.size(); ++p) {
    SCOPED_TRACE(p);
    const Xyz expected = times(rec709(colours[p][0], colours[p][1], colours[p][2]), balance);
    EXPECT_LT(test::rel_err(k.integrated(k.spectrum(out, p)), expected), kFloatTolerance);
    for (double v : k.spectrum(out, p)) {
      EXPECT_GE(v, 0.0);
      EXPECT_LE(v, 1.0);
    }
  }
  // RGB (1, 1, 1) is the reference white itself.
  for (double v : k.spectrum(out, 0)) {
    EXPECT_NEAR(v, 1.0, 1e-5);
  }
}

TEST(SpectralConverter, PreviewsAreTheWrittenSamplesIntegratedBack) {
  // Emission: the preview is the light's RGB; a reflectance's is taken back to D65 terms, so a
  // grey surface previews as that grey.
  for (const Mode mode : {Mode::emission, Mode::reflectance}) {
    SCOPED_TRACE(mode == Mode::emission ? "emission" : "reflectance");
    Kernel k(mode, false, false, false);
    const std::vector<float> in = {0.5f, 0.5f, 0.5f, 0.6f, 0.3f, 0.2f};
    const std::vector<float> out = k.run(in);
    for (std::size_t p = 0; p < 2; ++p) {
      Xyz xyz = k.integrated(k.spectrum(out, p));
      if (mode == Mode::reflectance) {
        const Xyz b = k.balance();
        xyz = {xyz.X / b.X, xyz.Y / b.Y, xyz.Z / b.Z};
      }
      const Xyz rgb = test::mul(test::inverse(test::kRec709ToXyz), xyz);
      const float* preview = out.data() + p * static_cast<std::size_t>(k.out_nch) + k.preview0;
      EXPECT_NEAR(preview[0], rgb.X, kFloatTolerance) << p;
      EXPECT_NEAR(preview[1], rgb.Y, kFloatTolerance) << p;
      EXPECT_NEAR(preview[2], rgb.Z, kFloatTolerance) << p;
      // Within the kernel's exactness, the input colour itself.
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(preview[c], in[p * 3 + static_cast<std::size_t>(c)], 1e-4) << p;
      }
    }
  }
}

TEST(SpectralConverter, GreyAndReorderedChannelsAreTheSameColour) {
  Kernel rgb(Mode::emission, false, false, false);
  Kernel bgr(Mode::emission, false, false, false, kRec709, {{2, 1, 0}, -1, {}});
  Kernel grey(Mode::emission, false, false, false, kRec709, {{1}, -1, {}});
  const std::vector<float> a = rgb.run({0.7f, 0.4f, 0.2f, 0.3f, 0.3f, 0.3f});
  EXPECT_EQ(bgr.run({0.2f, 0.4f, 0.7f, 0.3f, 0.3f, 0.3f}), a);
  // Grey: channel 1 replicated (the others ignored).
  const std::vector<float> g = grey.run({9, 0.3f, 9});
  EXPECT_EQ(grey.spectrum(g, 0), rgb.spectrum(a, 1));
}

// --- Alpha (docs/DESIGN.md §9) ---

TEST(SpectralConverter, EmissionIsPremultipliedAndAssociatedLightAtAlphaZeroIsKept) {
  Kernel associated(Mode::emission, true, false, false);
  Kernel straight(Mode::emission, true, true, false);
  const float rgb[3] = {0.6f, 0.3f, 0.2f};
  for (const float a : {1.0f, 0.5f, 0.25f}) {
    SCOPED_TRACE(a);
    // Associated input: the colour as given is already premultiplied.
    const std::vector<float> o1 = associated.run({rgb[0], rgb[1], rgb[2], a});
    EXPECT_LT(test::rel_err(associated.integrated(associated.spectrum(o1, 0)),
                            rec709(rgb[0], rgb[1], rgb[2])),
              kFloatTolerance);
    EXPECT_EQ(o1[static_cast<std::size_t>(associated.alpha)], a);
    // Straight input: premultiplied by the kernel.
    const std::vector<float> o2 = straight.run({rgb[0], rgb[1], rgb[2], a});
    EXPECT_LT(test::rel_err(straight.integrated(straight.spectrum(o2, 0)),
                            a * rec709(rgb[0], rgb[1], rgb[2])),
              kFloatTolerance);
  }
  // Associated colour at alpha 0: additive light, kept.
  const std::vector<float> o = associated.run({0.2f, 0.1f, 0.05f, 0.0f});
  EXPECT_LT(test::rel_err(associated.integrated(associated.spectrum(o, 0)), rec709(0.2, 0.1, 0.05)),
            kFloatTolerance);
  EXPECT_EQ(o[static_cast<std::size_t>(associated.alpha)], 0.0f);
}

TEST(SpectralConverter, AReflectanceIsTheStraightColoursSpectrumTimesAlpha) {
  Kernel k(Mode::reflectance, true, false, false);
  const float a = 0.4f;
  const float straight[3] = {0.9f, 0.7f, 0.5f};  // bright: its spectrum reaches near 1
  const std::vector<float> out = k.run({straight[0] * a, straight[1] * a, straight[2] * a, a,
                                        straight[0], straight[1], straight[2], 1.0f});
  const std::vector<double> covered = k.spectrum(out, 0), full = k.spectrum(out, 1);
  for (std::size_t i = 0; i < k.bands; ++i) {
    EXPECT_NEAR(covered[i], a * full[i], 1e-6) << i;  // the bound applies to the surface
    EXPECT_LE(covered[i], a + 1e-6) << i;
  }
  const Xyz expected = times(rec709(straight[0], straight[1], straight[2]), k.balance());
  EXPECT_LT(test::rel_err(k.integrated(covered), a * expected), kFloatTolerance);
}

TEST(SpectralConverter, BadAlphaIsClampedAndCounted) {
  Kernel k(Mode::emission, true, true, false);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<float> out = k.run({0.5f, 0.5f, 0.5f, nan, 0.5f, 0.5f, 0.5f, 1.5f, 0.5f, 0.5f,
                                        0.5f, -0.2f, 0.5f, 0.5f, 0.5f, 0.3f});
  const float expected[4] = {0.0f, 1.0f, 0.0f, 0.3f};
  for (std::size_t p = 0; p < 4; ++p) {
    EXPECT_EQ(out[p * static_cast<std::size_t>(k.out_nch) + static_cast<std::size_t>(k.alpha)],
              expected[p])
        << p;
  }
  EXPECT_EQ(k.converter->counts().alpha_invalid, 3u);
  // Alpha 0 on straight colour: no light at all.
  for (double v : k.spectrum(out, 0)) {
    EXPECT_EQ(v, 0.0);
  }
}

// --- Counts, HALF, threads ---

TEST(SpectralConverter, EveryPixelIsCountedByKind) {
  Kernel k(Mode::emission, false, false, false);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // clang-format off
  const std::vector<float> out = k.run({
      0.2f, 0.3f, 0.4f,    // in gamut
      nan, 0.3f, 0.4f,     // invalid
      0.0f, 0.0f, 0.0f,    // black
      -1, -1, -1,          // negative luminance
      1.0f, -0.01f, 0.5f,  // a negative component (still a colour)
  });
  // clang-format on
  const PixelCounts c = k.converter->counts();
  EXPECT_EQ(c.invalid, 1u);
  EXPECT_EQ(c.black, 1u);
  EXPECT_EQ(c.negative, 1u);
  EXPECT_EQ(c.negative_component, 2u);
  for (std::size_t p : {1u, 2u, 3u})
    for (double v : k.spectrum(out, p)) {
      EXPECT_EQ(v, 0.0) << "pixel " << p;
    }
  // A colour outside the spectral locus (XYZ input: Y alone, x = 0, y = 1) is mapped into it.
  Kernel xyz(Mode::emission, false, false, false, "CIE-XYZ-D65");
  xyz.run({0.0f, 1.0f, 0.0f});
  EXPECT_EQ(xyz.converter->counts().outside_locus, 1u);
  // A reflectance brighter than white is counted (and mapped into the reflectance solid).
  Kernel r(Mode::reflectance, false, false, false);
  const std::vector<float> bright = r.run({2, 2, 2, 0.5f, 0.5f, 0.5f});
  EXPECT_EQ(r.converter->counts().brighter_than_white, 1u);
  for (double v : r.spectrum(bright, 0)) {
    EXPECT_LE(v, 1.0);
  }
  // Counts add up over calls.
  k.run({0.0f, 0.0f, 0.0f});
  EXPECT_EQ(k.converter->counts().black, 2u);
}

TEST(SpectralConverter, AnInfiniteReflectanceIsInvalidNotBrighterThanWhite) {
  // Written as the zero spectrum, so not "dimmed into the reflectance solid": one count, one
  // warning (pipeline/image_report.h count_warnings).
  Kernel k(Mode::reflectance, false, false, false);
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<float> out = k.run({0.2f, inf, 0.1f, inf, inf, inf, 2, 2, 2});
  const PixelCounts c = k.converter->counts();
  EXPECT_EQ(c.invalid, 2u);
  EXPECT_EQ(c.brighter_than_white, 1u);  // only (2, 2, 2)
  for (std::size_t p : {0u, 1u})
    for (double v : k.spectrum(out, p)) {
      EXPECT_EQ(v, 0.0) << "pixel " << p;
    }
}

TEST(SpectralConverter, HalfOutputIsRoundedAndClampedToHalf) {
  // The bands are HALF values (the error is measured on what is written); every channel,
  // previews too, is within HALF's range.
  Kernel k(Mode::emission, false, false, true);
  const std::vector<float> out = k.run({0.3f, 0.2f, 0.1f, 1e5f, 1e5f, 1e5f});
  for (std::size_t p = 0; p < 2; ++p)
    for (int c = 0; c < k.out_nch; ++c) {
      const float v = out[p * static_cast<std::size_t>(k.out_nch) + static_cast<std::size_t>(c)];
      if (c >= k.band0) {
        EXPECT_EQ(static_cast<float>(Imath::half(v)), v) << "pixel " << p << " channel " << c;
      }
      EXPECT_LE(std::abs(v), 65504.0f) << "pixel " << p << " channel " << c;
    }
  EXPECT_EQ(k.converter->counts().half_overflow, 1u);
  // Rounding to HALF keeps the colour to its 11 bits (docs/DESIGN.md §3).
  EXPECT_LT(test::rel_err(k.integrated(k.spectrum(out, 0)), rec709(0.3, 0.2, 0.1)), 2e-3);
}

TEST(SpectralConverter, ManyPixelsOnSeveralThreadsAreEachConvertedAlone) {
  // More pixels than one chunk of work: each is the same as when converted alone.
  Kernel many(Mode::reflectance, false, false, false);
  Kernel one(Mode::reflectance, false, false, false);
  const float palette[4][3] = {
      {0.2f, 0.4f, 0.6f}, {0.9f, 0.1f, 0.1f}, {0.5f, 0.5f, 0.5f}, {0.0f, 0.0f, 0.0f}};
  const std::size_t n = 5000;
  std::vector<float> in;
  for (std::size_t p = 0; p < n; ++p) in.insert(in.end(), palette[p % 4], palette[p % 4] + 3);
  const std::vector<float> out = many.run(in);
  std::vector<std::vector<float>> alone;
  for (const auto& c : palette) alone.push_back(one.run({c[0], c[1], c[2]}));
  for (std::size_t p = 0; p < n; ++p) {
    ASSERT_TRUE(std::equal(alone[p % 4].begin(), alone[p % 4].end(),
                           out.begin() + static_cast<std::ptrdiff_t>(p) * many.out_nch))
        << "pixel " << p;
  }
  EXPECT_EQ(many.converter->counts().black, n / 4);
  EXPECT_EQ(many.converter->counts().error_pixels, 3 * n / 4);
}

}  // namespace
}  // namespace spectralize
