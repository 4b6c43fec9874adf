// End-to-end tests of the plots: `spectralize --color ... -o PLOT.png|.svg` and
// `spectralize --plot-pixel X,Y IN.exr -o PLOT.png|.svg`, read back with OIIO or as text.

#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.h"
#include "exr_support.h"

using e2e::run;
using e2e::Scratch;

namespace {

const std::string kImages = SPECTRALIZE_SOURCE_DIR "/testimages/";
const std::string kSamples = kImages + "spectral_samples/";
constexpr int kWidth = 1000, kHeight = 600;  // the documented size of every plot

// An 8-bit RGB picture read with OIIO.
struct Picture {
  int width = 0, height = 0, channels = 0;
  std::vector<unsigned char> px;
  std::array<int, 3> at(int x, int y) const {
    const std::size_t i = (static_cast<std::size_t>(y) * width + x) * channels;
    return {px[i], px[i + 1], px[i + 2]};
  }
};

Picture read_picture(const std::string& path) {
  Picture p;
  auto in = OIIO::ImageInput::open(path);
  if (!in) return p;
  p.width = in->spec().width;
  p.height = in->spec().height;
  p.channels = in->spec().nchannels;
  p.px.resize(static_cast<std::size_t>(p.width) * p.height * p.channels);
  in->read_image(0, 0, 0, p.channels, OIIO::TypeUInt8, p.px.data());
  return p;
}

// Pixels of the box [x0, x1) x [y0, y1) within `tol` (per channel, 0..255) of `rgb`.
int count_near(const Picture& p, std::array<int, 3> rgb, int tol, int x0, int y0, int x1, int y1) {
  int n = 0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      auto c = p.at(x, y);
      if (std::abs(c[0] - rgb[0]) <= tol && std::abs(c[1] - rgb[1]) <= tol &&
          std::abs(c[2] - rgb[2]) <= tol)
        ++n;
    }
  return n;
}

int distinct_colours(const Picture& p) {
  std::set<int> seen;
  for (int y = 0; y < p.height; ++y)
    for (int x = 0; x < p.width; ++x) {
      auto c = p.at(x, y);
      seen.insert((c[0] << 16) | (c[1] << 8) | c[2]);
    }
  return static_cast<int>(seen.size());
}

// The sRGB encoding (IEC 61966-2-1) of a linear component, as 0..255; written out here.
int srgb8(double linear) {
  const double v = linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
  return static_cast<int>(std::lround(std::clamp(v, 0.0, 1.0) * 255));
}

// The plot area (inside the axes) and the legend panel, generous boxes around the layout.
constexpr int kAreaX0 = 85, kAreaX1 = 710, kAreaY0 = 105, kAreaY1 = 525;
constexpr int kLegendX0 = 735;

// The curve colours of the first three curves (Tableau 10: blue, orange, green).
constexpr std::array<std::array<int, 3>, 3> kCurve = {
    {{31, 119, 180}, {255, 127, 14}, {44, 160, 44}}};

// --- A small well-formedness check of the SVG: every tag closed in order, attributes quoted ---
bool well_formed(const std::string& svg, std::string* why) {
  static const std::regex tag(R"(<(/?)([A-Za-z][\w:-]*)((?:\s+[\w:-]+="[^"<]*")*)\s*(/?)>)");
  std::vector<std::string> stack;
  std::size_t pos = svg.find("?>");  // after the XML declaration
  if (svg.rfind("<?xml", 0) != 0 || pos == std::string::npos)
    return *why = "no XML declaration", false;
  pos += 2;
  while ((pos = svg.find('<', pos)) != std::string::npos) {
    std::smatch m;
    std::string rest = svg.substr(pos, svg.find('>', pos) - pos + 1);
    if (!std::regex_match(rest, m, tag)) return *why = "malformed tag: " + rest, false;
    if (m[1] == "/") {
      if (stack.empty() || stack.back() != m[2])
        return *why = "unbalanced </" + m[2].str() + ">", false;
      stack.pop_back();
    } else if (m[4] != "/") {
      stack.push_back(m[2]);
    }
    pos += rest.size();
  }
  if (!stack.empty()) return *why = "unclosed <" + stack.back() + ">", false;
  return true;
}

struct Polyline {
  std::string stroke;
  std::vector<std::pair<double, double>> points;
};

std::vector<Polyline> polylines(const std::string& svg) {
  std::vector<Polyline> out;
  static const std::regex re(R"re(<polyline[^>]*stroke="([^"]+)"[^>]*points="([^"]*)")re");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), re); it != std::sregex_iterator();
       ++it) {
    Polyline p;
    p.stroke = (*it)[1];
    std::stringstream ss((*it)[2].str());
    for (std::string pair; ss >> pair;) {
      const auto comma = pair.find(',');
      p.points.emplace_back(std::stod(pair.substr(0, comma)), std::stod(pair.substr(comma + 1)));
    }
    out.push_back(p);
  }
  return out;
}

std::string svg_attribute(const std::string& svg, const std::string& name) {
  std::smatch m;
  const std::regex re("<svg[^>]*\\s" + name + "=\"([^\"]*)\"");
  return std::regex_search(svg, m, re) ? m[1].str() : "";
}

std::string svg_title(const std::string& svg) {
  const auto b = svg.find("<title>"), e = svg.find("</title>");
  return b == std::string::npos || e == std::string::npos ? "" : svg.substr(b + 7, e - b - 7);
}

// The curve draws `values`: x grows with the wavelength and a larger value is drawn higher
// (smaller y) -- the plot's ordering is the data's, whatever the axis scale.
void expect_curve_is(const Polyline& line, const std::vector<double>& values) {
  ASSERT_EQ(line.points.size(), values.size());
  for (std::size_t i = 1; i < values.size(); ++i) {
    EXPECT_GT(line.points[i].first, line.points[i - 1].first) << "x must grow, sample " << i;
  }
  const double span = *std::max_element(values.begin(), values.end());
  for (std::size_t i = 0; i < values.size(); ++i)
    for (std::size_t j = 0; j < values.size(); ++j)
      if (values[i] > values[j] + 0.01 * span) {
        EXPECT_LT(line.points[i].second, line.points[j].second)
            << "sample " << i << " (" << values[i] << ") must be above sample " << j << " ("
            << values[j] << ")";
      }
}

// The CSV spectrum `spectralize --color ARGS` prints.
std::vector<double> printed_spectrum(const std::string& args) {
  auto r = run(args);
  std::vector<double> v;
  std::stringstream ss(r.out);
  std::string line;
  std::getline(ss, line);
  while (std::getline(ss, line)) v.push_back(std::stod(line.substr(line.find(',') + 1)));
  return v;
}

// --- Colours ---

// Truth: the PNG has the documented size, real content (antialiased text and curves make many
// distinct colours), the curve's colour inside the plot area, and two swatches in the legend
// that both show the input colour (sRGB-encoded here independently): the round trip is exact.
TEST(PlotColor, PngIsTheDocumentedSizeWithCurveAndMatchingSwatches) {
  Scratch dir("plot");
  auto r = run("--color 0.21,0.72,0.15 --mode reflectance -o " + dir / "p.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Picture p = read_picture(dir / "p.png");
  ASSERT_EQ(p.width, kWidth);
  ASSERT_EQ(p.height, kHeight);
  EXPECT_GE(p.width, 800);
  EXPECT_GE(p.height, 500);
  EXPECT_GE(p.channels, 3);
  EXPECT_GT(distinct_colours(p), 100);
  EXPECT_GT(count_near(p, kCurve[0], 12, kAreaX0, kAreaY0, kAreaX1, kAreaY1), 500)
      << "no curve pixels in the plot area";
  const std::array<int, 3> input = {srgb8(0.21), srgb8(0.72), srgb8(0.15)};
  EXPECT_GT(count_near(p, input, 2, kLegendX0, 0, kWidth, kHeight), 2 * 1500)
      << "two swatches of the input colour expected (input and round trip)";
  EXPECT_EQ(dir.files(), std::vector<std::string>{"p.png"}) << "a temporary file was left";
}

// Truth: under another reference illuminant (A) the round-trip swatch still shows the input
// colour: the spectrum's XYZ is white balanced to A, and the plot undoes that before display.
TEST(PlotColor, RoundTripSwatchUndoesTheWhiteBalance) {
  Scratch dir("plot");
  auto r = run("--color 0.6,0.3,0.2 --mode reflectance --illuminant A -o " + dir / "a.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Picture p = read_picture(dir / "a.png");
  ASSERT_EQ(p.width, kWidth);
  const std::array<int, 3> input = {srgb8(0.6), srgb8(0.3), srgb8(0.2)};
  EXPECT_GT(count_near(p, input, 2, kLegendX0, 0, kWidth, kHeight), 2 * 1500);
}

// Truth: a light far above display white is drawn (exit 0) with swatches scaled to fit, not
// clipped to white: the swatches keep the light's hue (red > green > blue, not all 255).
TEST(PlotColor, BrightLightSwatchesAreScaledNotClipped) {
  Scratch dir("plot");
  auto r = run("--color 6000,5000,1000 -o " + dir / "light.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Picture p = read_picture(dir / "light.png");
  ASSERT_EQ(p.width, kWidth);
  // Linear (6000, 5000, 1000) scaled by 1/6000: (1, 0.833, 0.167).
  const std::array<int, 3> scaled = {srgb8(1.0), srgb8(5000.0 / 6000), srgb8(1000.0 / 6000)};
  EXPECT_GT(count_near(p, scaled, 2, kLegendX0, 0, kWidth, kHeight), 2 * 1500);
}

// Truth: the SVG is well-formed text of the documented size with one <polyline> of exactly
// one point per grid sample, drawing the same spectrum --color prints; the title names the
// colour, the colour space, the mode and the settings (model included).
TEST(PlotColor, SvgHasOnePolylinePointPerSampleDrawingThePrintedSpectrum) {
  Scratch dir("plot");
  const std::string args = "--color 0.21,0.72,0.15 --mode reflectance --wavelengths 400:700:10";
  auto r = run(args + " -o " + dir / "p.svg");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string svg = e2e::slurp(dir / "p.svg");
  std::string why;
  EXPECT_TRUE(well_formed(svg, &why)) << why;
  EXPECT_EQ(svg_attribute(svg, "width"), std::to_string(kWidth));
  EXPECT_EQ(svg_attribute(svg, "height"), std::to_string(kHeight));
  auto lines = polylines(svg);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].points.size(), 31u);  // 400..700 nm at 10 nm
  expect_curve_is(lines[0], printed_spectrum(args));
  const std::string title = svg_title(svg);
  for (const char* part : {"0.21,0.72,0.15", "Linear Rec.709 (sRGB)", "reflectance", "D65",
                           "model exemplar", "400:700:10", "cie1931"})
    EXPECT_NE(title.find(part), std::string::npos) << part << " missing from title: " << title;
  // Only the settings that matter: the edge filter is the paper model's.
  EXPECT_EQ(title.find("filter"), std::string::npos) << title;
}

// Truth: the title names the model the spectrum was chosen with (when the tool has --model).
TEST(PlotColor, TitleNamesTheModel) {
  if (run("--help").out.find("--model") == std::string::npos) {
    GTEST_SKIP() << "no --model flag";
  }
  Scratch dir("plot");
  auto r = run("--color 0.21,0.72,0.15 --mode reflectance --model smooth -o " + dir / "s.svg");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string title = svg_title(e2e::slurp(dir / "s.svg"));
  EXPECT_NE(title.find("model smooth"), std::string::npos) << title;
}

// Truth: several --color values give one curve each, in distinct colours, with a legend
// entry per colour; the PNG shows each curve colour in the plot area.
TEST(PlotColor, SeveralColoursGiveDistinctCurvesAndALegend) {
  Scratch dir("plot");
  const std::string colours = "--color 0.8,0.2,0.1 --color 0.1,0.6,0.2 --color 0.2,0.3,0.9";
  auto r = run(colours + " --mode reflectance -o " + dir / "m.svg");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string svg = e2e::slurp(dir / "m.svg");
  auto lines = polylines(svg);
  ASSERT_EQ(lines.size(), 3u);
  std::set<std::string> strokes;
  for (const auto& l : lines) {
    EXPECT_EQ(l.points.size(), 81u);
    strokes.insert(l.stroke);
  }
  EXPECT_EQ(strokes.size(), 3u) << "curve colours must differ";
  for (const char* label : {">0.8,0.2,0.1<", ">0.1,0.6,0.2<", ">0.2,0.3,0.9<"}) {
    EXPECT_NE(svg.find(label), std::string::npos) << "legend label " << label;
  }

  r = run(colours + " --mode reflectance -o " + dir / "m.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Picture p = read_picture(dir / "m.png");
  ASSERT_EQ(p.width, kWidth);
  for (const auto& c : kCurve) {
    EXPECT_GT(count_near(p, c, 12, kAreaX0, kAreaY0, kAreaX1, kAreaY1), 200)
        << "curve colour " << c[0] << "," << c[1] << "," << c[2] << " missing";
  }
}

// Truth: the extension decides: JPEG, TIFF and OpenEXR plots are images of the documented size;
// a non-image -o (.csv, .json) receives the printed spectrum.
TEST(PlotColor, ExtensionDecidesBetweenPlotAndPrintedSpectrum) {
  Scratch dir("plot");
  for (const char* name : {"p.jpg", "p.tif", "p.exr"}) {
    auto r = run("--color 0.5,0.2,0.1 -o " + dir / name);
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    const Picture p = read_picture(dir / name);
    EXPECT_EQ(p.width, kWidth) << name;
    EXPECT_EQ(p.height, kHeight) << name;
    EXPECT_GT(distinct_colours(p), 50) << name;
  }
  // The same picture, in linear light in the EXR and display sRGB in the PNG: decoding the
  // PNG's 8-bit values with the sRGB curve (IEC 61966-2-1) gives the EXR's values to 8-bit and
  // HALF rounding (0.01).
  ASSERT_EQ(run("--color 0.5,0.2,0.1 -o " + dir / "p.png").exit_code, 0);
  const Picture png = read_picture(dir / "p.png");
  const e2e::Exr exr = e2e::read_exr(dir / "p.exr");
  ASSERT_EQ(exr.width, png.width);
  double worst = 0;
  for (int y = 0; y < png.height; y += 3)
    for (int x = 0; x < png.width; x += 3)
      for (int c = 0; c < 3; ++c) {
        const double v = png.at(x, y)[c] / 255.0;
        const double lin = v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
        worst = std::max(worst, std::abs(lin - exr.at(x, y, c)));
      }
  EXPECT_LE(worst, 0.01);
  // A non-image -o writes the printed spectrum to that file (CSV, or JSON for .json).
  auto r = run("--color 0.5,0.2,0.1 -o " + dir / "s.csv");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_TRUE(r.out.empty()) << r.out.substr(0, 80);
  EXPECT_EQ(e2e::slurp(dir / "s.csv").rfind("wavelength_nm,value\n", 0), 0u);
  ASSERT_EQ(run("--color 0.5,0.2,0.1 -o " + dir / "s.json").exit_code, 0);
  EXPECT_EQ(e2e::slurp(dir / "s.json").rfind("{", 0), 0u);
}

// --- Pixels of spectral EXRs ---

// Truth: --plot-pixel on a file spectralize wrote (reflective T channels) draws that pixel's
// spectrum as stored in the file (read here with OIIO), one point per band; the title names the
// file, the pixel and the layout; the PNG is the documented size with the curve in the area.
TEST(PlotPixel, SpectralizeOutputPixelIsDrawnAsStored) {
  Scratch dir("plot");
  const std::string exr = dir / "checker.exr";
  ASSERT_EQ(run(kImages + "colorchecker_srgb8.png -q -o " + exr).exit_code, 0);
  auto r = run("--plot-pixel 30,20 " + exr + " -o " + dir / "px.svg");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const e2e::Exr e = e2e::read_exr(exr);
  const auto bands = e2e::spectral_channels(e, "T.");
  ASSERT_EQ(bands.size(), 81u);
  std::vector<double> values;
  for (const auto& [c, nm] : bands) values.push_back(e.at(30, 20, c));
  const std::string svg = e2e::slurp(dir / "px.svg");
  std::string why;
  EXPECT_TRUE(well_formed(svg, &why)) << why;
  auto lines = polylines(svg);
  ASSERT_EQ(lines.size(), 1u);
  expect_curve_is(lines[0], values);
  const std::string title = svg_title(svg);
  for (const char* part : {"checker.exr", "(30, 20)", "reflective", "81 bands", "380-780"}) {
    EXPECT_NE(title.find(part), std::string::npos) << part << " missing from title: " << title;
  }

  r = run("--plot-pixel 30,20 --plot-pixel 60,50 " + exr + " -o " + dir / "px.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Picture p = read_picture(dir / "px.png");
  ASSERT_EQ(p.width, kWidth);
  ASSERT_EQ(p.height, kHeight);
  EXPECT_GT(distinct_colours(p), 100);
  for (int i = 0; i < 2; ++i) {
    EXPECT_GT(count_near(p, kCurve[i], 12, kAreaX0, kAreaY0, kAreaX1, kAreaY1), 300) << i;
  }
  EXPECT_EQ(dir.files(), (std::vector<std::string>{"checker.exr", "px.png", "px.svg"}));
}

// Truth: other writers' files work too: colour-science's ColorChecker (16 T bands, HALF), the
// emissive D65 (97 S0 bands from 300 nm) and a polarised ART render (S0 plotted, said so).
TEST(PlotPixel, OtherWritersFilesArePlotted) {
  Scratch dir("plot");
  struct Case {
    const char* file;
    const char* pixel;
    std::size_t bands;
    const char* in_title;
  };
  for (const Case& c : {Case{"colour_Ohta1997.exr", "3,2", 16, "reflective"},
                        Case{"colour_D65.exr", "0,0", 97, "emissive"},
                        Case{"colour_Polarised.exr", "5,5", 8, "polarised"}}) {
    auto r = run(std::string("--plot-pixel ") + c.pixel + " " + kSamples + c.file + " -o " +
                 dir / "s.svg");
    ASSERT_EQ(r.exit_code, 0) << c.file << ": " << r.err;
    const std::string svg = e2e::slurp(dir / "s.svg");
    auto lines = polylines(svg);
    ASSERT_EQ(lines.size(), 1u) << c.file;
    EXPECT_EQ(lines[0].points.size(), c.bands) << c.file;
    const std::string title = svg_title(svg);
    EXPECT_NE(title.find(c.file), std::string::npos) << title;
    EXPECT_NE(title.find(c.in_title), std::string::npos) << title;
  }
  auto r = run("--plot-pixel 3,2 " + kSamples + "colour_Ohta1997.exr -o " + dir / "o.png");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Picture p = read_picture(dir / "o.png");
  EXPECT_EQ(p.width, kWidth);
  EXPECT_EQ(p.height, kHeight);
  EXPECT_GT(count_near(p, kCurve[0], 12, kAreaX0, kAreaY0, kAreaX1, kAreaY1), 300);
}

// --- Mistakes ---

// Truth: wrong command lines exit 2 with a message naming the flag and the value; failed jobs
// (non-spectral file, missing file or folder, output = input) exit 1 naming the file; nothing
// is left behind.
TEST(PlotErrors, BadInputsGiveTheStatedExitCodeAndMessage) {
  Scratch dir("plot");
  const std::string exr = dir / "checker.exr";
  ASSERT_EQ(run(kImages + "colorchecker_srgb8.png -q -o " + exr).exit_code, 0);
  struct Case {
    std::string args;
    int code;
    std::vector<std::string> message;
  };
  const std::vector<Case> cases = {
      {"--plot-pixel 110,0 " + exr + " -o " + dir / "a.png", 2, {"--plot-pixel '110,0'", "110x74"}},
      {"--plot-pixel 0,74 " + exr + " -o " + dir / "a.png", 2, {"outside"}},
      {"--plot-pixel '1;2' " + exr + " -o " + dir / "a.png", 2, {"--plot-pixel '1", "X,Y"}},
      {"--plot-pixel -1,2 " + exr + " -o " + dir / "a.png", 2, {"X,Y"}},
      {"--plot-pixel 1,2,3 " + exr + " -o " + dir / "a.png", 2, {"X,Y"}},
      {"--plot-pixel 1,2 " + exr, 2, {"-o"}},
      {"--plot-pixel 1,2 " + exr + " -o " + dir / "a.txt", 2, {"a.txt"}},
      {"--plot-pixel 1,2 -o " + dir / "a.png", 2, {"IN.exr"}},
      {"--plot-pixel 1,2 " + kImages + "hdri_sunset_256x128.exr -o " + dir / "a.png",
       1,
       {"hdri_sunset_256x128.exr", "no spectral channels"}},
      {"--plot-pixel 1,2 " + dir / "missing.exr -o " + dir / "a.png", 1, {"missing.exr"}},
      {"--plot-pixel 1,2 " + exr + " -o " + exr, 1, {"checker.exr", "input"}},
      {"--plot-pixel 1,2 " + exr + " -o " + dir / "nofolder/a.png", 1, {"nofolder"}},
      {"--color 0.2,0.3,0.4 -o " + dir / "nofolder/a.svg", 1, {"nofolder"}},
      {"--color 0.2,0.3,0.4 --format json -o " + dir / "a.png", 2, {"--format"}},
      {"--color 0.2,0.3 -o " + dir / "a.png", 2, {"--color"}},
      {"--color 0.2,0.3,0.4 --colorspace nope -o " + dir / "a.png", 2, {"nope"}},
  };
  for (const Case& c : cases) {
    auto r = run(c.args);
    EXPECT_EQ(r.exit_code, c.code) << c.args << "\n" << r.err;
    for (const auto& m : c.message) {
      EXPECT_NE(r.err.find(m), std::string::npos) << c.args << ": '" << m << "' not in " << r.err;
    }
  }
  std::string eleven;
  for (int i = 0; i < 11; ++i) eleven += " --color 0.1,0.2,0.3";
  auto r = run(eleven + " -o " + dir / "a.png");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("at most 10"), std::string::npos) << r.err;
  EXPECT_EQ(dir.files(), std::vector<std::string>{"checker.exr"}) << "leftovers";
}

// Truth: --help documents the plot flag.
TEST(PlotErrors, HelpListsPlotPixel) {
  auto r = run("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("--plot-pixel"), std::string::npos);
}

}  // namespace
