// Spectral files back to RGB (pipeline/rgb_from_spectral.h): the spectral channels of a spec are
// found in wavelength order whatever their order and unit, ambiguous files are refused naming
// the file; a constant reflectance rho is RGB (rho, rho, rho) in every linear space under every
// illuminant (the white balance of docs/DESIGN.md §3); emission spectra and reflectances lit
// "as lit" integrate to the XYZ the reference integration of docs/DESIGN.md §3 gives; invalid
// samples count as 0 and values beyond the output type are clamped and counted. Oracles: the
// CIE tables of data/ read here from their CSV files with the trapezoid rule written here on
// the piecewise-linear spectrum, the Rec.709 matrix of tests/unit/test_support.h, and the
// numbers each case constructs.

#include "pipeline/rgb_from_spectral.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "file_test_support.h"
#include "spectralize/core/error.h"
#include "test_support.h"

namespace spectralize {
namespace {

// --- The CIE tables, read from data/ ---

// Column `column` of data/<file> at 1 nm from 360 to 830 nm.
std::vector<double> table_column(const std::string& file, const std::string& column) {
  std::ifstream in(SPECTRALIZE_SOURCE_DIR "/data/" + file);
  EXPECT_TRUE(in) << file;
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  {
    std::stringstream header(line);
    for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  }
  const auto at = std::find(names.begin(), names.end(), column);
  EXPECT_NE(at, names.end()) << column;
  const std::size_t index = static_cast<std::size_t>(at - names.begin());
  std::vector<double> values(471, std::numeric_limits<double>::quiet_NaN());
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::vector<double> cells;
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(std::stod(cell));
    const int nm = static_cast<int>(std::lround(cells[0]));
    if (nm >= 360 && nm <= 830) values[static_cast<std::size_t>(nm - 360)] = cells[index];
  }
  for (double v : values) {
    EXPECT_TRUE(std::isfinite(v)) << file << " lacks a wavelength";
  }
  return values;
}

struct Cmf {
  std::vector<double> x, y, z;
};
Cmf cmf(const std::string& observer) {
  const std::string file =
      observer == "cie1964" ? "cie1964_10deg_cmf_1nm.csv" : "cie1931_2deg_cmf_1nm.csv";
  return {table_column(file, "xbar"), table_column(file, "ybar"), table_column(file, "zbar")};
}

std::vector<double> illuminant(const std::string& name) {
  return table_column("cie_illuminant_" + name + "_1nm.csv", "value");
}

// The value at `nm` of the piecewise-linear spectrum through (bands, values), zero outside.
double spectrum_at(const std::vector<double>& bands, const std::vector<double>& values, double nm) {
  if (nm < bands.front() || nm > bands.back()) return 0;
  std::size_t i = 0;
  while (i + 2 < bands.size() && nm > bands[i + 1]) ++i;
  const double t = (nm - bands[i]) / (bands[i + 1] - bands[i]);
  return (1 - t) * values[i] + t * values[i + 1];
}

// Trapezoid sums on the 1 nm tables (360..830) of cmf * E * spectrum (E empty: emission).
Xyz raw_integral(const Cmf& c, const std::vector<double>& light, const std::vector<double>& bands,
                 const std::vector<double>& values) {
  Xyz s;
  for (std::size_t k = 0; k < 471; ++k) {
    const double tau = (k == 0 || k == 470) ? 0.5 : 1.0;
    const double v = spectrum_at(bands, values, 360.0 + static_cast<double>(k)) *
                     (light.empty() ? 1.0 : light[k]);
    s.X += tau * v * c.x[k];
    s.Y += tau * v * c.y[k];
    s.Z += tau * v * c.z[k];
  }
  return s;
}

// K = sum tau ybar over the whole table: the emission normalisation.
double emission_norm(const Cmf& c) {
  double k = 0;
  for (std::size_t i = 0; i < 471; ++i) k += ((i == 0 || i == 470) ? 0.5 : 1.0) * c.y[i];
  return k;
}

// --- The code under test, set up ---

const ColourSpaces& spaces() {
  static const ColourSpaces s = ColourSpaces::load();
  return s;
}

Settings settings_for(const std::string& space, const std::string& observer = "cie1931",
                      const std::string& light = "D65", bool as_lit = false) {
  Settings s;
  s.colorspace = space;
  s.spectral.observer = observer;
  s.spectral.illuminant = light;
  s.as_lit = as_lit;
  return s;
}

std::vector<double> bands_from(double first, double last, double step) {
  std::vector<double> b;
  for (double nm = first; nm <= last + 1e-9; nm += step) b.push_back(nm);
  return b;
}

// One pixel of `values` (and alpha, when the layout has it) converted; the RGB(A) out.
std::vector<float> convert_one(const RgbFromSpectral& conv, const SpectralLayoutInfo& layout,
                               const std::vector<double>& values, RgbCounts* counts = nullptr,
                               OIIO::TypeDesc type = OIIO::TypeFloat, float alpha = 1) {
  std::vector<float> in(values.begin(), values.end());
  if (layout.alpha >= 0) in.push_back(alpha);
  std::vector<float> out(static_cast<std::size_t>(conv.output_channels()));
  const RgbCounts c = conv.convert(in.data(), static_cast<int>(in.size()), 1, out.data(), type);
  if (counts) *counts = c;
  return out;
}

// max |got - expected| / max |expected| of an RGB triple.
double relative_error(const std::vector<float>& got, const Xyz& expected) {
  return std::max({std::abs(got[0] - expected.X), std::abs(got[1] - expected.Y),
                   std::abs(got[2] - expected.Z)}) /
         expected.max_abs();
}

using test::spec_of;

// --- Finding the spectral channels ---

TEST(RgbFromSpectral, BandsAreFoundInWavelengthOrderWhateverTheirOrderAndUnit) {
  // OpenEXR stores names sorted as text; units other than nm are converted (0,55um = 550 nm).
  const SpectralLayoutInfo t = analyse_spectral_layout(
      spec_of({"T.700,000000nm", "A", "T.400,000000nm", "T.0,55um", "T.450,5nm", "Z"}), "a.exr");
  EXPECT_FALSE(t.emissive);
  ASSERT_EQ(t.wavelengths.size(), 4u);
  const double nm[4] = {400, 450.5, 550, 700};
  const int channel[4] = {2, 4, 3, 0};
  for (int i = 0; i < 4; ++i) {
    EXPECT_NEAR(t.wavelengths[i], nm[i], 1e-9) << i;
    EXPECT_EQ(t.band_channels[i], channel[i]) << i;
  }
  EXPECT_EQ(t.alpha, 1);
  EXPECT_FALSE(t.polarised);
  // Emissive, polarised (S1..S3 ignored), and a name that looks spectral but does not parse.
  const SpectralLayoutInfo s = analyse_spectral_layout(
      spec_of({"S0.500,0nm", "S1.500,0nm", "S0.600,0nm", "S1.600,0nm", "S0.what"}), "b.exr");
  EXPECT_TRUE(s.emissive);
  EXPECT_TRUE(s.polarised);
  EXPECT_EQ(s.band_channels, (std::vector<int>{0, 2}));
  EXPECT_EQ(s.unparsed, std::vector<std::string>{"S0.what"});
  EXPECT_EQ(s.alpha, -1);
}

TEST(RgbFromSpectral, FilesThatAreNotPlainSpectraAreRefusedNamingTheFile) {
  struct Case {
    std::vector<std::string> channels;
    const char* why;
  };
  const Case cases[] = {
      {{"R", "G", "B"}, "no spectral channels"},
      {{"S0.500,0nm", "S0.600,0nm", "T.500,0nm", "T.600,0nm"}, "both emissive"},
      {{"S1.500,0nm", "S1.600,0nm"}, "no S0"},
      {{"T.500,0nm", "T.600,0nm", "T.500,000000nm.600,000000nm"}, "bispectral"},
      {{"S0.550,0nm", "S0.550,000000nm", "S0.600,0nm"}, "same wavelength"},
      {{"S0.550,0nm", "A"}, "single spectral band"},
      {{"S0.1000,0nm", "S0.1100,0nm"}, "no band inside 360-830"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.why);
    test::expect_error_mentioning([&] { analyse_spectral_layout(spec_of(c.channels), "bad.exr"); },
                                  {"'bad.exr'", c.why}, c.why);
  }
}

TEST(RgbFromSpectral, SampleWavelengthsAreChecked) {
  const SpectralLayoutInfo ok = spectral_layout_of_samples({400, 500, 600}, true, "arg: ");
  EXPECT_EQ(ok.wavelengths, (std::vector<double>{400, 500, 600}));
  EXPECT_EQ(ok.band_channels, (std::vector<int>{0, 1, 2}));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::vector<double>> bad = {
      {400, nan, 600}, {400, 400, 600}, {500, 400}, {550}, {}, {900, 1000}};
  for (const auto& w : bad) {
    try {
      spectral_layout_of_samples(w, false, "arg: ");
      ADD_FAILURE() << "accepted " << w.size() << " wavelengths";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()).rfind("arg: ", 0), 0u) << e.what();
    }
  }
}

// --- Colour ---

TEST(RgbFromSpectral, AConstantReflectanceIsThatGreyInEveryLinearSpaceUnderEveryIlluminant) {
  // rho == 1 is the reference white, taken to the D65 white: RGB (1, 1, 1) of every space of
  // the config (all D65-referred); the mapping is linear, so rho gives (rho, rho, rho).
  const std::vector<double> bands = bands_from(400, 700, 10);
  const SpectralLayoutInfo layout = spectral_layout_of_samples(bands, false, "");
  for (const char* space : {"Linear Rec.709 (sRGB)", "Linear Rec.2020", "Linear P3-D65",
                            "Linear Adobe RGB (1998)", "ACEScg", "ACES2065-1"})
    for (const char* light : {"D65", "A", "D50", "E", "F11"})
      for (const char* observer : {"cie1931", "cie1964"}) {
        SCOPED_TRACE(std::string(space) + ", " + light + ", " + observer);
        const RgbFromSpectral conv(layout, settings_for(space, observer, light), spaces());
        for (const double rho : {0.0, 0.18, 0.5, 1.0, 3.0}) {
          const std::vector<float> rgb =
              convert_one(conv, layout, std::vector<double>(bands.size(), rho));
          // Float weights and OCIO's float maths (docs/DESIGN.md §3: float files, 1e-5).
          for (int c = 0; c < 3; ++c) {
            EXPECT_NEAR(rgb[c], rho, 1e-5 * std::max(1.0, rho)) << c;
          }
        }
      }
}

TEST(RgbFromSpectral, AnEmissionSpectrumEqualToAColourMatchingFunctionIntegratesToItsXyz) {
  for (const char* observer : {"cie1931", "cie1964"}) {
    const Cmf c = cmf(observer);
    const double k = emission_norm(c);
    // On the table's own wavelengths (the spectrum is the function itself) and on 5 nm bands
    // (the piecewise-linear spectrum through its samples).
    for (const double step : {1.0, 5.0}) {
      const std::vector<double> bands = bands_from(360, 830, step);
      const SpectralLayoutInfo layout = spectral_layout_of_samples(bands, true, "");
      const RgbFromSpectral xyz(layout, settings_for("CIE-XYZ-D65", observer), spaces());
      const RgbFromSpectral rec709(layout, settings_for("Linear Rec.709 (sRGB)", observer),
                                   spaces());
      const std::vector<double>* rows[3] = {&c.x, &c.y, &c.z};
      for (int row = 0; row < 3; ++row) {
        SCOPED_TRACE(std::string(observer) + " row " + std::to_string(row) + " step " +
                     std::to_string(step));
        std::vector<double> values;
        for (double nm : bands) values.push_back((*rows[row])[static_cast<std::size_t>(nm - 360)]);
        const Xyz expected = (1.0 / k) * raw_integral(c, {}, bands, values);
        EXPECT_LT(relative_error(convert_one(xyz, layout, values), expected), 1e-5);
        // The same light in Linear Rec.709: the inverse of its RGB -> XYZ matrix.
        const Xyz rgb = test::mul(test::inverse(test::kRec709ToXyz), expected);
        EXPECT_LT(relative_error(convert_one(rec709, layout, values), rgb), 1e-5);
      }
      // A constant spectrum over the whole table has Y = its value (docs/DESIGN.md §3).
      const std::vector<float> flat =
          convert_one(xyz, layout, std::vector<double>(bands.size(), 2.5));
      EXPECT_NEAR(flat[1], 2.5, 2.5e-5);
    }
  }
}

TEST(RgbFromSpectral, AReflectanceIsItsReflectedLightBalancedToD65OrAsLit) {
  const std::vector<double> bands = bands_from(380, 780, 5);
  std::vector<double> rho;
  for (double nm : bands) rho.push_back(0.1 + 0.8 * (nm - 380) / 400);  // a ramp: orange-ish
  const SpectralLayoutInfo layout = spectral_layout_of_samples(bands, false, "");
  const Cmf c = cmf("cie1931");
  for (const char* light : {"a", "d50", "d65"}) {
    SCOPED_TRACE(light);
    const std::vector<double> e = illuminant(light);
    const Xyz white = raw_integral(c, e, bands, std::vector<double>(bands.size(), 1.0));
    const Xyz lit = (1.0 / white.Y) * raw_integral(c, e, bands, rho);
    // As lit: the reflected light itself, rho == 1 having Y = 1.
    const RgbFromSpectral as_lit(layout, settings_for("CIE-XYZ-D65", "cie1931", light, true),
                                 spaces());
    EXPECT_LT(relative_error(convert_one(as_lit, layout, rho), lit), 1e-5);
    // Balanced: each component scaled by D65's white over the reflected white's (XYZ scaling).
    const Xyz d65{0.3127 / 0.3290, 1.0, 0.3583 / 0.3290};
    const Xyz w = (1.0 / white.Y) * white;
    const Xyz balanced{lit.X * d65.X / w.X, lit.Y * d65.Y / w.Y, lit.Z * d65.Z / w.Z};
    const RgbFromSpectral conv(layout, settings_for("CIE-XYZ-D65", "cie1931", light), spaces());
    EXPECT_LT(relative_error(convert_one(conv, layout, rho), balanced), 1e-5);
  }
}

// --- Invalid samples, ranges, alpha ---

TEST(RgbFromSpectral, NonFiniteSamplesCountAsZero) {
  const std::vector<double> bands = bands_from(400, 700, 50);
  const SpectralLayoutInfo layout = spectral_layout_of_samples(bands, true, "");
  const RgbFromSpectral conv(layout, settings_for("Linear Rec.709 (sRGB)"), spaces());
  const int nch = static_cast<int>(bands.size());
  const float nan = std::numeric_limits<float>::quiet_NaN(),
              inf = std::numeric_limits<float>::infinity();
  // Three pixels: clean, a NaN band, an infinite band; then the same with those bands 0.
  std::vector<float> in = {1, 2, 3, 4, 5, 6, 7, 1, nan, 3, 4, 5, 6, 7, 1, 2, 3, -inf, 5, 6, 7};
  std::vector<float> zeroed = {1, 2, 3, 4, 5, 6, 7, 1, 0, 3, 4, 5, 6, 7, 1, 2, 3, 0, 5, 6, 7};
  std::vector<float> out(9), expected(9);
  const RgbCounts counts = conv.convert(in.data(), nch, 3, out.data(), OIIO::TypeFloat);
  EXPECT_EQ(counts.invalid, 2u);
  EXPECT_EQ(conv.convert(zeroed.data(), nch, 3, expected.data(), OIIO::TypeFloat).invalid, 0u);
  EXPECT_EQ(out, expected);
}

TEST(RgbFromSpectral, ValuesBeyondTheOutputTypeAreClampedAndCounted) {
  // Reflectances in Linear Rec.709 under D65: rho gives RGB (rho, rho, rho) (tested above).
  const std::vector<double> bands = bands_from(400, 700, 25);
  const SpectralLayoutInfo layout = spectral_layout_of_samples(bands, false, "");
  const RgbFromSpectral conv(layout, settings_for("Linear Rec.709 (sRGB)"), spaces());
  auto grey = [&](double rho, OIIO::TypeDesc type, RgbCounts& c) {
    return convert_one(conv, layout, std::vector<double>(bands.size(), rho), &c, type);
  };
  RgbCounts c;
  // 8-bit: beyond half a code value (0.5/255) outside 0..1 is clipped and counted.
  EXPECT_EQ(grey(1.5, OIIO::TypeUInt8, c), (std::vector<float>{1, 1, 1}));
  EXPECT_EQ(c.clipped, 1u);
  EXPECT_EQ(grey(-0.5, OIIO::TypeUInt8, c), (std::vector<float>{0, 0, 0}));
  EXPECT_EQ(c.clipped, 1u);
  EXPECT_EQ(grey(1 + 0.25 / 255, OIIO::TypeUInt8, c), (std::vector<float>{1, 1, 1}));
  EXPECT_EQ(c.clipped, 0u);  // rounds to code 255 anyway: nothing lost
  EXPECT_EQ(grey(1 + 0.25 / 255, OIIO::TypeUInt16, c), (std::vector<float>{1, 1, 1}));
  EXPECT_EQ(c.clipped, 1u);  // beyond half of a 16-bit code
  // HALF: beyond 65504, clamped to it.
  for (float v : grey(1e5, OIIO::TypeHalf, c)) {
    EXPECT_EQ(v, 65504.0f);
  }
  EXPECT_EQ(c.half_overflow, 1u);
  for (float v : grey(-1e5, OIIO::TypeHalf, c)) {
    EXPECT_EQ(v, -65504.0f);
  }
  EXPECT_EQ(c.half_overflow, 1u);
  grey(6e4, OIIO::TypeHalf, c);
  EXPECT_EQ(c.half_overflow, 0u);
  // FLOAT: beyond float's range, made finite (a component OCIO's float maths overflowed to NaN
  // comes out as 0) and counted.
  for (float v : grey(std::numeric_limits<float>::max(), OIIO::TypeFloat, c)) {
    EXPECT_TRUE(std::isfinite(v)) << v;
  }
  EXPECT_EQ(c.float_overflow, 1u);
  EXPECT_EQ(c.half_overflow + c.clipped + c.invalid, 0u);
}

TEST(RgbFromSpectral, AlphaIsCarriedAndClampedToTheOutputType) {
  const std::vector<double> bands = bands_from(400, 700, 100);
  SpectralLayoutInfo layout = spectral_layout_of_samples(bands, false, "");
  layout.alpha = static_cast<int>(bands.size());  // the channel after the bands
  const RgbFromSpectral conv(layout, settings_for("Linear Rec.709 (sRGB)"), spaces());
  EXPECT_EQ(conv.output_channels(), 4);
  const std::vector<double> grey(bands.size(), 0.5);
  EXPECT_EQ(convert_one(conv, layout, grey, nullptr, OIIO::TypeFloat, 0.25f)[3], 0.25f);
  EXPECT_EQ(convert_one(conv, layout, grey, nullptr, OIIO::TypeFloat, 1.7f)[3], 1.7f);
  EXPECT_EQ(convert_one(conv, layout, grey, nullptr, OIIO::TypeUInt8, 1.7f)[3], 1.0f);
  EXPECT_EQ(convert_one(conv, layout, grey, nullptr, OIIO::TypeUInt16, -0.5f)[3], 0.0f);
  EXPECT_EQ(convert_one(conv, layout, grey, nullptr, OIIO::TypeHalf, 1e6f)[3], 65504.0f);
  EXPECT_EQ(convert_one(conv, layout, grey, nullptr, OIIO::TypeFloat,
                        std::numeric_limits<float>::quiet_NaN())[3],
            0.0f);
  const SpectralLayoutInfo no_alpha = spectral_layout_of_samples(bands, false, "");
  EXPECT_EQ(RgbFromSpectral(no_alpha, settings_for("ACEScg"), spaces()).output_channels(), 3);
}

// --- The output's type and spec ---

TEST(RgbFromSpectral, TheSampleTypeIsTheOneAsked) {
  Settings s;
  EXPECT_EQ(rgb_sample_type(s), OIIO::TypeHalf);
  s.half = false;
  EXPECT_EQ(rgb_sample_type(s), OIIO::TypeFloat);
  s.integer_bits = 8;
  EXPECT_EQ(rgb_sample_type(s), OIIO::TypeUInt8);
  s.integer_bits = 16;
  EXPECT_EQ(rgb_sample_type(s), OIIO::TypeUInt16);
}

TEST(RgbFromSpectral, TheOutputSpecKeepsTheWindowsAndSaysWhatTheRgbIs) {
  OIIO::ImageSpec source =
      spec_of({"T.400,0nm", "T.500,0nm", "T.600,0nm", "T.700,0nm", "A"}, OIIO::TypeHalf, 4, 2);
  source.x = 3;
  source.y = -2;
  source.full_x = 0;
  source.full_y = -4;
  source.full_width = 10;
  source.full_height = 12;
  const SpectralLayoutInfo layout = analyse_spectral_layout(source, "in.exr");
  Settings s = settings_for("ACEScg", "cie1964", "A");
  s.half = false;
  const OIIO::ImageSpec spec = rgb_output_spec(source, layout, s, spaces(), "2026:01:02 03:04:05");
  EXPECT_EQ(spec.width, 4);
  EXPECT_EQ(spec.height, 2);
  EXPECT_EQ(spec.x, 3);
  EXPECT_EQ(spec.y, -2);
  EXPECT_EQ(spec.full_x, 0);
  EXPECT_EQ(spec.full_y, -4);
  EXPECT_EQ(spec.full_width, 10);
  EXPECT_EQ(spec.full_height, 12);
  EXPECT_EQ(spec.channelnames, (std::vector<std::string>{"R", "G", "B", "A"}));
  EXPECT_EQ(spec.alpha_channel, 3);
  EXPECT_EQ(spec.format, OIIO::TypeFloat);
  EXPECT_EQ(spec.get_string_attribute("DateTime"), "2026:01:02 03:04:05");
  EXPECT_EQ(spec.get_string_attribute("spectralize:mode"), "reflectance");
  EXPECT_EQ(spec.get_string_attribute("spectralize:observer"), "cie1964");
  EXPECT_EQ(spec.get_string_attribute("spectralize:illuminant"), "A");
  EXPECT_EQ(spec.get_string_attribute("oiio:ColorSpace"),
            test::oiio_colour_space("ACEScg", "lin_ap1_scene"));
  // An emissive file records no illuminant.
  const OIIO::ImageSpec emissive_source = spec_of({"S0.400,0nm", "S0.700,0nm"});
  const OIIO::ImageSpec e =
      rgb_output_spec(emissive_source, analyse_spectral_layout(emissive_source, "e.exr"), s,
                      spaces(), "2026:01:02 03:04:05");
  EXPECT_EQ(e.get_string_attribute("spectralize:mode"), "emission");
  EXPECT_EQ(e.find_attribute("spectralize:illuminant"), nullptr);
  EXPECT_EQ(e.channelnames, (std::vector<std::string>{"R", "G", "B"}));
  EXPECT_EQ(e.alpha_channel, -1);
}

TEST(RgbFromSpectral, ChannelsSortedByWavelengthAndStrangeOnesNamed) {
  const auto info = analyse_spectral_layout(
      spec_of({"A", "S0.1000,0nm", "S0.950,0nm", "S0.0,55um", "S0.5x0nm", "R"}), "f.exr");
  EXPECT_EQ(info.wavelengths, (std::vector<double>{550, 950, 1000}));
  EXPECT_EQ(info.band_channels, (std::vector<int>{3, 2, 1}));
  EXPECT_EQ(info.alpha, 0);
  EXPECT_EQ(info.unparsed, std::vector<std::string>{"S0.5x0nm"});
  EXPECT_THROW(
      analyse_spectral_layout(spec_of({"T.500,0nm", "T.500,0nm.510,0nm", "T.510,0nm"}), "bi.exr"),
      Error);
  EXPECT_THROW(analyse_spectral_layout(spec_of({"S0.900,0nm", "S0.950,0nm"}), "ir.exr"), Error);
  EXPECT_THROW(analyse_spectral_layout(spec_of({"S0.500,0nm", "T.600,0nm"}), "mixed.exr"), Error);
}

}  // namespace
}  // namespace spectralize
