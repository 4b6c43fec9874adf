// Spectrum plots (plot/spectrum_plot.h): the raster written is an image of the documented size
// (kPlotWidth x kPlotHeight) whatever it shows, in 8-bit encoded colours (PNG) or linear half
// (OpenEXR) tagged with the space written; curves land where their values say: read back from
// the pixels, a constant spectrum is a horizontal line at the height of its value between the
// plot frame's bottom (the axis' 0) and top (its last tick), a ramp rises in proportion across
// the frame, and on a log scale a value sits at its decade's fraction; the SVG holds one
// polyline per curve with one point per sample, at the same places, and escapes its text. The
// palette is Tableau 10; the plot's spaces are the config's roles; paths that cannot hold a
// plot, missing folders and inputs are refused naming the file, with nothing written. Oracles:
// the frame found in the image itself, the values drawn, the published Tableau 10 colours, the
// roles of the config files written here, and the file system.

#include "plot/spectrum_plot.h"

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "colour/colour_space.h"
#include "file_test_support.h"
#include "spectralize/core/error.h"
#include "test_support.h"

namespace fs = std::filesystem;

namespace spectralize {
namespace {

struct TempDir : test::TempDir {
  TempDir() : test::TempDir("spectrum_plot") {}
};

const ColourSpaces& shipped() {
  static const ColourSpaces spaces = ColourSpaces::load();
  return spaces;
}

constexpr PlotColour kRed{1, 0, 0}, kGreen{0, 1, 0}, kBlue{0, 0, 1};

// A curve over 400..700 nm in 10 nm steps, of value f(nm).
template <typename F>
PlotCurve curve(const std::string& label, PlotColour colour, F f) {
  PlotCurve c;
  c.label = label;
  c.colour = colour;
  for (double nm = 400; nm <= 700; nm += 10) {
    c.wavelengths.push_back(nm);
    c.values.push_back(f(nm));
  }
  return c;
}

std::string text_of(const std::string& path) {
  std::ifstream f(path);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// An 8-bit image read back: its spec and RGB pixels.
struct Raster {
  OIIO::ImageSpec spec;
  std::vector<float> px;  // as float, 0..1 (8-bit codes / 255) or linear
  std::array<float, 3> at(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * spec.width + x) * 3;
    return {px[i], px[i + 1], px[i + 2]};
  }
};

Raster read_raster(const std::string& path) {
  Raster r;
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    ADD_FAILURE() << path << ": " << OIIO::geterror();
    return r;
  }
  r.spec = in->spec();
  r.px.resize(static_cast<std::size_t>(r.spec.width) * r.spec.height * 3);
  EXPECT_TRUE(in->read_image(0, 0, 0, 3, OIIO::TypeFloat, r.px.data())) << in->geterror();
  return r;
}

// The plot frame found in the pixels: the rows and columns (weighted centres) of the dark grey
// lines that run across most of the image.
struct Frame {
  double top = 0, bottom = 0, left = 0, right = 0;
};

Frame find_frame(const Raster& r) {
  const int w = r.spec.width, h = r.spec.height;
  auto darkness = [&](int x, int y) {
    const auto p = r.at(x, y);
    const bool grey = std::abs(p[0] - p[1]) < 0.04f && std::abs(p[1] - p[2]) < 0.04f;
    return grey && p[0] < 0.8f ? 1.0 - p[0] : 0.0;
  };
  // Bands of consecutive lines holding dark grey over more than `need` pixels; their centres.
  auto bands = [&](int n, int m, int need, auto dark_at) {
    std::vector<double> centres;
    double sum = 0, weight = 0;
    for (int i = 0; i <= n; ++i) {
      double line = 0;
      int count = 0;
      if (i < n)
        for (int j = 0; j < m; ++j) {
          const double d = dark_at(i, j);
          line += d;
          count += d > 0;
        }
      if (count > need) {
        sum += line * (i + 0.5);
        weight += line;
      } else if (weight > 0) {
        centres.push_back(sum / weight);
        sum = weight = 0;
      }
    }
    return centres;
  };
  const auto rows = bands(h, w, w * 4 / 10, [&](int y, int x) { return darkness(x, y); });
  const auto cols = bands(w, h, h * 5 / 10, [&](int x, int y) { return darkness(x, y); });
  Frame f;
  EXPECT_EQ(rows.size(), 2u) << "the frame's top and bottom";
  EXPECT_EQ(cols.size(), 2u) << "the frame's left and right";
  if (rows.size() == 2 && cols.size() == 2) f = {rows[0], rows[1], cols[0], cols[1]};
  return f;
}

// The weighted centre row of `colour`'s pixels in column x between the frame's rows.
std::optional<double> colour_row(const Raster& r, const Frame& f, int x, PlotColour colour) {
  double sum = 0, weight = 0;
  for (int y = static_cast<int>(f.top) - 3; y <= static_cast<int>(f.bottom) + 3; ++y) {
    const auto p = r.at(x, y);
    // How much more of the colour's own channel than of the others.
    const int k = colour.r > 0 ? 0 : colour.g > 0 ? 1 : 2;
    const double d = p[k] - std::max(p[(k + 1) % 3], p[(k + 2) % 3]);
    if (d > 0.2) {
      sum += d * (y + 0.5);
      weight += d;
    }
  }
  if (weight == 0) return std::nullopt;
  return sum / weight;
}

// The median over the frame's inner columns of colour_row.
double median_row(const Raster& r, const Frame& f, PlotColour colour) {
  std::vector<double> rows;
  for (int x = static_cast<int>(f.left) + 4; x < static_cast<int>(f.right) - 4; ++x)
    if (auto y = colour_row(r, f, x, colour)) rows.push_back(*y);
  if (rows.empty()) return NAN;
  std::nth_element(rows.begin(), rows.begin() + rows.size() / 2, rows.end());
  return rows[rows.size() / 2];
}

TEST(SpectrumPlot, ConstantSpectraAreHorizontalLinesAtTheirValuesHeight) {
  TempDir t;
  SpectrumPlot plot;
  plot.title = {"constant spectra", "a second line"};
  plot.y_top_at_least = 1;  // the value axis from 0 to 1
  plot.curves = {curve("0.25", kRed, [](double) { return 0.25; }),
                 curve("0.75", kBlue, [](double) { return 0.75; }),
                 curve("ramp", kGreen, [](double nm) { return (nm - 400) / 300; })};
  const std::string path = t / "plot.png";
  EXPECT_TRUE(write_raster(plot, path, plot_spaces(shipped())).empty());
  const Raster r = read_raster(path);
  EXPECT_EQ(r.spec.width, kPlotWidth);
  EXPECT_EQ(r.spec.height, kPlotHeight);
  EXPECT_EQ(r.spec.nchannels, 3);
  EXPECT_EQ(r.spec.format, OIIO::TypeUInt8);
  EXPECT_EQ(r.at(2, 2), (std::array<float, 3>{1, 1, 1}));  // a white background
  const Frame f = find_frame(r);
  ASSERT_GT(f.bottom - f.top, 100);
  ASSERT_GT(f.right - f.left, 100);
  auto row_of = [&](double v) { return f.bottom - v * (f.bottom - f.top); };
  const double kTol = 1.0;  // pixels: the lines' antialiased edges, the brush's half pixel
  EXPECT_NEAR(median_row(r, f, kRed), row_of(0.25), kTol);
  EXPECT_NEAR(median_row(r, f, kBlue), row_of(0.75), kTol);
  // The ramp: from 0 at the left of the frame (400 nm) to 1 at its right (700 nm), in
  // proportion, away from where it crosses the other lines.
  int checked = 0;
  for (int x = static_cast<int>(f.left) + 20; x < static_cast<int>(f.right) - 20; x += 7) {
    const double v = (x + 0.5 - f.left) / (f.right - f.left);
    if (std::abs(v - 0.25) < 0.05 || std::abs(v - 0.75) < 0.05) continue;
    const auto y = colour_row(r, f, x, kGreen);
    ASSERT_TRUE(y) << "column " << x;
    EXPECT_NEAR(*y, row_of(v), 2 * kTol) << "column " << x;
    ++checked;
  }
  EXPECT_GT(checked, 50);
}

TEST(SpectrumPlot, OnALogScaleAValueSitsAtItsFractionOfTheDecades) {
  TempDir t;
  SpectrumPlot plot;
  plot.log_scale = true;
  // 10 to 1000: the axis spans the decades 10^1..10^3.
  PlotCurve span;
  span.colour = kGreen;
  span.wavelengths = {400, 700};
  span.values = {10, 1000};
  plot.curves = {span, curve("100", kRed, [](double) { return 100.0; }),
                 curve("10^2.5", kBlue, [](double) { return std::pow(10.0, 2.5); })};
  const std::string path = t / "log.png";
  write_raster(plot, path, plot_spaces(shipped()));
  const Raster r = read_raster(path);
  const Frame f = find_frame(r);
  auto row_of = [&](double decade) { return f.bottom - (decade - 1) / 2 * (f.bottom - f.top); };
  EXPECT_NEAR(median_row(r, f, kRed), row_of(2), 1.0);
  EXPECT_NEAR(median_row(r, f, kBlue), row_of(2.5), 1.0);
}

TEST(SpectrumPlot, EveryPlotIsOfTheDocumentedSizeWhateverItShows) {
  TempDir t;
  SpectrumPlot empty;
  SpectrumPlot full;
  full.title = {std::string(500, 'T'), "two", "three", "four: not drawn"};
  full.swatch_labels = {"input", "spectrum"};
  full.notes = {"a note", "another"};
  for (std::size_t i = 0; i < kMaxPlotCurves; ++i) {
    PlotCurve c = curve("curve " + std::to_string(i), plot_palette(i),
                        [&](double nm) { return 1e4 * i + nm; });
    c.swatches = {plot_palette(i), PlotColour{1, 1, 1}};
    full.curves.push_back(c);
  }
  // The raster (the other tests draw other contents at this size); the SVG's declared size.
  write_raster(full, t / "full.png", plot_spaces(shipped()));
  const Raster r = read_raster(t / "full.png");
  EXPECT_EQ(r.spec.width, kPlotWidth);
  EXPECT_EQ(r.spec.height, kPlotHeight);
  for (const auto& [name, plot] : {std::pair{"empty.svg", empty}, {"full.svg", full}}) {
    write_svg(plot, t / name, plot_spaces(shipped()));
    EXPECT_NE(text_of(t / name).find("width=\"1000\" height=\"600\" viewBox=\"0 0 1000 600\""),
              std::string::npos)
        << name;
  }
}

TEST(SpectrumPlot, AnOpenExrPlotIsLinearHalfTaggedWithTheLinearSpace) {
  TempDir t;
  SpectrumPlot plot;
  plot.y_top_at_least = 1;
  plot.curves = {curve("0.5", kRed, [](double) { return 0.5; })};
  const PlotSpaces cs = plot_spaces(shipped());
  const std::string path = t / "plot.exr";
  write_raster(plot, path, cs);
  const Raster r = read_raster(path);
  EXPECT_EQ(r.spec.width, kPlotWidth);
  EXPECT_EQ(r.spec.height, kPlotHeight);
  EXPECT_EQ(r.spec.format, OIIO::TypeHalf);
  // The ASWF colour interop ID of linear Rec.709 ('Linear Rec.709 (sRGB)', scene_linear).
  EXPECT_EQ(r.spec.get_string_attribute("colorInteropID"), "lin_rec709_scene");
  // White is white, and the encoded red (1, 0, 0) the linear red of the same primaries.
  for (float v : r.at(2, 2)) EXPECT_NEAR(v, 1.0f, 2e-3f);
  const int x = kPlotWidth / 3;
  float best = 0;
  std::array<float, 3> reddest{};
  for (int y = 0; y < kPlotHeight; ++y) {
    const auto p = r.at(x, y);
    if (p[0] - p[1] > best) best = p[0] - p[1], reddest = p;
  }
  EXPECT_NEAR(reddest[0], 1.0f, 2e-3f);
  EXPECT_NEAR(reddest[1], 0.0f, 2e-3f);
  EXPECT_NEAR(reddest[2], 0.0f, 2e-3f);
}

TEST(SpectrumPlot, TheSvgHoldsAPolylinePerCurveAPointPerSampleAtTheSamePlaces) {
  TempDir t;
  SpectrumPlot plot;
  plot.title = {"a <title> & \"more\""};
  plot.y_top_at_least = 1;
  plot.curves = {curve("flat <0.25>", kRed, [](double) { return 0.25; }),
                 curve("ramp & co", kBlue, [](double nm) { return (nm - 400) / 300; })};
  const std::string path = t / "plot.svg";
  EXPECT_TRUE(write_svg(plot, path, plot_spaces(shipped())).empty());
  const std::string svg = text_of(path);
  EXPECT_NE(svg.find("width=\"1000\" height=\"600\""), std::string::npos);
  EXPECT_NE(svg.find("<title>a &lt;title&gt; &amp; &quot;more&quot;</title>"), std::string::npos);
  EXPECT_NE(svg.find("flat &lt;0.25&gt;"), std::string::npos);
  EXPECT_NE(svg.find("ramp &amp; co"), std::string::npos);
  // The frame: the long horizontal and vertical lines of the frame colour.
  std::vector<double> ys, xs;
  const std::regex line(
      R"re(<line x1="([-\d.]+)" y1="([-\d.]+)" x2="([-\d.]+)" y2="([-\d.]+)" stroke="#333333")re");
  for (std::sregex_iterator it(svg.begin(), svg.end(), line), end; it != end; ++it) {
    const double x1 = std::stod((*it)[1]), y1 = std::stod((*it)[2]), x2 = std::stod((*it)[3]),
                 y2 = std::stod((*it)[4]);
    if (y1 == y2 && std::abs(x2 - x1) > 300) ys.push_back(y1);
    if (x1 == x2 && std::abs(y2 - y1) > 300) xs.push_back(x1);
  }
  std::sort(ys.begin(), ys.end());
  std::sort(xs.begin(), xs.end());
  ASSERT_EQ(ys.size(), 2u);
  ASSERT_EQ(xs.size(), 2u);
  const double top = ys[0], bottom = ys[1], left = xs[0], right = xs[1];
  // The polylines, in curve order, one point per sample.
  const std::regex poly(R"re(<polyline [^>]*points="([^"]*)")re");
  std::vector<std::vector<std::pair<double, double>>> curves;
  for (std::sregex_iterator it(svg.begin(), svg.end(), poly), end; it != end; ++it) {
    std::vector<std::pair<double, double>> pts;
    std::istringstream in((*it)[1].str());
    for (std::string pair; in >> pair;) {
      const auto comma = pair.find(',');
      pts.emplace_back(std::stod(pair.substr(0, comma)), std::stod(pair.substr(comma + 1)));
    }
    curves.push_back(pts);
  }
  ASSERT_EQ(curves.size(), 2u);
  const double kTol = 0.01;  // two decimals in the file
  for (std::size_t c = 0; c < 2; ++c) {
    SCOPED_TRACE("curve " + std::to_string(c));
    ASSERT_EQ(curves[c].size(), 31u);
    for (std::size_t k = 0; k < 31; ++k) {
      const double fraction = k / 30.0;  // of 400..700 nm, and of the ramp's value
      const double value = c == 0 ? 0.25 : fraction;
      EXPECT_NEAR(curves[c][k].first, left + fraction * (right - left), kTol) << k;
      EXPECT_NEAR(curves[c][k].second, bottom - value * (bottom - top), kTol) << k;
    }
  }
}

TEST(SpectrumPlot, AnSvgOfColoursThatAreNotSrgbSaysTheyWillLookWrong) {
  TempDir t;
  PlotSpaces cs = plot_spaces(shipped());
  cs.encoded = "ACEScg";
  SpectrumPlot plot;
  plot.curves = {curve("x", kRed, [](double) { return 0.5; })};
  const auto warnings = write_svg(plot, t / "acescg.svg", cs);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("SVG colours are sRGB"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("ACEScg"), std::string::npos) << warnings[0];
  EXPECT_NE(warnings[0].find("acescg.svg"), std::string::npos) << warnings[0];
}

TEST(SpectrumPlot, ThePaletteIsTableauTenAndCyclesAfterTen) {
  // The published Tableau 10 colours, in order.
  const int tableau[10][3] = {{0x1f, 0x77, 0xb4}, {0xff, 0x7f, 0x0e}, {0x2c, 0xa0, 0x2c},
                              {0xd6, 0x27, 0x28}, {0x94, 0x67, 0xbd}, {0x8c, 0x56, 0x4b},
                              {0xe3, 0x77, 0xc2}, {0x7f, 0x7f, 0x7f}, {0xbc, 0xbd, 0x22},
                              {0x17, 0xbe, 0xcf}};
  for (std::size_t i = 0; i < 23; ++i) {
    const PlotColour c = plot_palette(i);
    const int* want = tableau[i % 10];
    EXPECT_NEAR(c.r * 255, want[0], 1e-3) << i;
    EXPECT_NEAR(c.g * 255, want[1], 1e-3) << i;
    EXPECT_NEAR(c.b * 255, want[2], 1e-3) << i;
  }
}

TEST(SpectrumPlot, ThePlotsSpacesAreTheConfigsRoles) {
  TempDir t;
  // The shipped config: color_picking 'sRGB - Texture', scene_linear 'Linear Rec.709 (sRGB)'.
  const PlotSpaces cs = plot_spaces(shipped());
  EXPECT_EQ(cs.encoded, "sRGB - Texture");
  EXPECT_EQ(cs.linear, "Linear Rec.709 (sRGB)");
  EXPECT_EQ(cs.spaces, &shipped());
  // Other roles: color_picking first, else matte_paint.
  const std::string text =
      text_of(std::string(SPECTRALIZE_SOURCE_DIR) + "/ocio_configs/spectralize.ocio");
  auto with = [&](const std::string& name, std::vector<std::pair<std::string, std::string>> edits) {
    std::string s = text;
    for (const auto& [from, to] : edits) {
      const auto at = s.find(from);
      EXPECT_NE(at, std::string::npos) << from;
      if (at != std::string::npos) s.replace(at, from.size(), to);
    }
    std::ofstream(t / name) << s;
    return ColourSpaces::load(t / name);
  };
  const ColourSpaces picking = with(
      "picking.ocio", {{"color_picking: sRGB - Texture", "color_picking: Display P3 - Texture"},
                       {"scene_linear: Linear Rec.709 (sRGB)", "scene_linear: ACEScg"}});
  EXPECT_EQ(plot_spaces(picking).encoded, "Display P3 - Texture");
  EXPECT_EQ(plot_spaces(picking).linear, "ACEScg");
  const ColourSpaces matte = with(
      "matte.ocio", {{"  color_picking: sRGB - Texture\n", ""},
                     {"matte_paint: sRGB - Texture", "matte_paint: Adobe RGB (1998) - Texture"}});
  EXPECT_EQ(plot_spaces(matte).encoded, "Adobe RGB (1998) - Texture");
}

TEST(SpectrumPlot, PathsThatCannotHoldAPlotAreRefusedNamingTheFileAndNothingIsWritten) {
  TempDir t;
  for (const char* path : {"a.svg", "a.SVG", "a.png", "a.exr", "a.tif", "a.jpg", "a.hdr"})
    EXPECT_TRUE(is_plot_path(path)) << path;
  for (const char* path : {"a.txt", "a.csv", "noextension", "a.", ""})
    EXPECT_FALSE(is_plot_path(path)) << path;
  for (const char* path : {"a.svg", "a.png", "a.exr", "a.hdr", "a.tif"})
    EXPECT_NO_THROW(check_plot_file(t / path)) << path;
  SpectrumPlot plot;
  plot.curves = {curve("x", kRed, [](double) { return 0.5; })};
  const PlotSpaces cs = plot_spaces(shipped());
  test::expect_error_mentioning([&] { check_plot_file(t / "a.txt"); }, {t / "a.txt"}, ".txt");
  test::expect_error_mentioning([&] { write_plot(plot, t / "a.txt", cs); }, {t / "a.txt"},
                                "a plot as .txt");
  test::expect_error_mentioning([&] { write_plot(plot, t / "missing/a.png", cs); },
                                {t / "missing/a.png"}, "a missing folder");
  test::expect_error_mentioning([&] { write_plot(plot, t / "missing/a.svg", cs); },
                                {t / "missing/a.svg"}, "a missing folder (SVG)");
  // Never over an input (the raster's file: ImageFileOutput's tests).
  const std::string input = t / "input.svg";
  std::ofstream(input) << "an input";
  const std::vector<std::string> inputs = {input};
  test::expect_error_mentioning([&] { write_plot(plot, input, cs, inputs); }, {input},
                                "over an input");
  EXPECT_EQ(text_of(input), "an input");
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(t.dir)) names.push_back(e.path().filename());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"input.svg"}));
}

}  // namespace
}  // namespace spectralize
