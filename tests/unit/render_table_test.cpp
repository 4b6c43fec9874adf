// The render-time table of a colour space (pipeline/render_table.h, docs/DESIGN.md §14): a
// space's primaries matrix is the normalised primary matrix of its published primaries and
// white (encoded spaces too: 0 and 1 survive any transfer curve), data spaces have none; the
// table's frame is that matrix for D65 spaces, else Linear Rec.709's; only a linear space is
// a matrix space; plan_table refuses what a table cannot be made for, naming the option as the
// caller spells it and, for an encoded space, the linear space with its primaries; a small
// table's bytes depend on the settings only and its spectra, read back through the render-time
// evaluator, integrate to their colours. Oracles: the matrices derived from the primaries in
// tests/unit/test_support.h, the reference integration there, and <spectralize/rt.hpp> reading
// the bytes.

#include "pipeline/render_table.h"

#include <fmt/core.h>
#include <gtest/gtest.h>

// The one unit of io_unit_tests that compiles the evaluator's definitions
// (include/spectralize/rt_impl.hpp).
#define SPECTRALIZE_RT_IMPLEMENTATION
#include <spectralize/rt.hpp>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "file_test_support.h"
#include "spectralize/core/error.h"
#include "test_support.h"

namespace spectralize {
namespace {

const std::string kRec709 = "Linear Rec.709 (sRGB)";
const OptionNames kFlags{"--", "-o"};
const OptionNames kKeywords{"", "output"};
const LogFn kQuiet = [](int, const std::string&) {};

const ColourSpaces& spaces() {
  static const ColourSpaces s = ColourSpaces::load();
  return s;
}

// The normalised primary matrices of the spaces' published primaries and D65 white.
test::Mat3 rec709() {
  return test::rgb_to_xyz(0.64, 0.33, 0.30, 0.60, 0.15, 0.06, 0.3127, 0.3290);
}
test::Mat3 rec2020() {
  return test::rgb_to_xyz(0.708, 0.292, 0.170, 0.797, 0.131, 0.046, 0.3127, 0.3290);
}
test::Mat3 p3_d65() {
  return test::rgb_to_xyz(0.680, 0.320, 0.265, 0.690, 0.150, 0.060, 0.3127, 0.3290);
}
test::Mat3 adobe_rgb() {
  return test::rgb_to_xyz(0.64, 0.33, 0.21, 0.71, 0.15, 0.06, 0.3127, 0.3290);
}

double max_diff(const Mat3& got, const test::Mat3& want) {
  double d = 0;
  for (int i = 0; i < 9; ++i) d = std::max(d, std::abs(got[i] - want[i / 3][i % 3]));
  return d;
}

Mat3 flat(const test::Mat3& m) {
  Mat3 f;
  for (int i = 0; i < 9; ++i) f[i] = m[i / 3][i % 3];
  return f;
}

std::string message_of(const std::function<void()>& fn) {
  return test::error_message(fn);
}

// OCIO's float processors: 1e-6 of the matrices' 0..1 entries, with room.
constexpr double kMatrixTolerance = 1e-5;

TEST(RenderTable, APrimariesMatrixIsTheSpacesPublishedPrimariesAndWhite) {
  const std::pair<std::string, test::Mat3> cases[] = {
      {kRec709, rec709()},
      {"sRGB - Texture", rec709()},  // encoded: 0 and 1 survive the curve
      {"Gamma 2.2 Rec.709 - Texture", rec709()},
      {"Linear Rec.2020", rec2020()},
      {"Linear P3-D65", p3_d65()},
      {"Display P3 - Texture", p3_d65()},
      {"Linear Adobe RGB (1998)", adobe_rgb()},
      {"ACEScg", test::acescg_to_xyz_d65()},  // AP1, its white Bradford-adapted to D65
      {"CIE-XYZ-D65", {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}}},
  };
  for (const auto& [space, want] : cases) {
    SCOPED_TRACE(space);
    const std::optional<Mat3>& m = spaces().facts(space).rgb_to_xyz;
    ASSERT_TRUE(m.has_value());
    EXPECT_LT(max_diff(*m, want), kMatrixTolerance);
  }
  // The written-out Rec.709 and Rec.2020 matrices agree with their primaries (the oracle).
  EXPECT_LT(max_diff(flat(test::kRec709ToXyz), rec709()), 1e-4);
  EXPECT_LT(max_diff(flat(test::kRec2020ToXyz), rec2020()), 1e-4);
}

TEST(RenderTable, DataSpacesHaveNoPrimariesMatrixAndUnknownOnesAreRefused) {
  EXPECT_FALSE(spaces().facts("Raw").rgb_to_xyz.has_value());
  EXPECT_THROW(spaces().facts("no such space"), Error);
}

TEST(RenderTable, TheTableFrameIsTheSpacesMatrixWhenItsWhiteIsD65) {
  EXPECT_LT(max_diff(table_frame(spaces(), "Linear Rec.2020"), rec2020()), kMatrixTolerance);
  EXPECT_LT(max_diff(table_frame(spaces(), "sRGB - Texture"), rec709()), kMatrixTolerance);
  EXPECT_LT(max_diff(table_frame(spaces(), "ACEScg"), test::acescg_to_xyz_d65()), kMatrixTolerance);
  // White E (XYZ (1, 1, 1) is not D65), data and unknown spaces: Linear Rec.709's frame.
  for (const char* space : {"CIE-XYZ-D65", "Raw", "no such space"}) {
    SCOPED_TRACE(space);
    EXPECT_LT(max_diff(table_frame(spaces(), space), rec709()), kMatrixTolerance);
  }
}

TEST(RenderTable, OnlyALinearSpaceIsAMatrixSpace) {
  for (const char* space : {"Linear Rec.709 (sRGB)", "Linear Rec.2020", "ACEScg"}) {
    SCOPED_TRACE(space);
    EXPECT_TRUE(spaces().facts(space).linear);
  }
  // A curve shows between 0 and 1 (and beyond); a log curve has a matrix of its unit colours
  // but is no matrix space.
  for (const char* space : {"sRGB - Texture", "Gamma 2.2 Rec.709 - Texture", "ACEScct"}) {
    SCOPED_TRACE(space);
    EXPECT_FALSE(spaces().facts(space).linear);
  }
  EXPECT_TRUE(spaces().facts("ACEScct").rgb_to_xyz.has_value());
}

TEST(RenderTable, APlanIsForALinearSpaceAndASpztabAndAutoIsAReflectance) {
  Settings s;
  const JobPlan plan = plan_table(s, "srgb.spztab", kFlags);
  EXPECT_EQ(plan.settings.colorspace, kRec709);  // the config's scene_linear role
  EXPECT_EQ(plan.settings.spectral.mode, Mode::reflectance);
  EXPECT_EQ(plan_table(s, "dir/T.SPZTAB", kFlags).settings.spectral.mode, Mode::reflectance);
  s.mode = ModeChoice::emission;
  s.colorspace = "ACEScg";
  const JobPlan lights = plan_table(s, "acescg.spztab", kFlags);
  EXPECT_EQ(lights.settings.spectral.mode, Mode::emission);
  EXPECT_EQ(lights.settings.colorspace, "ACEScg");
  // Not a .spztab: refused naming the output as the caller spells it.
  const std::string cli = message_of([] { plan_table(Settings{}, "t.exr", kFlags); });
  EXPECT_EQ(cli.rfind("-o 't.exr'", 0), 0u) << cli;
  EXPECT_NE(cli.find("NAME.spztab"), std::string::npos) << cli;
  const std::string python = message_of([] { plan_table(Settings{}, "t.spz", kKeywords); });
  EXPECT_EQ(python.rfind("output 't.spz'", 0), 0u) << python;
}

TEST(RenderTable, AnEncodedSpaceIsRefusedNamingTheLinearSpaceWithItsPrimaries) {
  const std::pair<std::string, std::string> cases[] = {
      {"sRGB - Texture", kRec709},
      {"Gamma 2.2 Rec.709 - Texture", kRec709},
      {"Display P3 - Texture", "Linear P3-D65"},
      {"Adobe RGB (1998) - Texture", "Linear Adobe RGB (1998)"},
      {"ACEScct", "ACEScg"}};
  for (const auto& [encoded, linear] : cases) {
    SCOPED_TRACE(encoded);
    Settings s;
    s.colorspace = encoded;
    const std::string cli = message_of([&] { plan_table(s, "t.spztab", kFlags); });
    EXPECT_EQ(cli.rfind("--colorspace '" + encoded + "': not linear RGB", 0), 0u) << cli;
    EXPECT_NE(cli.find("use '" + linear + "', the linear space with its primaries"),
              std::string::npos)
        << cli;
    const std::string python = message_of([&] { plan_table(s, "t.spztab", kKeywords); });
    EXPECT_EQ(python.rfind("colorspace '" + encoded + "'", 0), 0u) << python;
  }
}

TEST(RenderTable, ADataSpaceIsRefusedAsNotRgb) {
  Settings s;
  s.colorspace = "Raw";
  const std::string m = message_of([&] { plan_table(s, "raw.spztab", kKeywords); });
  EXPECT_EQ(m.rfind("colorspace 'Raw': not an RGB colour space", 0), 0u) << m;
}

// A table cheap enough for a unit test: 20 nm bands.
JobPlan small_plan(ModeChoice mode, int threads) {
  Settings s;
  s.colorspace = kRec709;
  s.mode = mode;
  s.threads = threads;
  s.spectral.grid = WavelengthGrid(400, 700, 20);
  return plan_table(s, "small.spztab", kFlags);
}

// Built once for the tests below (~0.7 s on two cores), with what it said.
struct Built {
  std::vector<std::string> said;
  RenderTable table;
};
const Built& small_table() {
  static const Built built = [] {
    Built b;
    b.table = make_render_table(small_plan(ModeChoice::reflectance, 2),
                                [&](int, const std::string& m) { b.said.push_back(m); });
    return b;
  }();
  return built;
}

TEST(RenderTable, ATablesBytesDependOnlyOnItsSettings) {
  // Lights (the cheaper table): built on two cores and on one, node by node in another order.
  const RenderTable a = make_render_table(small_plan(ModeChoice::emission, 2), kQuiet);
  const RenderTable b = make_render_table(small_plan(ModeChoice::emission, 1), kQuiet);
  EXPECT_EQ(a.bytes, b.bytes);
  EXPECT_EQ(a.colorspace, kRec709);
  EXPECT_GT(a.spectra, 0u);
}

TEST(RenderTable, AReflectanceTableSaysWhatItIsAndHasBoundaryCells) {
  const RenderTable& t = small_table().table;
  EXPECT_EQ(t.colorspace, kRec709);
  EXPECT_GT(t.spectra, 0u);
  EXPECT_EQ(t.boundary_cells, t.stats.boundary_cells);
  EXPECT_GT(t.boundary_cells, 0u);  // the solid's boundary crosses the cube's cells
  const std::vector<std::string>& said = small_table().said;
  ASSERT_FALSE(said.empty());
  EXPECT_NE(said.front().find("'" + kRec709 + "' (reflectance)"), std::string::npos)
      << said.front();
}

TEST(RenderTable, ATablesSpectraReadBackIntegrateToTheirColours) {
  const RenderTable& t = small_table().table;
  // The evaluator wants 8-byte aligned bytes.
  std::vector<std::uint64_t> words((t.bytes.size() + 7) / 8);
  std::memcpy(words.data(), t.bytes.data(), t.bytes.size());
  spz::TableView view;
  char error[256] = "";
  ASSERT_TRUE(view.open(words.data(), t.bytes.size(), error, sizeof error)) << error;
  ASSERT_EQ(view.bands(), 16u);
  EXPECT_TRUE(view.reflectance());
  const WavelengthGrid grid(400, 700, 20);
  const Observer& obs = Observer::get("cie1931");
  const Illuminant d65 = Illuminant::get("D65");
  // The white balance of docs/DESIGN.md §3: rho == 1 on the grid over the D65 white.
  const Xyz w = test::reference_xyz(grid, std::vector<double>(16, 1.0), obs, &d65.spd);
  const Xyz d65w = test::d65_white();
  for (const std::array<float, 3>& c :
       {std::array<float, 3>{0.5f, 0.5f, 0.5f}, {0.6f, 0.3f, 0.2f}, {0.1f, 0.4f, 0.2f}}) {
    SCOPED_TRACE(::testing::PrintToString(c));
    spz::Spectrum s;
    ASSERT_EQ(view.fetch(c.data(), s), SPZ_EXACT);
    std::vector<double> v;
    for (std::size_t i = 0; i < grid.size(); ++i) {
      v.push_back(spz::eval(s, static_cast<float>(grid[i])));
      EXPECT_GE(v.back(), 0.0);
      EXPECT_LE(v.back(), 1.0);
    }
    const Xyz lin = test::rgb(test::kRec709ToXyz, c[0], c[1], c[2]);
    const Xyz want{lin.X * w.X / d65w.X, lin.Y * w.Y / d65w.Y, lin.Z * w.Z / d65w.Z};
    EXPECT_LT(test::rel_err(test::reference_xyz(grid, v, obs, &d65.spd), want), 1e-5);
  }
}

// A table for a renderer's conventions: its own matrix (here Rec.2020's primaries with the
// white of illuminant A under the CIE 1931 observer, computed by the test) and illuminant A.
// The spectra reproduce that matrix's XYZ, with a reflectance's XYZ relative to A's own Y over
// 360-830 nm, as a renderer integrates (oracle: the test's integration of the CSV-derived
// tables, not the library's weights).
std::string text_of(const test::Mat3& m) {
  std::string t;
  for (int k = 0; k < 9; ++k) t += fmt::format("{}{:.17g}", k ? "," : "", m[k / 3][k % 3]);
  return t;
}

spz::TableView open_view(const RenderTable& t, std::vector<std::uint64_t>& words) {
  words.assign((t.bytes.size() + 7) / 8, 0);
  std::memcpy(words.data(), t.bytes.data(), t.bytes.size());
  spz::TableView view;
  char error[256] = "";
  EXPECT_TRUE(view.open(words.data(), t.bytes.size(), error, sizeof error)) << error;
  return view;
}

TEST(RenderTable, ARenderersMatrixAndIlluminantAreReproducedAsTheRendererIntegrates) {
  const Observer& obs = Observer::get("cie1931");
  const Illuminant a = Illuminant::get("A");
  const Xyz white = test::illuminant_xyz(obs, a);
  const auto xy = test::chromaticity(white);
  const test::Mat3 m = test::rgb_to_xyz(0.708, 0.292, 0.170, 0.797, 0.131, 0.046, xy[0], xy[1]);
  // On a narrower grid a reflectance's units differ from a renderer's (rho == 1 on 400-700
  // nm is darker than A's white): the table scales its targets, the renderer sees its XYZ.
  const struct {
    ModeChoice mode;
    WavelengthGrid grid;
  } cases[] = {{ModeChoice::reflectance, WavelengthGrid(360, 830, 10)},
               {ModeChoice::emission, WavelengthGrid(360, 830, 10)},
               {ModeChoice::reflectance, WavelengthGrid(400, 700, 20)}};
  for (const auto& [mode, grid] : cases) {
    SCOPED_TRACE((mode == ModeChoice::emission ? "emission " : "reflectance ") + grid.to_string());
    Settings s;
    s.colorspace = "Linear Rec.2020";
    s.mode = mode;
    s.threads = 2;
    s.spectral.grid = grid;
    s.spectral.illuminant = "A";
    s.rgb_to_xyz = text_of(m);
    const RenderTable t = make_render_table(plan_table(s, "r.spztab", kFlags), kQuiet);
    std::vector<std::uint64_t> words;
    const spz::TableView view = open_view(t, words);
    ASSERT_TRUE(view.loaded());
    double worst = 0;
    for (const std::array<float, 3>& c : {std::array<float, 3>{1.0f, 1.0f, 1.0f},
                                          {0.5f, 0.5f, 0.5f},
                                          {0.6f, 0.3f, 0.2f},
                                          {0.1f, 0.4f, 0.2f},
                                          {0.02f, 0.01f, 0.3f}}) {
      SCOPED_TRACE(::testing::PrintToString(c));
      spz::Spectrum sp;
      // White is rho == 1 exactly, on the solid's boundary: within rounding of it, mapped.
      const int status = view.fetch(c.data(), sp);
      EXPECT_TRUE(status == SPZ_EXACT || (c[0] == 1.0f && status == SPZ_MAPPED)) << status;
      if (status != SPZ_EXACT) continue;
      Xyz got;
      for (int nm = 360; nm <= 830; ++nm) {
        const std::size_t k = static_cast<std::size_t>(nm - 360);
        const double tau = (nm == 360 || nm == 830) ? 0.5 : 1.0;
        const double v = spz::eval(sp, static_cast<float>(nm));
        const double e = mode == ModeChoice::reflectance ? a.spd[k] : 1.0;
        for (int ch = 0; ch < 3; ++ch) got[ch] += tau * v * e * obs.cmf[ch][k];
      }
      const double norm = mode == ModeChoice::reflectance ? white.Y : test::y_integral(obs);
      got = Xyz{got.X / norm, got.Y / norm, got.Z / norm};
      const Xyz want = test::rgb(m, c[0], c[1], c[2]);
      worst = std::max(worst, test::rel_err(got, want));
    }
    EXPECT_LT(worst, 1e-5);
    // Without the renderer's matrix, the project's D65-balanced conventions: ~1e-2 from it
    // under A, so the test above can tell the two apart.
    s.rgb_to_xyz.clear();
    if (mode == ModeChoice::reflectance && grid.size() == 48) {
      const RenderTable plain = make_render_table(plan_table(s, "p.spztab", kFlags), kQuiet);
      std::vector<std::uint64_t> w2;
      const spz::TableView v2 = open_view(plain, w2);
      double m2[9];
      std::memcpy(m2, v2.header().rgb_to_target, sizeof m2);
      EXPECT_GT(std::abs(m2[0] - m[0][0]), 1e-3);
    }
  }
}

// A config of two DCI-P3 spaces (P3 primaries, the DCI white 0.314, 0.351): one adapted to D65
// by Bradford as configs adapt, one whose white stays DCI; the matrices from test_support.h.
std::string dci_p3_config() {
  const test::Mat3 npm = test::rgb_to_xyz(0.680, 0.320, 0.265, 0.690, 0.150, 0.060, 0.314, 0.351);
  const test::Mat3 adapted =
      test::matmul(test::bradford(test::xyz_from_xy(0.314, 0.351), test::d65_white()), npm);
  auto matrix = [](const test::Mat3& m) {
    return fmt::format(
        "[{:.12g}, {:.12g}, {:.12g}, 0, {:.12g}, {:.12g}, {:.12g}, 0, {:.12g}, "
        "{:.12g}, {:.12g}, 0, 0, 0, 0, 1]",
        m[0][0], m[0][1], m[0][2], m[1][0], m[1][1], m[1][2], m[2][0], m[2][1], m[2][2]);
  };
  return "ocio_profile_version: 2\n"
         "roles:\n  scene_linear: P3-DCI adapted\n  default: P3-DCI adapted\n"
         "  cie_xyz_d65_interchange: XYZ\n"
         "displays:\n  sRGB:\n    - !<View> {name: Raw, colorspace: XYZ}\n"
         "colorspaces:\n"
         "  - !<ColorSpace>\n    name: XYZ\n    isdata: false\n"
         "  - !<ColorSpace>\n    name: P3-DCI adapted\n    isdata: false\n"
         "    to_scene_reference: !<MatrixTransform> {matrix: " +
         matrix(adapted) +
         "}\n"
         "  - !<ColorSpace>\n    name: P3-DCI unadapted\n    isdata: false\n"
         "    to_scene_reference: !<MatrixTransform> {matrix: " +
         matrix(npm) + "}\n";
}

// A renderer's matrix is compared with the space on the space's own terms: a standard's own
// primaries and white (AP0 and AP1 with the ACES white, as pbrt-v4 builds ACES2065-1) are
// accepted, as is the config's D65-adapted view; a space no standard names is compared after
// adapting both whites to D65. Oracle: the published primaries and Bradford in test_support.h.
TEST(RenderTable, ARenderersPrimariesAreComparedOnTheSpacesOwnTerms) {
  auto nine = [](const test::Mat3& m) {
    return fmt::format("{},{},{},{},{},{},{},{},{}", m[0][0], m[0][1], m[0][2], m[1][0], m[1][1],
                       m[1][2], m[2][0], m[2][1], m[2][2]);
  };
  const test::Mat3 ap0 =
      test::rgb_to_xyz(0.7347, 0.2653, 0.0, 1.0, 0.0001, -0.077, 0.32168, 0.33767);
  test::TempDir t("render_table");
  const std::string dci = t / "dci.ocio";
  std::ofstream(dci) << dci_p3_config();
  const test::Mat3 p3_dci =
      test::rgb_to_xyz(0.680, 0.320, 0.265, 0.690, 0.150, 0.060, 0.314, 0.351);
  const struct {
    std::string config, space, matrix;
    bool accepted;
  } cases[] = {
      {"", "ACES2065-1", "0.7347,0.2653,0.0,1.0,0.0001,-0.077,D60", true},
      {"", "ACES2065-1", nine(ap0), true},                          // the textbook AP0 matrix
      {"", "ACES2065-1", nine(test::aces2065_to_xyz_d65()), true},  // the config's own view
      {"", "ACEScg", "0.713,0.293,0.165,0.830,0.128,0.044,D60", true},
      {"", "Linear Rec.2020", "0.708,0.292,0.170,0.797,0.131,0.046,D65", true},
      {"", "Linear P3-D65", "0.680,0.320,0.265,0.690,0.150,0.060,D65", true},
      {dci, "P3-DCI adapted", nine(p3_dci), true},
      {dci, "P3-DCI unadapted", nine(p3_dci), true},
      // Other primaries: refused.
      {"", "ACES2065-1", "0.713,0.293,0.165,0.830,0.128,0.044,D60", false},
      {"", "ACEScg", "0.7347,0.2653,0.0,1.0,0.0001,-0.077,D60", false},
      {"", "Linear P3-D65", "0.708,0.292,0.170,0.797,0.131,0.046,D65", false},
      // P3 primaries with D65 white are another space than the DCI-white one a config adapts.
      {dci, "P3-DCI adapted", "0.680,0.320,0.265,0.690,0.150,0.060,D65", false},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.space + " " + c.matrix);
    Settings s;
    s.config = c.config;
    s.colorspace = c.space;
    s.rgb_to_xyz = c.matrix;
    const std::string msg = message_of([&] { plan_table(s, "r.spztab", kFlags); });
    if (c.accepted) {
      EXPECT_EQ(msg, "");
    } else {
      EXPECT_NE(msg.find("--rgb-to-xyz"), std::string::npos) << msg;
      EXPECT_NE(msg.find("not those of '" + c.space + "'"), std::string::npos) << msg;
    }
  }
}

// pbrt-v4's ACES2065-1 (AP0 primaries, the white of its D60 illuminant): its table's spectra
// give the renderer's XYZ of AP0 colours under the table's illuminant (D65), as the renderer
// integrates them. Oracle: the primaries' matrix and the reference integration of test_support.h.
TEST(RenderTable, AnAcesTableReproducesTheRenderersAp0Colours) {
  const Observer& obs = Observer::get("cie1931");
  const Illuminant d60 = Illuminant::get("D60"), d65 = Illuminant::get("D65");
  const auto xy = test::chromaticity(test::illuminant_xyz(obs, d60));
  const test::Mat3 m = test::rgb_to_xyz(0.7347, 0.2653, 0.0, 1.0, 0.0001, -0.077, xy[0], xy[1]);
  Settings s;
  s.colorspace = "ACES2065-1";
  s.mode = ModeChoice::reflectance;
  s.threads = 2;
  s.spectral.grid = WavelengthGrid(360, 830, 10);
  s.rgb_to_xyz = "0.7347,0.2653,0.0,1.0,0.0001,-0.077,D60";
  const RenderTable t = make_render_table(plan_table(s, "aces.spztab", kFlags), kQuiet);
  std::vector<std::uint64_t> words;
  const spz::TableView view = open_view(t, words);
  ASSERT_TRUE(view.loaded());
  const Xyz white = test::illuminant_xyz(obs, d65);
  double worst = 0;
  int exact = 0;
  for (const std::array<float, 3>& c : {std::array<float, 3>{0.18f, 0.18f, 0.18f},
                                        {0.3f, 0.2f, 0.1f},
                                        {0.1f, 0.25f, 0.15f},
                                        {0.05f, 0.05f, 0.2f}}) {
    spz::Spectrum sp;
    if (view.fetch(c.data(), sp) != SPZ_EXACT) continue;
    ++exact;
    Xyz got;
    for (int nm = 360; nm <= 830; ++nm) {
      const std::size_t k = static_cast<std::size_t>(nm - 360);
      const double tau = (nm == 360 || nm == 830) ? 0.5 : 1.0;
      const double v = spz::eval(sp, static_cast<float>(nm));
      for (int ch = 0; ch < 3; ++ch) got[ch] += tau * v * d65.spd[k] * obs.cmf[ch][k];
    }
    got = Xyz{got.X / white.Y, got.Y / white.Y, got.Z / white.Y};
    worst = std::max(worst, test::rel_err(got, test::rgb(m, c[0], c[1], c[2])));
  }
  EXPECT_EQ(exact, 4);
  EXPECT_LT(worst, 1e-5);
  RecordProperty("worst_relative_xyz_error", fmt::format("{:.3g}", worst));
}

TEST(RenderTable, ARenderersMatrixIsForTheSpaceTheTableIsNamedAfter) {
  Settings s;
  s.colorspace = kRec709;
  s.rgb_to_xyz = "0.708,0.292,0.170,0.797,0.131,0.046,D65";  // Rec.2020's primaries
  const std::string msg = message_of([&] { plan_table(s, "r.spztab", kFlags); });
  EXPECT_NE(msg.find("--rgb-to-xyz"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not those of 'Linear Rec.709 (sRGB)'"), std::string::npos) << msg;
  s.rgb_to_xyz = "0.64,0.33,0.3,0.6,0.15,0.06,D65";
  EXPECT_NO_THROW(plan_table(s, "r.spztab", kFlags));
}

}  // namespace
}  // namespace spectralize
