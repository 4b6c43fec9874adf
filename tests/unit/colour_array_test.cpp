// Arrays of colours to spectra and back (pipeline/colour_array.h, docs/DESIGN.md §13): the
// spectra of colours integrate back to them (emission: their XYZ; reflectance: their XYZ
// white-balanced to the reference illuminant, within [0, 1]; docs/DESIGN.md §3) in float's
// 1e-5, from linear and encoded spaces alike; bad colours are zero spectra, counted by kind;
// colours of one settings share the pool's table. rgb_of_spectra: a constant reflectance is
// the grey of its value on any strictly increasing wavelengths and under any illuminant (as
// lit: the illuminant's own colour), light is its integral, spectra of colours give the
// colours back, and bad wavelengths are refused starting with the caller's `where`. Oracles:
// the reference integration and the matrices of tests/unit/test_support.h, the sRGB curve
// written here, and the colours each case makes.

#include "pipeline/colour_array.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "pipeline/render_table.h"
#include "spectralize/core/error.h"
#include "test_support.h"

namespace spectralize {
namespace {

const std::string kRec709 = "Linear Rec.709 (sRGB)";
const OptionNames kKeywords{"", "output"};
const LogFn kQuiet = [](int, const std::string&) {};

// Float samples and OCIO's float maths (docs/DESIGN.md §3: float files, 1e-5).
constexpr double kFloatTolerance = 1e-5;
// Colours through OCIO's float matrices twice (to spectra and back).
constexpr double kTwiceThroughOcio = 1e-4;

JobPlan colours_plan(const std::string& space, ModeChoice mode = ModeChoice::automatic) {
  Settings s;
  s.colorspace = space;
  s.mode = mode;
  s.threads = 2;
  return plan_colours(s, ColourSubject::colours, kKeywords);
}

JobPlan spectra_plan(ModeChoice mode, const std::string& illuminant = "D65", bool as_lit = false) {
  Settings s;
  s.colorspace = kRec709;
  s.mode = mode;
  s.spectral.illuminant = illuminant;
  s.as_lit = as_lit;
  s.threads = 2;
  return plan_colours(s, ColourSubject::spectra, kKeywords);
}

std::vector<float> packed(const std::vector<std::array<float, 3>>& colours) {
  std::vector<float> v;
  for (const auto& c : colours) v.insert(v.end(), c.begin(), c.end());
  return v;
}

// Sample i of colour p.
std::vector<double> spectrum_of(const std::vector<float>& out, std::size_t bands, std::size_t p) {
  return std::vector<double>(out.begin() + static_cast<std::ptrdiff_t>(p * bands),
                             out.begin() + static_cast<std::ptrdiff_t>((p + 1) * bands));
}

Xyz integrated(const Settings& s, const std::vector<double>& values) {
  return test::reference_xyz(s.spectral, values);
}

Xyz balance(const Settings& s) {
  return test::white_balance(s.spectral);
}

double srgb_decode(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

TEST(ColourArrays, EmissionSpectraIntegrateBackToTheColours) {
  TablePool pool;
  const ColourArrays arrays(colours_plan(kRec709), pool, kQuiet);
  EXPECT_EQ(arrays.settings().spectral.mode, Mode::emission);  // "auto" colours are light
  EXPECT_FALSE(arrays.settings().half);                        // arrays are float
  ASSERT_EQ(arrays.bands(), 81u);
  const std::vector<std::array<float, 3>> colours = {
      {1, 1, 1}, {0.18f, 0.18f, 0.18f}, {0.8f, 0.2f, 0.1f}, {0.05f, 0.6f, 0.3f}, {40, 30, 20}};
  std::vector<float> out(colours.size() * arrays.bands(), -1.0f);
  const PixelCounts c = arrays.spectra(packed(colours).data(), colours.size(), out.data());
  for (std::size_t p = 0; p < colours.size(); ++p) {
    SCOPED_TRACE(p);
    const std::vector<double> s = spectrum_of(out, arrays.bands(), p);
    EXPECT_LT(
        test::rel_err(integrated(arrays.settings(), s),
                      test::rgb(test::kRec709ToXyz, colours[p][0], colours[p][1], colours[p][2])),
        kFloatTolerance);
    EXPECT_GE(*std::min_element(s.begin(), s.end()), 0.0);  // light is never negative
  }
  EXPECT_EQ(c.error_pixels, colours.size());
  EXPECT_LT(c.max_error, kFloatTolerance);
  EXPECT_EQ(c.invalid + c.black + c.negative + c.outside_locus, 0u);
}

TEST(ColourArrays, ReflectancesOfEncodedColoursAreBoundedAndIntegrateToTheBalancedColour) {
  TablePool pool;
  const ColourArrays arrays(colours_plan("sRGB - Texture", ModeChoice::reflectance), pool, kQuiet);
  EXPECT_EQ(arrays.settings().spectral.mode, Mode::reflectance);
  const std::vector<std::array<float, 3>> codes = {
      {0.9f, 0.9f, 0.9f}, {0.5f, 0.5f, 0.5f}, {0.8f, 0.3f, 0.15f}, {0.1f, 0.6f, 0.25f}};
  std::vector<float> out(codes.size() * arrays.bands());
  arrays.spectra(packed(codes).data(), codes.size(), out.data());
  const Xyz b = balance(arrays.settings());
  for (std::size_t p = 0; p < codes.size(); ++p) {
    SCOPED_TRACE(p);
    const std::vector<double> s = spectrum_of(out, arrays.bands(), p);
    for (double v : s) {
      EXPECT_GE(v, 0.0);
      EXPECT_LE(v, 1.0);
    }
    const Xyz lin = test::rgb(test::kRec709ToXyz, srgb_decode(codes[p][0]),
                              srgb_decode(codes[p][1]), srgb_decode(codes[p][2]));
    EXPECT_LT(
        test::rel_err(integrated(arrays.settings(), s), Xyz{lin.X * b.X, lin.Y * b.Y, lin.Z * b.Z}),
        kFloatTolerance);
  }
}

TEST(ColourArrays, WideGamutColoursUnderAnotherIlluminantAreExactToo) {
  TablePool pool;
  JobPlan plan = colours_plan("ACEScg", ModeChoice::reflectance);
  plan.settings.spectral.illuminant = "A";
  const ColourArrays arrays(plan, pool, kQuiet);
  const std::vector<std::array<float, 3>> colours = {
      {0.5f, 0.5f, 0.5f}, {0.4f, 0.2f, 0.1f}, {0.1f, 0.3f, 0.15f}};
  std::vector<float> out(colours.size() * arrays.bands());
  arrays.spectra(packed(colours).data(), colours.size(), out.data());
  const Xyz b = balance(arrays.settings());
  for (std::size_t p = 0; p < colours.size(); ++p) {
    SCOPED_TRACE(p);
    const Xyz xyz =
        test::rgb(test::acescg_to_xyz_d65(), colours[p][0], colours[p][1], colours[p][2]);
    EXPECT_LT(test::rel_err(integrated(arrays.settings(), spectrum_of(out, arrays.bands(), p)),
                            Xyz{xyz.X * b.X, xyz.Y * b.Y, xyz.Z * b.Z}),
              kFloatTolerance);
  }
}

TEST(ColourArrays, BadColoursAreZeroSpectraCountedByKind) {
  TablePool pool;
  const ColourArrays arrays(colours_plan(kRec709, ModeChoice::reflectance), pool, kQuiet);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<std::array<float, 3>> colours = {
      {nan, 0.5f, 0.5f}, {0.2f, inf, 0.1f}, {0, 0, 0}, {-0.3f, -0.2f, -0.1f}, {2, 2, 2}};
  std::vector<float> out(colours.size() * arrays.bands(), -1.0f);
  const PixelCounts c = arrays.spectra(packed(colours).data(), colours.size(), out.data());
  EXPECT_EQ(c.invalid, 2u);
  EXPECT_EQ(c.black, 1u);
  EXPECT_EQ(c.negative, 1u);
  EXPECT_EQ(c.brighter_than_white, 1u);
  for (std::size_t p = 0; p < 4; ++p)
    for (double v : spectrum_of(out, arrays.bands(), p)) EXPECT_EQ(v, 0.0) << p;
  // Brighter than white: dimmed into the reflectance solid, still a reflectance.
  for (double v : spectrum_of(out, arrays.bands(), 4)) {
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 1.0);
  }
}

TEST(ColourArrays, ColoursOfOneSettingsShareThePoolsTable) {
  TablePool pool;
  const JobPlan plan = colours_plan(kRec709);
  const ColourArrays first(plan, pool, kQuiet), second(plan, pool, kQuiet);
  const std::vector<float> rgb = {0.3f, 0.2f, 0.1f, 0.1f, 0.5f, 0.2f};
  std::vector<float> a(2 * first.bands()), b(2 * second.bands());
  first.spectra(rgb.data(), 2, a.data());
  const TablePool::Entry& e =
      pool.get(first.settings(), table_frame(plan.colour_spaces(), kRec709), kQuiet);
  const std::uint64_t computed = e.table->stats().nodes_computed;
  EXPECT_GT(computed, 0u);
  second.spectra(rgb.data(), 2, b.data());
  EXPECT_EQ(e.table->stats().nodes_computed, computed);  // no node solved twice
  EXPECT_EQ(a, b);
}

// --- rgb_of_spectra ---

TEST(RgbOfSpectra, AConstantReflectanceIsTheGreyOfItsValue) {
  // Strictly increasing but uneven wavelengths: rho == 1 is the white wherever it is sampled.
  const std::vector<double> nm = {380, 400, 430, 455, 500, 520, 560, 600, 610, 650, 700, 780};
  for (const std::string illuminant : {"D65", "A", "FL2"}) {
    SCOPED_TRACE(illuminant);
    const JobPlan plan = spectra_plan(ModeChoice::reflectance, illuminant);
    const std::vector<float> rho = {0.0f, 0.25f, 0.6f, 1.0f};
    std::vector<float> spectra;
    for (float v : rho) spectra.insert(spectra.end(), nm.size(), v);
    std::vector<float> rgb(rho.size() * 3, -1.0f);
    const RgbCounts c = rgb_of_spectra(spectra.data(), rho.size(), nm, plan, rgb.data(), "arg: ");
    EXPECT_EQ(c.invalid, 0u);
    for (std::size_t p = 0; p < rho.size(); ++p)
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(rgb[p * 3 + k], rho[p], kFloatTolerance * std::max(rho[p], 1e-3f))
            << p << " " << k;
  }
}

TEST(RgbOfSpectra, AsLitAWhiteSurfaceIsTheIlluminantsOwnColour) {
  const JobPlan plan = spectra_plan(ModeChoice::reflectance, "A", true);
  const WavelengthGrid grid(380, 780, 5);
  std::vector<double> nm;
  for (std::size_t i = 0; i < grid.size(); ++i) nm.push_back(grid[i]);
  const std::vector<float> ones(grid.size(), 1.0f);
  float rgb[3];
  rgb_of_spectra(ones.data(), 1, nm, plan, rgb, "arg: ");
  // rho == 1 under A at Y = 1 (docs/DESIGN.md §3), in Linear Rec.709: warm, not grey.
  const Illuminant a = Illuminant::get("A");
  const Xyz xyz = test::reference_xyz(grid, std::vector<double>(grid.size(), 1.0),
                                      Observer::get("cie1931"), &a.spd);
  const Xyz want = test::mul(test::inverse(test::kRec709ToXyz), xyz);
  EXPECT_LT(test::rel_err(Xyz{rgb[0], rgb[1], rgb[2]}, want), kFloatTolerance);
  EXPECT_GT(rgb[0], 1.5f * rgb[2]);
}

TEST(RgbOfSpectra, LightIsItsIntegralAndSpectraOfColoursGiveTheColoursBack) {
  const JobPlan plan = spectra_plan(ModeChoice::automatic);  // spectra are light by default
  ASSERT_EQ(plan.settings.spectral.mode, Mode::emission);
  // A ramp on 400..700 nm at 10 nm, by the reference integration.
  const WavelengthGrid grid(400, 700, 10);
  std::vector<double> nm, ramp;
  for (std::size_t i = 0; i < grid.size(); ++i) nm.push_back(grid[i]), ramp.push_back(0.1 * i);
  const std::vector<float> ramp_f(ramp.begin(), ramp.end());
  float rgb[3];
  rgb_of_spectra(ramp_f.data(), 1, nm, plan, rgb, "arg: ");
  const Xyz want = test::mul(test::inverse(test::kRec709ToXyz),
                             test::reference_xyz(grid, ramp, Observer::get("cie1931"), nullptr));
  EXPECT_LT(test::rel_err(Xyz{rgb[0], rgb[1], rgb[2]}, want), kFloatTolerance);
  // ColourArrays' spectra of colours, back: the colours again.
  TablePool pool;
  const ColourArrays arrays(colours_plan(kRec709), pool, kQuiet);
  const std::vector<float> colours = {0.8f, 0.2f, 0.1f, 0.05f, 0.6f, 0.3f, 3, 2, 1};
  std::vector<float> spectra(3 * arrays.bands()), back(9);
  arrays.spectra(colours.data(), 3, spectra.data());
  const WavelengthGrid& g = arrays.settings().spectral.grid;
  std::vector<double> wavelengths;
  for (std::size_t i = 0; i < g.size(); ++i) wavelengths.push_back(g[i]);
  rgb_of_spectra(spectra.data(), 3, wavelengths, plan, back.data(), "arg: ");
  for (std::size_t p = 0; p < 3; ++p) {
    const float peak = std::max({colours[3 * p], colours[3 * p + 1], colours[3 * p + 2]});
    for (int k = 0; k < 3; ++k)
      EXPECT_LT(std::abs(back[3 * p + k] - colours[3 * p + k]) / peak, kTwiceThroughOcio)
          << p << " " << k;
  }
}

TEST(RgbOfSpectra, NonFiniteSamplesAreCountedAndGiveFiniteColours) {
  const JobPlan plan = spectra_plan(ModeChoice::emission);
  const std::vector<double> nm = {400, 500, 600, 700};
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<float> spectra = {0.5f, nan, 0.5f, 0.5f, 0.2f, 0.2f, 0.2f, 0.2f};
  float rgb[6];
  const RgbCounts c = rgb_of_spectra(spectra.data(), 2, nm, plan, rgb, "arg: ");
  EXPECT_EQ(c.invalid, 1u);
  for (float v : rgb) EXPECT_TRUE(std::isfinite(v));
}

TEST(RgbOfSpectra, BadWavelengthsAreRefusedStartingWithWhere) {
  const JobPlan plan = spectra_plan(ModeChoice::reflectance);
  const float samples[8] = {0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f, 0.5f};
  float rgb[3];
  const std::vector<std::pair<std::vector<double>, std::string>> cases = {
      {{400, 500, 500, 700}, "increase strictly"},
      {{400, 600, 500, 700}, "increase strictly"},
      {{400, std::nan(""), 600, 700}, "not finite"},
      {{400, std::numeric_limits<double>::infinity()}, "not finite"},
      {{550}, "single spectral band"},
      {{}, "single spectral band"},
      {{900, 950, 1000}, "no band inside 360-830 nm"},
      {{100, 200, 300}, "no band inside 360-830 nm"}};
  for (const auto& [nm, why] : cases) {
    SCOPED_TRACE(::testing::PrintToString(nm));
    try {
      rgb_of_spectra(samples, 1, nm, plan, rgb, "wavelengths: ");
      ADD_FAILURE() << "accepted";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("wavelengths: ", 0), 0u) << m;
      EXPECT_NE(m.find(why), std::string::npos) << m;
    }
  }
}

}  // namespace
}  // namespace spectralize
